"""The paper's table tb:summary from our runs: every scenario for one model, then the table.

Per model (one graph at a time): the disk step-length sweep, the omnidirectional scale sweep,
the push schedule, the terrain tile sizes x seeds, and the START -> GOAL run. The table puts the
LIPM baseline beside the three-mass MPC with the improvement ratio, next to the paper's numbers.
"""
import json
from pathlib import Path
import time
from typing import Callable, Dict, List

from biped_tools.scenarios import disk, omni, push, start_goal, terrain
from biped_tools.scenarios.trial import TrialFactory

PAPER = {  # tb:summary: baseline, proposed, improvement
    'disk': (0.12, 0.22, 0.83), 'omni': (1.03, 1.16, 0.13), 'push': (100.0, 150.0, 0.50),
    'terrain': (0.0, 1.0, 1.0)}


def run_model(out: Path, model: str, domain_base: int, seeds: List[int], record: bool = True,
              log: Callable = print) -> Dict:
    """Every scenario for one model; writes out/<model>_results.json and returns it."""
    trial = TrialFactory(out, model, domain_base, record, log)
    wall0 = time.monotonic()
    results = {'model': model}
    log(f'[summary {model}] disk: step length sweep {disk.STEP_LENGTHS[0]}..'
        f'{disk.STEP_LENGTHS[-1]} m')
    best, tried = disk.largest_step_length(trial)
    results['disk'] = {'largest_step_length_m': best, 'tried': tried_keys(tried)}
    log(f'[summary {model}] omni: command scale sweep')
    best, tried = omni.largest_scale(trial)
    results['omni'] = {'largest_scale': best, 'tried': tried_keys(tried)}
    log(f'[summary {model}] push: 80, 100, 120, 130, ... N every 8 s')
    pushed = push.run(trial('push', 'schedule'), push.forces())
    results['push'] = {'largest_withstood_n': pushed['largest_withstood_n'],
                       'first_fall_force_n': pushed['first_fall_force_n']}
    log(f'[summary {model}] terrain: tiles {terrain.TILE_AREAS_CM2} cm^2 x seeds {seeds}')
    runs = [terrain.run(trial('terrain', f'{area}cm2_seed{seed}'), area, seed)
            for area in terrain.TILE_AREAS_CM2 for seed in seeds]
    results['terrain'] = {
        'success_fraction': sum(r['success'] for r in runs) / len(runs),
        'runs': [{k: r[k] for k in ('tile_area_cm2', 'seed', 'success',
                                    'terrain_fraction_crossed')} for r in runs]}
    log(f'[summary {model}] START -> GOAL')
    goal = start_goal.run(trial('goal', 'paper_map'))
    results['goal'] = {'success': goal['success'], 'final_error_m': goal['final_error_m']}
    results['wall_s'] = round(time.monotonic() - wall0, 1)
    (out / f'{model}_results.json').write_text(json.dumps(results, indent=2))
    return results


def tried_keys(tried: Dict[float, bool]) -> Dict[str, bool]:
    """{setting: completed} with the settings as JSON keys."""
    return {f'{value:g}': ok for value, ok in sorted(tried.items())}


def improvement(baseline, proposed):
    if baseline is None or proposed is None:
        return None
    if baseline == 0:
        return None if proposed == 0 else float('inf')
    return (proposed - baseline) / baseline


def table(lipm: Dict, three_mass: Dict) -> Dict:
    """Rows of tb:summary: ours (baseline, proposed, improvement) and the paper's."""
    values = {
        'disk': ('Walking around a disk (largest step length, m)',
                 lipm['disk']['largest_step_length_m'],
                 three_mass['disk']['largest_step_length_m']),
        'omni': ('Omnidirectional walking (largest command scale)',
                 lipm['omni']['largest_scale'], three_mass['omni']['largest_scale']),
        'push': ('Push recovery in place (largest push withstood, N)',
                 lipm['push']['largest_withstood_n'], three_mass['push']['largest_withstood_n']),
        'terrain': ('Uneven terrain (share of tile sizes x seeds crossed)',
                    lipm['terrain']['success_fraction'],
                    three_mass['terrain']['success_fraction']),
    }
    rows = []
    for key, (name, baseline, proposed) in values.items():
        paper = PAPER[key]
        # terrain: the paper's 100 % is the gain in success (fail -> success), a difference
        gain = (proposed - baseline) if key == 'terrain' else improvement(baseline, proposed)
        rows.append({'scenario': name, 'baseline': baseline, 'proposed': proposed,
                     'improvement': gain,
                     'paper_baseline': paper[0], 'paper_proposed': paper[1],
                     'paper_improvement': paper[2]})
    rows.append({'scenario': 'START -> GOAL with obstacles (final error, m)',
                 'baseline': lipm['goal']['final_error_m'] if lipm['goal']['success'] else None,
                 'proposed': three_mass['goal']['final_error_m']
                 if three_mass['goal']['success'] else None,
                 'improvement': None, 'paper_baseline': None, 'paper_proposed': None,
                 'paper_improvement': None})
    return {'rows': rows}


def markdown(summary: Dict) -> str:
    def cell(value, percent=False):
        if value is None:
            return 'failed' if not percent else '-'
        if percent:
            return 'inf' if value == float('inf') else f'{100 * value:+.0f} %'
        return f'{value:g}'
    lines = ['| Scenario | LIPM baseline | Three-mass MPC | Improvement | Paper: baseline / '
             'proposed / improvement |', '|---|---|---|---|---|']
    for row in summary['rows']:
        paper = '-' if row['paper_baseline'] is None else (
            f'{row["paper_baseline"]:g} / {row["paper_proposed"]:g} / '
            f'{100 * row["paper_improvement"]:+.0f} %')
        lines.append(f'| {row["scenario"]} | {cell(row["baseline"])} | {cell(row["proposed"])} '
                     f'| {cell(row["improvement"], True)} | {paper} |')
    return '\n'.join(lines) + '\n'
