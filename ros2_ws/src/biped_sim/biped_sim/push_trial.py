"""Library push trials of the PyBullet humanoid walking in place, with or without step adjustment.

One definition for the test and scripts/experiments/push_library_sweep.py: the paper's push
scenario (walking in place, 0.3 s single and 0.1 s double support, a 100 ms push on the
pelvis) from any horizontal direction at one of four phases of a step:

- early_single: a quarter into a single support on the right foot (the paper's phase);
- late_single: the last 0.1 s of a single support on the right foot (ends at touchdown);
- double: the double support (0.1 s, the push covers it);
- early_single_left: a quarter into a single support on the left foot (the other stance).

With step adjustment the reference source is an AdjustedWalk: after every cycle the DCM of the
measured state (biped_mpc.balance.measured_dcm: odometry pelvis + leg kinematics, the
three-mass centre of mass) is handed to it, and the next window is sampled from the plan the
OnlineStepAdjuster may have replanned.
"""
from dataclasses import dataclass, replace
import math
from typing import Optional

import numpy as np

from biped_mpc.balance.measured_dcm import MeasuredDcm
from biped_planner.step_adjuster import OnlineStepAdjuster, OnlineStepAdjusterParams
from biped_planner.step_adjustment import StepAdjustmentParams
from biped_planner.footsteps import straight_footsteps
from biped_planner.sides import SUPPORT_LEFT, SUPPORT_RIGHT
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference

from biped_sim.closed_loop import ClosedLoopRunner
from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.reference_sources import AdjustedWalk

TIMING = StepTiming(single_support=0.3, double_support=0.1)   # the paper's push scenario
REFERENCE = ReferenceParams(com_height=0.497, swing_height=0.04, foot_length=0.2,
                            foot_width=0.1)
STEP_WIDTH = 0.14
T_START = 0.5
PUSH_DURATION = 0.1
FIRST_PUSH_AFTER = 2.0   # s: the push falls in the first step of its phase after this
RECOVERY = 1.5           # s walked after the push ends; the falls seen came within 1.2 s
# The controller's swing lag for recovery steps (swing_smoothing_time_constant, s): the default
# 0.07 s lands each step softly and a little late, which costs the pushes that need a step
# (docs/controller_notes.md, "Recovery steps land on time").
RECOVERY_SWING_LAG = 0.0
# The graph's push-directions schedule (biped_tools.scenarios.push_directions, the README's
# command): the first push 3 s into the walk, then one every SCHEDULE_INTERVAL s, each watched
# until 1 s before the next would start.
SCHEDULE_FIRST_PUSH = 3.0
SCHEDULE_INTERVAL = 3.0
SCHEDULE_LOOKAHEAD = 1.0  # s: a push is placed from the plan this long before it
# s: the largest shift of a scheduled push inside its phase (run_push_schedule)
MAX_PHASE_OFFSET = 0.05
# s: the longest time with neither foot on the ground a push may cause and count as walked
# through on the ground (PushScheduleResult.largest_grounded). Unpushed walks touch at every
# 20 ms cycle; pushes walked through left both feet unloaded for up to 80 ms (landing rebounds).
# One cycle is allowed: a touchdown can flicker across the contact threshold.
MAX_FLIGHT = 0.02
# phase name: (support of the phase, push start after the phase start (s))
PHASES = {
    'early_single': (SUPPORT_RIGHT, 0.25 * TIMING.single_support),
    'late_single': (SUPPORT_RIGHT, TIMING.single_support - PUSH_DURATION),
    'double': (None, 0.0),
    'early_single_left': (SUPPORT_LEFT, 0.25 * TIMING.single_support),
}
# The humanoid's legs (hips 0.47 m high): steps of 0.3 m ahead, 0.2 m back, ankles 0.1 to
# 0.3 m apart sideways (no crossing); the shortest step 0.15 s after lift-off.
HUMANOID_STEP_LIMITS = StepAdjustmentParams(
    com_height=REFERENCE.com_height, reach_forward=0.3, reach_backward=0.2, width_min=0.1,
    width_max=0.3, step_time_min=0.15, step_time_max=0.45)
