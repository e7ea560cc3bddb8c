"""When a push on the model plant counts as withstood, and the search for the largest one.

An evaluator of the paper's MATLAB loop (biped_sim.model_walk): the model plant cannot fall,
so a run is judged by what a real robot would need.
"""
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from biped_mpc.linear_model import OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG
from biped_planner.parameter_fields import parameter, validate_fields

from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.walk_log import WalkLog


@dataclass(frozen=True)
class WithstandCriteria:
    """Thresholds of the definition of a withstood push (see evaluate_push).

    :raises ConfigError: naming the field, for a value out of its range
    """

    recovery_time: float = parameter(0.5, 'time after the end of the push during which the '
                                     'fictitious ZMP may stay outside the support polygon (s)',
                                     low=0.0, high=10.0)
    zmp_tolerance: float = parameter(0.005, 'distance outside the real support polygon '
                                     'tolerated after the recovery time (m)', low=0.0, high=0.1)
    leg_error: float = parameter(0.15, 'largest distance of a leg mass from its reference at '
                                 'any time (m); beyond it the legs could not realise the '
                                 'motion', low=0.0, high=10.0, low_open=True)
    torso_offset: float = parameter(0.3, 'largest distance of the torso mass from the hip '
                                    'reference at any time (m)', low=0.0, high=10.0,
                                    low_open=True)
    final_com_error: float = parameter(0.05, 'largest distance of the centre of mass from the '
                                       'final hip reference at the end of the run (m)', low=0.0,
                                       high=10.0, low_open=True)
    final_com_speed: float = parameter(0.1, 'largest centre-of-mass speed per plane at the end '
                                       'of the run (m/s)', low=0.0, high=10.0, low_open=True)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


@dataclass(frozen=True)
class PushOutcome:
    """Verdict on one run.

    :param force: (3,) push force of the run (N)
    :param withstood: True when every condition holds
    :param failures: the conditions that failed, in words
    :param metrics: the measured quantities behind the verdict (SI units)
    """

    force: tuple
    withstood: bool
    failures: tuple
    metrics: dict = field(default_factory=dict)


def late_excursion(log: WalkLog, t_from: float) -> float:
    """Largest distance of the fictitious ZMP outside the real support polygon from t_from on.

    :param log: a run
    :param t_from: start of the interval (s)
    :return: the distance (m), 0 if always inside
    """
    after = log.t >= t_from - 1e-9
    return float(log.polygon_excursion()[after].max()) if after.any() else 0.0


def evaluate_push(log: WalkLog, push: ExternalPush,
                  criteria: WithstandCriteria = WithstandCriteria()) -> PushOutcome:
    """Decide whether the robot of the model plant withstood the push.

    The model plant cannot fall, so "withstood" is defined by what a real robot would need.
    A push is withstood when all of the following hold:

    1. Balance regained: from recovery_time (0.5 s) after the end of the push to the end of
       the run, the fictitious ZMP stays inside the real support polygon (the feet, not
       scaled by 0.9) up to zmp_tolerance (5 mm: the margin between the scaled and the real
       foot length, which covers the jitter that measurement noise causes through the state
       estimate). During the push and the recovery time it may leave the polygon (the
       paper's Fig. of the disturbance: "ZMP goes out of the support polygon for a moment").
    2. Kinematically possible: at every cycle each leg mass is within leg_error (0.15 m) of
       its reference and the torso mass within torso_offset (0.3 m) of the hip reference;
       farther, the legs could not produce the motion.
    3. The walk ends standing: at the end of the run (the reference's end plus the settle
       time) the centre of mass is within final_com_error (5 cm) of the final hip reference
       and moves slower than final_com_speed (0.1 m/s) in each plane.

    :param log: the run with the push
    :param push: the push of the run (start_time None: at the start of the run)
    :param criteria: the thresholds
    :return: the verdict, with the failed conditions and the metrics
    """
    start = float(log.t[0]) if push.start_time is None else push.start_time
    t_from = start + push.duration + criteria.recovery_time
    excursion = log.polygon_excursion()
    late = late_excursion(log, t_from)
    allowed = criteria.zmp_tolerance
    leg_error = np.abs(log.true_outputs[:, :, [OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG]]
                       - log.reference[:, :, [OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG]])
    max_leg_error = float(leg_error.max())
    max_torso_offset = float(np.abs(log.torso - log.hip).max())
    final_com_error = float(np.hypot(*(log.com[-1] - log.hip[-1])))
    final_com_speed = float(np.abs(log.com_velocity[-1]).max())
    outside = excursion.max(axis=1) > criteria.zmp_tolerance
    last_outside = float(log.t[np.flatnonzero(outside)[-1]]) if outside.any() else None
    metrics = {
        'max_zmp_excursion': float(excursion.max()),
        'late_zmp_excursion': late,
        'last_time_outside': last_outside,
        'max_leg_error': max_leg_error,
        'max_torso_offset': max_torso_offset,
        'final_com_error': final_com_error,
        'final_com_speed': final_com_speed,
        'fallback_cycles': int(np.count_nonzero(log.status.max(axis=1))),
    }
    failures = []
    if late > allowed:
        failures.append(f'ZMP {late * 1000:.1f} mm outside the support polygon more than '
                        f'{criteria.recovery_time} s after the push')
    if max_leg_error > criteria.leg_error:
        failures.append(f'a leg mass {max_leg_error:.3f} m from its reference')
    if max_torso_offset > criteria.torso_offset:
        failures.append(f'the torso {max_torso_offset:.3f} m from the hip reference')
    if final_com_error > criteria.final_com_error or final_com_speed > criteria.final_com_speed:
        failures.append(f'not standing at the end (COM error {final_com_error:.3f} m, speed '
                        f'{final_com_speed:.3f} m/s)')
    return PushOutcome(force=tuple(float(f) for f in push.force), withstood=not failures,
                       failures=tuple(failures), metrics=metrics)


