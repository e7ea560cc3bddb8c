"""The paper's table tb:summary from our runs: every scenario for one model, then the table.

Per model: the disk step-length sweep, the omnidirectional scale sweep, the push schedule, the
terrain tile sizes x seeds, and the START -> GOAL run, in independent units that `jobs`
processes run side by side (each graph on its own ROS domains). The table puts the LIPM baseline
beside the three-mass MPC with the improvement ratio, next to the paper's numbers.
"""
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
import json
import multiprocessing
from pathlib import Path
import time
from typing import Callable, Dict, List

from biped_tools.scenarios import disk, omni, push, start_goal, terrain
from biped_tools.scenarios.trial import TrialFactory

PAPER = {  # tb:summary: baseline, proposed, improvement
    'disk': (0.12, 0.22, 0.83), 'omni': (1.03, 1.16, 0.13), 'push': (100.0, 150.0, 0.50),
    'terrain': (0.0, 1.0, 1.0)}


MAX_DOMAIN_ID = 232  # Fast DDS's UDP ports stay below 65535 up to this domain
UNIT_DOMAINS = 10    # domains of one unit: its trials cycle through them (TrialFactory)


@dataclass(frozen=True)
class Unit:
    """One independent part of the summary: its trials run one after the other in one graph
    at a time, on its own block of ROS domains, so units can run in parallel.

    :param model: the controller's model
    :param scenario: disk, omni, push, terrain or goal
    :param domain_base: first domain of its block
    :param tile_area: the terrain unit's tile area (cm^2)
    :param repeats: runs at each limit (disk, omni) or of the push schedule, judged by the median
    """

    model: str
    scenario: str
    domain_base: int
    tile_area: float = 0.0
    repeats: int = 1


def units_of(models, domain_base: int, repeats: int = 1) -> List[Unit]:
    """Every unit of the summary, the same list for any number of jobs (so each trial gets the
    same domain, and the same result, whatever runs beside it).

    :raises ValueError: when the domains would pass MAX_DOMAIN_ID
    """
    kinds = [('disk', 0.0), ('omni', 0.0), ('push', 0.0), ('goal', 0.0)] + [
        ('terrain', area) for area in terrain.TILE_AREAS_CM2]
    units = [Unit(model, kind, domain_base + UNIT_DOMAINS * index, area, repeats)
             for index, (model, (kind, area)) in enumerate(
                 (model, kind) for model in models for kind in kinds)]
    last = units[-1].domain_base + UNIT_DOMAINS - 1
    if last > MAX_DOMAIN_ID:
        raise ValueError(f'the summary needs domains {domain_base}..{last}: start at '
                         f'{MAX_DOMAIN_ID + 1 - (last + 1 - domain_base)} or lower')
    return units


def run_unit(unit: Unit, out: Path, seeds: List[int], record: bool = True,
             log: Callable = print) -> Dict:
    """The trials of one unit; :return: its part of the model's results."""
    trial = TrialFactory(out, unit.model, unit.domain_base, record, log)
    model = unit.model
    if unit.scenario == 'disk':
        log(f'[summary {model}] disk: step length sweep {disk.STEP_LENGTHS[0]}..'
            f'{disk.STEP_LENGTHS[-1]} m')
        best, tried = disk.largest_step_length(trial, unit.repeats)
        return {'largest_step_length_m': best, 'tried': tried_keys(tried)}
    if unit.scenario == 'omni':
        log(f'[summary {model}] omni: command scale sweep')
        best, tried = omni.largest_scale(trial, repeats=unit.repeats)
        return {'largest_scale': best, 'tried': tried_keys(tried)}
    if unit.scenario == 'push':
        log(f'[summary {model}] push: 80, 100, 120, 130, ... N every 8 s, {unit.repeats} '
            f'run(s)')
        return push.repeated(trial, push.forces(), unit.repeats)
    if unit.scenario == 'terrain':
        log(f'[summary {model}] terrain: tiles of {unit.tile_area:g} cm^2 x seeds {seeds}')
        runs = [terrain.run(trial('terrain', f'{unit.tile_area}cm2_seed{seed}'),
                            unit.tile_area, seed) for seed in seeds]
        return {'runs': [{k: r[k] for k in ('tile_area_cm2', 'seed', 'success',
                                            'terrain_fraction_crossed')} for r in runs]}
    log(f'[summary {model}] START -> GOAL')
    goal = start_goal.run(trial('goal', 'paper_map'))
    return {'success': goal['success'], 'final_error_m': goal['final_error_m']}


def _run_unit_in_worker(unit: Unit, out: Path, seeds: List[int], record: bool) -> Dict:
    label = f'[{unit.model} {unit.scenario}{f" {unit.tile_area:g}" if unit.tile_area else ""}]'
    return run_unit(unit, out, seeds, record, lambda line: print(f'{label} {line}', flush=True))


def run_models(out: Path, models, domain_base: int, seeds: List[int], record: bool = True,
               log: Callable = print, jobs: int = 1, repeats: int = 1) -> Dict[str, Dict]:
    """Every scenario of every model, `jobs` units at a time (each in its own process when
    jobs > 1), each limit confirmed by `repeats` runs; writes out/<model>_results.json and
    returns {model: results}."""
    units = units_of(models, domain_base, repeats)
    wall0 = time.monotonic()
    if jobs <= 1:
        parts = [run_unit(unit, out, seeds, record, log) for unit in units]
    else:
        context = multiprocessing.get_context('spawn')  # no rclpy state forked into a worker
        with ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
            futures = [pool.submit(_run_unit_in_worker, unit, out, seeds, record)
                       for unit in units]
            parts = [future.result() for future in futures]
    wall = round(time.monotonic() - wall0, 1)
    per_model = {}
    for model in models:
        results = {'model': model}
        runs = []
        for unit, part in zip(units, parts):
            if unit.model != model:
                continue
            if unit.scenario == 'terrain':
                runs.extend(part['runs'])
            else:
                results[unit.scenario] = part
        results['terrain'] = {'success_fraction': sum(r['success'] for r in runs) / len(runs),
                              'runs': runs}
        results['wall_s'] = wall
        (out / f'{model}_results.json').write_text(json.dumps(results, indent=2))
        per_model[model] = results
    return per_model


def tried_keys(tried: Dict[float, List[bool]]) -> Dict[str, List[bool]]:
    """{setting: [completed, ...]} with the settings as JSON keys."""
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