# Replans answer a push once (and correct once); the swing foot follows its planned curve, so
# the landing may still change 0.08 s before touchdown. The graph's defaults
# (biped_planner/config/reference_generator.yaml; a test keeps the two equal), so a library
# table is read as the graph's.
HUMANOID_ADJUSTER = OnlineStepAdjusterParams(
    dcm_deadband=0.01, ankle_authority=0.3, location_threshold=0.02, timing_threshold=0.03,
    freeze_time=0.08, max_replans_per_step=2, replan_interval=0.04,
    replan_hip_from_estimate=False, replan_dcm_from_footsteps=True)


@dataclass(frozen=True)
class PushTrialResult:
    """What a push trial measured.

    :param fallen: the run ended in a fall
    :param fall_time: when (s), NaN without a fall
    :param push: the push applied
    :param revisions: plan revisions the step adjuster made (0 without it)
    :param adjustments: (t, StepAdjustment) of every replan
    :param reference: the plan at the end of the run
    :param log: the runner's RunLog
    :param adjuster_times: (n,) wall time of each cycle's adjustment (s), empty without it
    """

    fallen: bool
    fall_time: float
    push: ExternalPush
    revisions: int
    adjustments: tuple
    reference: object
    log: object
    adjuster_times: np.ndarray


@dataclass(frozen=True)
class PushScheduleResult:
    """What a push schedule measured.

    :param forces: the forces pushed, in order (N), the first fall's last
    :param push_times: start of each push (s)
    :param fall_time: when the robot fell (s), NaN without a fall
    :param largest_withstood: the largest force walked through before a fall (N), 0 for none
    :param revisions: plan revisions the step adjuster made (0 without it)
    :param footsteps: the plan's footsteps at the end, as the adjuster left them
    :param flights: per push, the longest time with neither foot in contact from its start
        until the next push (or the fall) (s)
    """

    forces: tuple
    push_times: tuple
    fall_time: float
    largest_withstood: float
    revisions: int
    footsteps: tuple = ()
    flights: tuple = ()

    def largest_grounded(self, max_flight: float = MAX_FLIGHT) -> float:
        """The largest force walked through, with a foot in contact, before the first fall or
        the first push that left both feet unloaded for longer than max_flight (s), 0 for none:
        the stricter reading of the schedule, where a bounce is no recovery."""
        walked = self.forces[:-1] if math.isfinite(self.fall_time) else self.forces
        return largest_grounded(walked, self.flights, max_flight)


def largest_grounded(walked, flights, max_flight: float = MAX_FLIGHT) -> float:
    """The largest of the forces walked through (in push order) before the first whose push
    left both feet unloaded for longer than max_flight (s), 0 for none.

    :param walked: the forces walked through, in order (N)
    :param flights: per push, the longest time with neither foot loaded after it (s)
    """
    best = 0.0
    for force, flight in zip(walked, flights):
        if flight > max_flight + 1e-9:
            break
        best = max(best, force)
    return best


def walk_reference(step_length: float = 0.0, n_steps: int = 16) -> WalkingReference:
    """The straight walk of the push trials: n_steps steps of step_length (m) from T_START."""
    return WalkingReference(straight_footsteps(n_steps, step_length, STEP_WIDTH), TIMING,
                            REFERENCE, t_start=T_START)


def walk_in_place_reference(n_steps: int = 16) -> WalkingReference:
    """The in-place walk of the push trials (n_steps steps from T_START)."""
    return walk_reference(0.0, n_steps)


def push_start(reference, phase: str, after: float = FIRST_PUSH_AFTER) -> float:
    """Start time of the push at a phase: the first phase of that kind starting after `after`.

    :param reference: the WalkingReference walked
    :param phase: a key of PHASES
    :param after: earliest phase start (s)
    :return: the push start (s)
    :raises ConfigError: for an unknown phase or none after `after`
    """
    if phase not in PHASES:
        raise ConfigError(f'phase must be one of {tuple(PHASES)}, got {phase!r}')
    support, delay = PHASES[phase]
    for candidate in reference.phases:
        if candidate.t_begin < after - 1e-9:
            continue
        if support is None and candidate.kind == 'double_support' or \
                support is not None and candidate.kind == 'single_support' and \
                candidate.support == support:
            return float(candidate.t_begin) + delay
    raise ConfigError(f'no {phase} phase after {after} s in the plan')


