"""The START -> GOAL run with obstacles: A* on the paper's map, footsteps, walking (demo.py)."""
from paper_scenarios.trial import Trial, write_result


def run(trial: Trial) -> dict:
    import demo
    trial.directory.mkdir(parents=True, exist_ok=True)
    summary = demo.run(trial.directory, trial.domain_id, trial.model, timeout=600.0,
                       log=lambda line: None)
    result = {'scenario': trial.scenario, 'model': trial.model, 'setting': trial.setting,
              **summary}
    result['success'] = bool(summary['finished'] and not summary['fallen'] and
                             summary['final_error_m'] <= 0.15)
    result['plots'] = [str(trial.directory / 'walk_top_view.png'),
                       str(trial.directory / 'walk_zmp.png')]
    return write_result(trial, result)