def evaluate_push_paper(log: WalkLog, push: ExternalPush,
                        criteria: WithstandCriteria = WithstandCriteria()) -> PushOutcome:
    """The paper's criterion: the fictitious ZMP returns inside the support polygon and the walk
    completes.

    The paper (section "Robustness w.r.t. External Disturbance") lets the fictitious ZMP leave
    the support polygon "for a moment" after the push; "the controller regains it back and
    keeps the stability of the robot". Stated as checks on the run:

    1. The ZMP returns: the last cycle with the fictitious ZMP outside the real support polygon
       (beyond zmp_tolerance, the noise jitter of evaluate_push) is before the reference's end,
       so that it stays inside through the final settle and the settle time.
    2. The walk completes: at the end of the run the centre of mass is within final_com_error
       of the final hip reference and slower than final_com_speed in each plane.

    Nothing bounds the legs' or the torso's excursions or the time the ZMP spends outside:
    evaluate_push is the stricter criterion reported beside this one.

    :param log: the run with the push
    :param push: the push of the run
    :param criteria: the thresholds (zmp_tolerance, final_com_error, final_com_speed are used)
    :return: the verdict, with the failed conditions and the metrics of evaluate_push
    """
    strict = evaluate_push(log, push, criteria)
    metrics = strict.metrics
    failures = []
    last_outside = metrics['last_time_outside']
    if last_outside is not None and last_outside >= log.reference_end:
        failures.append(f'ZMP outside the support polygon until t = {last_outside:.2f} s, '
                        f'after the walk ends at {log.reference_end:.2f} s')
    if metrics['final_com_error'] > criteria.final_com_error or \
            metrics['final_com_speed'] > criteria.final_com_speed:
        failures.append(f'not standing at the end (COM error {metrics["final_com_error"]:.3f} '
                        f'm, speed {metrics["final_com_speed"]:.3f} m/s)')
    return PushOutcome(force=strict.force, withstood=not failures, failures=tuple(failures),
                       metrics=metrics)


def largest_withstood_force(outcome_of: Callable[[float], PushOutcome], sign: float,
                            initial: float = 100.0, limit: float = 3000.0,
                            resolution: float = 5.0) -> tuple:
    """Bisection for the largest push magnitude that is withstood in one direction.

    Doubles the magnitude from initial until a push fails (or limit is reached), then
    bisects between the last withstood and the first failed magnitude down to resolution.
    It assumes that a stronger push is never easier, which the runs check only at the points
    visited.

    :param outcome_of: runs the walk with a push of the given signed force (N) and judges it
    :param sign: +1 for pushes along +axis, -1 along -axis
    :param initial: first magnitude tried (N), > 0
    :param limit: largest magnitude tried (N)
    :param resolution: bisection stops when the bracket is narrower (N), > 0
    :return: (largest withstood magnitude (N), 0 if even no push fails; list of outcomes)
    :raises ConfigError: for a sign other than +-1 or non-positive magnitudes
    """
    if sign not in (1.0, -1.0, 1, -1):
        raise ConfigError(f'sign must be +1 or -1, got {sign!r}')
    if not (0.0 < initial <= limit) or resolution <= 0.0:
        raise ConfigError(f'need 0 < initial <= limit and resolution > 0, got {initial}, '
                          f'{limit}, {resolution}')
    outcomes = []

    def judge(magnitude: float) -> bool:
        outcome = outcome_of(sign * magnitude)
        outcomes.append(outcome)
        return outcome.withstood

    if not judge(0.0):
        return 0.0, outcomes
    good, bad = 0.0, None
    magnitude = initial
    while bad is None:
        if judge(magnitude):
            good = magnitude
            if magnitude >= limit:
                return good, outcomes
            magnitude = min(2.0 * magnitude, limit)
        else:
            bad = magnitude
    while bad - good > resolution:
        middle = 0.5 * (good + bad)
        if judge(middle):
            good = middle
        else:
            bad = middle
    return good, outcomes