def adjusted_source(reference, robot, adjuster, step_limits, measured_zmp=False, clock=None,
                    times=None):
    """(source, on_cycle): the reference as the step adjuster replans it from the measured DCM."""
    qp = replace(step_limits, com_height=REFERENCE.com_height)
    source = AdjustedWalk(reference, OnlineStepAdjuster(adjuster, qp))
    measured = MeasuredDcm(robot)

    def observe(t, window, output, readings):
        com, dcm = measured.update(readings.time, readings.joints.position[:12],
                                   readings.base.position, readings.base.orientation)
        zmp = readings.zmp if measured_zmp else None
        if clock is None:
            source.adjust(readings.time, com, dcm, zmp)
            return
        begin = clock()
        source.adjust(readings.time, com, dcm, zmp)
        times.append(clock() - begin)

    return source, observe


def run_push_schedule(backend, controller, robot, forces, direction: float, phase: str,
                      adjuster: Optional[OnlineStepAdjusterParams] = None,
                      step_limits: StepAdjustmentParams = HUMANOID_STEP_LIMITS,
                      step_length: float = 0.0,
                      interval: float = SCHEDULE_INTERVAL,
                      phase_offset: float = 0.0) -> PushScheduleResult:
    """One walk pushed again and again, as the graph's push-directions trial does.

    The forces are pushed in order, one every `interval` s from SCHEDULE_FIRST_PUSH s into the
    walk, each at the first phase of its kind at or after its due time in the plan as it is
    SCHEDULE_LOOKAHEAD s before (the adjuster may have moved touchdowns), until a fall. A push is
    walked through when the robot still stands when the next one starts (the last: 1 s before
    another would be due); a fall before a push starts is the previous push's. Unlike
    run_push_trial, the robot meets each push as the earlier ones left it.

    :param forces: push magnitudes in order (N), each finite and >= 0
    :param interval: s between the due times of two pushes, > SCHEDULE_LOOKAHEAD
    :param phase_offset: s added to each push's start in its phase, |offset| <= 0.05: a cell
        is a region of the gait, and nearby starts show how much its figure owes to the exact
        instant
    :return: the schedule's outcome
    :raises ConfigError: for a bad force, an unknown phase, a too short interval or offset
    """
    forces = tuple(float(f) for f in forces)
    if not forces or not all(math.isfinite(f) and f >= 0.0 for f in forces):
        raise ConfigError(f'forces must be finite and >= 0 (N), got {forces!r}')
    if not math.isfinite(interval) or interval <= SCHEDULE_LOOKAHEAD + PUSH_DURATION:
        raise ConfigError(f'interval must exceed {SCHEDULE_LOOKAHEAD + PUSH_DURATION} s, got '
                          f'{interval!r}')
    if not (math.isfinite(phase_offset) and abs(phase_offset) <= MAX_PHASE_OFFSET):
        raise ConfigError(f'phase_offset must be within +-{MAX_PHASE_OFFSET} s, got '
                          f'{phase_offset!r}')
    walk_time = SCHEDULE_FIRST_PUSH + interval * (len(forces) + 1)
    step_time = TIMING.single_support + TIMING.double_support
    reference = walk_reference(step_length, int(math.ceil(walk_time / step_time)) + 2)
    source, on_cycle = reference, None
    if adjuster is not None and adjuster.enabled:
        source, on_cycle = adjusted_source(reference, robot, adjuster, step_limits)
    runner = ClosedLoopRunner(backend, controller, source)
    runner.reset()
    pushed, times, flights = [], [], []

    def result(fall_time: float) -> PushScheduleResult:
        # after a fall the last push pushed is the one that felled the robot
        walked = pushed[:-1] if math.isfinite(fall_time) else pushed
        return PushScheduleResult(tuple(pushed), tuple(times), fall_time, max(walked, default=0.0),
                                  _revisions(source), _footsteps(source), tuple(flights))

    due = T_START + SCHEDULE_FIRST_PUSH
    for force in forces:
        runner.run(max(due - SCHEDULE_LOOKAHEAD - backend.time, 0.0), on_cycle=on_cycle)
        plan = source.reference if isinstance(source, AdjustedWalk) else reference
        in_phase = push_start(plan, phase, after=max(due, backend.time + 0.1))
        start = in_phase + phase_offset
        runner.push(ExternalPush(force=(force * math.cos(direction),
                                        force * math.sin(direction), 0.0),
                                 duration=PUSH_DURATION, start_time=start))
        due = in_phase + interval  # the offset moves each push, not the schedule
        log = runner.run(due + PUSH_DURATION - SCHEDULE_LOOKAHEAD - backend.time,
                         on_cycle=on_cycle)
        if log.fallen and log.fall_time < start:
            # down before this push began: the one before felled it (as the graph counts)
            return result(float(log.fall_time))
        pushed.append(force)
        times.append(start)
        flights.append(log.longest_flight(start))
        if log.fallen:
            return result(float(log.fall_time))
    return result(math.nan)


def _revisions(source) -> int:
    return source.revision if isinstance(source, AdjustedWalk) else 0


def _footsteps(source) -> tuple:
    return tuple((source.reference if isinstance(source, AdjustedWalk) else source).footsteps)


def run_push_trial(backend, controller, robot, force: float, direction: float, phase: str,
                   adjuster: Optional[OnlineStepAdjusterParams] = None,
                   step_limits: StepAdjustmentParams = HUMANOID_STEP_LIMITS,
                   recovery: float = RECOVERY, clock=None,
                   measured_zmp: bool = False, step_length: float = 0.0) -> PushTrialResult:
    """Walk in place (or forward), push the pelvis, walk on for `recovery` s (or until a fall).

    :param backend: a PyBulletBackend
    :param controller: a WalkingController
    :param robot: the RobotModel the controller uses (the measured DCM needs its legs)
    :param force: push magnitude (N), >= 0
    :param direction: push direction in the horizontal plane, from +x towards +y (rad)
    :param phase: a key of PHASES
    :param adjuster: step adjustment parameters, None (or enabled False) for none
    :param step_limits: the adjustment QP's limits and weights
    :param recovery: time walked after the push (s)
    :param clock: wall clock timing each adjustment (time.perf_counter), None for no timing
    :param measured_zmp: predict the DCM with the F/T ZMP instead of the stance foot
    :param step_length: 0 walks in place; 0.1 forward as the graph's push-directions does (m)
    :return: the trial's outcome
    :raises ConfigError: for a negative or non-finite force or an unknown phase
    """
    if not math.isfinite(force) or force < 0.0:
        raise ConfigError(f'force must be finite and >= 0 (N), got {force!r}')
    reference = walk_reference(step_length)
    start = push_start(reference, phase)
    push = ExternalPush(force=(force * math.cos(direction), force * math.sin(direction), 0.0),
                        duration=PUSH_DURATION, start_time=start)
    source = reference
    on_cycle = None
    times = []
    if adjuster is not None and adjuster.enabled:
        source, on_cycle = adjusted_source(reference, robot, adjuster, step_limits,
                                           measured_zmp, clock, times)
    runner = ClosedLoopRunner(backend, controller, source)
    runner.reset()
    runner.push(push)
    log = runner.run(start + PUSH_DURATION + recovery, on_cycle=on_cycle)
    fallen = bool(log.fallen)
    final = source.reference if isinstance(source, AdjustedWalk) else reference
    return PushTrialResult(
        fallen, float(log.fall_time) if fallen else math.nan, push,
        _revisions(source),
        tuple(source.history) if isinstance(source, AdjustedWalk) else (), final, log,
        np.array(times))
