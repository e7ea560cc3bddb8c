"""Walking references from footsteps: ZMP, hip, swing feet, leg masses and MPC bounds.

This is the paper's section "ZMP, Hip and Swing Reference Trajectories" and "Masses Reference
Trajectories", sampled at any times the MPC asks for.
"""
from dataclasses import dataclass
import math
from typing import List, Optional, Sequence, Tuple

import numpy as np

from biped_planner.errors import ConfigError
from biped_planner.footsteps import check_footstep_sequence, Footstep, LEFT
from biped_planner.lipm_trajectory import PiecewiseLipm
from biped_planner.step_timing import StepTiming
from biped_planner.support_polygon import double_support_box, scaled_foot_box
from biped_planner.swing_trajectory import swing_lift, swing_progress

SUPPORT_LEFT = 0
SUPPORT_RIGHT = 1
SUPPORT_DOUBLE = 2

PHASE_STAND = 'stand'
PHASE_INITIAL_SHIFT = 'initial_shift'
PHASE_SINGLE_SUPPORT = 'single_support'
PHASE_DOUBLE_SUPPORT = 'double_support'
PHASE_FINAL_SETTLE = 'final_settle'

NO_SWING = -1
# Where, as fractions of its duration, a double support phase gets its free ZMP knots: one in
# the phase that starts a plan (initial shift, or the first double support after a splice) and
# one in the final settle; two when the final settle is also the first phase after a splice.
FREE_KNOT_FRACTIONS = {1: (0.5,), 2: (1.0 / 3.0, 2.0 / 3.0)}
_PRECOMPUTED_SAMPLES = 1024


def _check(name: str, value: float, low: float, high: float, low_open: bool = False) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or value > high or value < low or (low_open and value == low):
        bracket = '(' if low_open else '['
        raise ConfigError(f'ReferenceParams.{name} must be a finite number in {bracket}{low}, '
                          f'{high}], got {value!r}')


@dataclass(frozen=True)
class ReferenceParams:
    """Parameters of the reference trajectories.

    :param com_height: LIPM height of the hip z_h, omega = sqrt(g / z_h) (m), (0.05, 5]
    :param swing_height: highest point of the swing foot above the ground (m), [0, 0.5]
    :param foot_length: sole length along the foot heading (m), (0, 1]
    :param foot_width: sole width (m), (0, 1]
    :param support_scale: scale of the foot in the ZMP bounds (the paper's 0.9), (0, 1]
    :param gravity: gravitational acceleration g (m/s^2), (0, 30]
    :param landing_half_length: half size along world x of the swing landing box (m), [0, 2]
    :param landing_half_width: half size along world y of the swing landing box (m), [0, 2]
    :param initial_shift_time: double support that shifts the hip from standing over the first
        support foot, the paper's Initialize state (s), [0.1, 10]
    :param final_settle_time: final double support that brings the hip to rest midway between
        the last two feet (s), [0.1, 10]
    """

    com_height: float = 0.5
    swing_height: float = 0.04
    foot_length: float = 0.16
    foot_width: float = 0.08
    support_scale: float = 0.9
    gravity: float = 9.81
    landing_half_length: float = 0.05
    landing_half_width: float = 0.05
    initial_shift_time: float = 1.0
    final_settle_time: float = 1.0

    def __post_init__(self) -> None:
        _check('com_height', self.com_height, 0.05, 5.0, low_open=True)
        _check('swing_height', self.swing_height, 0.0, 0.5)
        _check('foot_length', self.foot_length, 0.0, 1.0, low_open=True)
        _check('foot_width', self.foot_width, 0.0, 1.0, low_open=True)
        _check('support_scale', self.support_scale, 0.0, 1.0, low_open=True)
        _check('gravity', self.gravity, 0.0, 30.0, low_open=True)
        _check('landing_half_length', self.landing_half_length, 0.0, 2.0)
        _check('landing_half_width', self.landing_half_width, 0.0, 2.0)
        _check('initial_shift_time', self.initial_shift_time, 0.1, 10.0)
        _check('final_settle_time', self.final_settle_time, 0.1, 10.0)

    @property
    def omega(self) -> float:
        """LIPM natural frequency sqrt(g / z_h) (1/s)."""
        return math.sqrt(self.gravity / self.com_height)


@dataclass(frozen=True)
class ReferenceWindow:
    """References at N sample times (all positions in the world frame, m).

    :param t: sample times (N,) (s)
    :param zmp: ZMP reference (N, 2)
    :param hip: hip (COM) reference (N, 2)
    :param left_foot: left sole centre x, y, z (N, 3), z > 0 while swinging
    :param right_foot: right sole centre x, y, z (N, 3)
    :param left_yaw: left foot heading (N,) (rad), unwrapped along the plan
    :param right_yaw: right foot heading (N,) (rad)
    :param left_mass: left leg mass, midway between the left sole centre and the hip (N, 2)
    :param right_mass: right leg mass, midway between the right sole centre and the hip (N, 2)
    :param zmp_min: lower corner of the axis-aligned support polygon box (N, 2)
    :param zmp_max: upper corner of the support polygon box (N, 2)
    :param left_landing_min: lower corner of the left swing landing box, -inf in stance (N, 2)
    :param left_landing_max: upper corner of the left swing landing box, +inf in stance (N, 2)
    :param right_landing_min: lower corner of the right swing landing box (N, 2)
    :param right_landing_max: upper corner of the right swing landing box (N, 2)
    :param support: SUPPORT_LEFT, SUPPORT_RIGHT or SUPPORT_DOUBLE (N,) uint8
    :param step_index: 0 before the first step, k + 1 during step k (which lands footsteps[k + 2])
        (N,) int
    """

    t: np.ndarray
    zmp: np.ndarray
    hip: np.ndarray
    left_foot: np.ndarray
    right_foot: np.ndarray
    left_yaw: np.ndarray
    right_yaw: np.ndarray
    left_mass: np.ndarray
    right_mass: np.ndarray
    zmp_min: np.ndarray
    zmp_max: np.ndarray
    left_landing_min: np.ndarray
    left_landing_max: np.ndarray
    right_landing_min: np.ndarray
    right_landing_max: np.ndarray
    support: np.ndarray
    step_index: np.ndarray


@dataclass(frozen=True)
class ReferencePhase:
    """One phase of the walking reference.

    :param kind: PHASE_STAND, PHASE_INITIAL_SHIFT, PHASE_SINGLE_SUPPORT, PHASE_DOUBLE_SUPPORT or
        PHASE_FINAL_SETTLE
    :param t_begin: start time (s)
    :param t_end: end time (s)
    :param support: SUPPORT_LEFT, SUPPORT_RIGHT or SUPPORT_DOUBLE
    :param step_index: as in ReferenceWindow.step_index
    :param swing_side: LEFT or RIGHT in single support, NO_SWING otherwise
    """

    kind: str
    t_begin: float
    t_end: float
    support: int
    step_index: int
    swing_side: int


@dataclass
class _PhaseRows:
    """Per-phase rows, appended while planning and turned into arrays for sampling."""

    phases: List[ReferencePhase]
    feet_start: List[List[float]]
    feet_delta: List[List[float]]
    feet_height: List[List[float]]
    zmp_min: List[np.ndarray]
    zmp_max: List[np.ndarray]
    landing: List[List[float]]
    knot_times: List[float]
    knot_zmp: List[np.ndarray]
    free_knots: List[int]


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2.0 * math.pi) - math.pi


class WalkingReference:
    """ZMP, hip, swing and leg-mass references of a footstep plan, sampled at any times.

    Timeline (t_start is the time the walk starts from standing):

    * initial shift (double support, initial_shift_time): the ZMP moves from below the standing
      hip to the first support foot (the paper's Initialize state);
    * for each step k (swing foot from its previous footstep to footsteps[k + 2]): single support
      T_ss with the ZMP at the centre of the stance foot, then double support T_ds with the ZMP
      moving linearly to the foot that just landed (eq. zmpEquation,
      p = f_i + SL (t - T_ss) / T_ds);
    * the last step's double support is the final settle (final_settle_time): the ZMP moves to
      the midpoint of the last two feet and the hip comes to rest there; later times hold it.

    Hip: the LIPM analytic solution of eq. com_traj_x0xf in every segment of constant or linear
    ZMP, with the boundary positions of the unique bounded (non-falling) solution, which makes the
    hip C2 (see biped_planner.lipm_trajectory). To start exactly at rest (hip velocity zero at
    t_start) and end exactly at rest, the ZMP in the middle of the initial shift and of the final
    settle is shifted by the amount that satisfies these two conditions (about 6 cm from the
    straight ramp with the defaults, which the tests check stays inside the double support box):
    the ZMP first moves about 1 cm towards the swing foot, as in human gait initiation.

    Swing foot: quintic Bezier curves (biped_planner.swing_trajectory), zero velocity at lift-off
    and touch-down. Leg masses (section "Masses Reference Trajectories"): each leg's mass is
    midway between its sole centre and the hip. For the stance leg in single support this is the
    paper's "midway between the ZMP and the hip" because the ZMP is at the stance sole centre; for
    the swing leg it is the paper's "midway between the swing foot and the hip"; in double support
    (both legs stance) each leg uses its own sole centre, which keeps the references continuous
    when a foot lands.

    Bounds: zmp_min/zmp_max are the axis-aligned box of the stance foot scaled by support_scale in
    single support and the box spanning both scaled feet in double support
    (biped_planner.support_polygon); the landing box of the swing leg is the planned landing sole
    centre +- (landing_half_length, landing_half_width), and +-inf for a leg in stance or in
    double support. The landing box bounds the foot; the matching leg-mass box is
    (box + hip) / 2.
    """

    def __init__(self, footsteps: Sequence[Footstep], timing: StepTiming,
                 params: ReferenceParams = ReferenceParams(),
                 hip0: Optional[Sequence[float]] = None, t_start: float = 0.0) -> None:
        """Plan the references of a walk that starts from standing.

        :param footsteps: footstep list (footsteps[0] first support foot, footsteps[1] first
            swing foot's initial place, then the landings), at least 3
        :param timing: single and double support durations of every step
        :param params: reference parameters
        :param hip0: standing hip position (x, y) at t_start (m); default midway between the
            two initial feet
        :param t_start: time the initial shift starts (s)
        :raises ConfigError: if the footsteps break the convention, an argument has the wrong
            type, or hip0 / t_start is not finite
        """
        if not isinstance(timing, StepTiming):
            raise ConfigError(f'timing must be a StepTiming, got {type(timing).__name__}')
        if not isinstance(params, ReferenceParams):
            raise ConfigError(f'params must be ReferenceParams, got {type(params).__name__}')
        if isinstance(t_start, bool) or not isinstance(t_start, (int, float)) \
                or not math.isfinite(t_start):
            raise ConfigError(f't_start must be a finite number, got {t_start!r}')
        footsteps = tuple(footsteps)
        check_footstep_sequence(footsteps)
        if hip0 is None:
            hip0 = np.array([0.5 * (footsteps[0].x + footsteps[1].x),
                             0.5 * (footsteps[0].y + footsteps[1].y)])
        else:
            try:
                hip0 = np.asarray(hip0, dtype=float)
            except (TypeError, ValueError) as error:
                raise ConfigError(f'hip0 must be 2 finite numbers (x, y), got {hip0!r}') \
                    from error
            if hip0.shape != (2,) or not np.all(np.isfinite(hip0)):
                raise ConfigError(f'hip0 must be 2 finite numbers (x, y), got {hip0!r}')
        self._params = params
        self._omega = params.omega
        self._footsteps = footsteps
        self._step_timings = [timing] * (len(footsteps) - 2)
        self._t_start = float(t_start)
        rows = self._plan(first_step=0, t_begin=self._t_start, start_zmp=hip0, stand_until=None,
                          yaws=None)
        self._lipm = PiecewiseLipm(np.array(rows.knot_times), np.array(rows.knot_zmp),
                                   self._omega, hip0, hip0,
                                   (rows.free_knots[0], rows.free_knots[-1]))
        self._set_phases(rows, keep=0)

    @property
    def footsteps(self) -> Tuple[Footstep, ...]:
        """The footstep list being walked (initial feet, then landings)."""
        return self._footsteps

    @property
    def params(self) -> ReferenceParams:
        """The reference parameters."""
        return self._params

    @property
    def omega(self) -> float:
        """LIPM natural frequency (1/s)."""
        return self._omega

    @property
    def t_start(self) -> float:
        """Time the initial shift starts (s)."""
        return self._t_start

    @property
    def t_end(self) -> float:
        """Time the hip comes to rest at the end of the final settle (s)."""
        return self._phases[-1].t_end

    @property
    def duration(self) -> float:
        """Time from the start of the initial shift to the end of the final settle (s)."""
        return self.t_end - self._t_start

    @property
    def n_steps(self) -> int:
        """Number of steps (swings) in the plan."""
        return len(self._footsteps) - 2

    @property
    def phases(self) -> Tuple[ReferencePhase, ...]:
        """The phases of the plan in time order."""
        return self._phases

    @property
    def lipm(self) -> PiecewiseLipm:
        """The hip trajectory (ZMP knots, boundary conditions, hip velocity)."""
        return self._lipm

    @property
    def start_correction(self) -> float:
        """ZMP shift at the free knot of the last (re)planned start (m): how much the ZMP had to
        bend to start from rest or to join the previous plan smoothly."""
        return float(self._lipm.correction[0])

    def step_timing(self, step: int) -> StepTiming:
        """Timing of one step.

        :param step: step index k (0-based; step k lands footsteps[k + 2])
        :return: its StepTiming
        :raises ConfigError: if there is no such step
        """
        if not 0 <= step < len(self._step_timings):
            raise ConfigError(f'step must be in [0, {len(self._step_timings) - 1}], got {step!r}')
        return self._step_timings[step]

    def sample(self, t0: float, n: int, dt: float) -> ReferenceWindow:
        """References at t0, t0 + dt, ..., t0 + (n - 1) dt.

        Times before t_start give the standing pose at the start and times after t_end the final
        standing pose.

        :param t0: first sample time (s)
        :param n: number of samples, >= 1
        :param dt: sample period (s), > 0
        :return: the references
        :raises ConfigError: if t0 or dt is not finite, dt <= 0 or n < 1
        """
        if not isinstance(t0, (int, float)) or not math.isfinite(t0):
            raise ConfigError(f't0 must be a finite number, got {t0!r}')
        if not isinstance(dt, (int, float)) or not math.isfinite(dt) or dt <= 0.0:
            raise ConfigError(f'dt must be a finite number > 0, got {dt!r}')
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ConfigError(f'n must be an integer >= 1, got {n!r}')
        ramp = _RAMP[:n] if n <= _PRECOMPUTED_SAMPLES else np.arange(n, dtype=float)
        t = t0 + dt * ramp
        # One gather of the per-segment table, then column arithmetic: the LIPM evaluation of
        # PiecewiseLipm.evaluate and the phase lookups, inlined for speed.
        j = np.searchsorted(self._knot_times, t, side='right') - 1
        np.clip(j, 0, self._segment_count - 1, out=j)
        row = self._table[j]
        tau = np.minimum(np.maximum(t - row[:, _T0], 0.0), row[:, _SPAN])
        zmp = row[:, _ZMP] + row[:, _SLOPE] * tau[:, None]
        omega = self._omega
        stable = np.exp(-omega * tau)
        unstable = np.exp(omega * (tau - row[:, _SPAN]))
        hip = zmp + row[:, _STABLE] * stable[:, None] + row[:, _UNSTABLE] * unstable[:, None]
        s = (t - row[:, _PHASE_T0]) * row[:, _PHASE_RATE]
        np.clip(s, 0.0, 1.0, out=s)
        feet = row[:, _FEET_START] + row[:, _FEET_DELTA] * swing_progress(s)[:, None]
        lift = row[:, _FEET_HEIGHT] * swing_lift(s)[:, None]
        left_foot = np.empty((n, 3))
        left_foot[:, :2] = feet[:, 0:2]
        left_foot[:, 2] = lift[:, 0]
        right_foot = np.empty((n, 3))
        right_foot[:, :2] = feet[:, 3:5]
        right_foot[:, 2] = lift[:, 1]
        return ReferenceWindow(
            t=t, zmp=zmp, hip=hip, left_foot=left_foot, right_foot=right_foot,
            left_yaw=feet[:, 2], right_yaw=feet[:, 5],
            left_mass=0.5 * (feet[:, 0:2] + hip), right_mass=0.5 * (feet[:, 3:5] + hip),
            zmp_min=row[:, _ZMP_MIN], zmp_max=row[:, _ZMP_MAX],
            left_landing_min=row[:, _LEFT_LANDING_MIN], left_landing_max=row[:, _LEFT_LANDING_MAX],
            right_landing_min=row[:, _RIGHT_LANDING_MIN],
            right_landing_max=row[:, _RIGHT_LANDING_MAX],
            support=row[:, _SUPPORT].astype(np.uint8), step_index=row[:, _STEP].astype(np.int64))

    def extend(self, footsteps: Sequence[Footstep], t_now: float,
               timing: Optional[StepTiming] = None,
               replace_from: Optional[int] = None) -> 'WalkingReference':
        """A new reference that walks this plan and then the given landings (online extension).

        Nothing before t_now changes. The plan is rejoined at the splice time: the start of the
        first double support (not the initial shift) that begins at or after t_now. From there
        the old final settle becomes an ordinary double support and the new steps follow. The
        splice keeps the hip position and velocity (the hip stays C2) by shifting the ZMP at a
        free knot in the middle of that double support; start_correction reports by how much.
        The shift is small when the footsteps that change are a step or more after the splice,
        so extend one or two steps ahead of the robot (a teleop node that keeps a preview of
        the next steps at the current command and replaces it with replace_from changes little).
        If no such double support is left (t_now in the final settle or after it), the new walk
        starts from standing at max(t_now, t_end) with a new initial shift.

        :param footsteps: the new landings; feet alternate, and the first is the other foot than
            the footstep before replace_from
        :param t_now: current time (s)
        :param timing: timing of the new steps (default: that of the last kept step)
        :param replace_from: index of the first footstep to replace (default: append after the
            last); it must not be a foot already landed or swinging at the splice time
        :return: the extended reference (self if nothing changes)
        :raises ConfigError: if the footsteps break the convention, replace_from names a
            footstep that can no longer change, timing has the wrong type or t_now is not
            finite
        """
        if isinstance(t_now, bool) or not isinstance(t_now, (int, float)) \
                or not math.isfinite(t_now):
            raise ConfigError(f't_now must be a finite number, got {t_now!r}')
        footsteps = tuple(footsteps)
        old_count = len(self._footsteps)
        if replace_from is None:
            replace_from = old_count
        if isinstance(replace_from, bool) or not isinstance(replace_from, (int, np.integer)) \
                or not 2 <= replace_from <= old_count:
            raise ConfigError(f'replace_from must be an integer in [2, {old_count}], got '
                              f'{replace_from!r}')
        if not footsteps and replace_from == old_count:
            return self
        if timing is None:
            timing = self._step_timings[replace_from - 3] if replace_from > 2 \
                else self._step_timings[0]
        elif not isinstance(timing, StepTiming):
            raise ConfigError(f'timing must be a StepTiming, got {type(timing).__name__}')
        cut = next((index for index, phase in enumerate(self._phases)
                    if phase.t_begin >= t_now
                    and phase.kind in (PHASE_DOUBLE_SUPPORT, PHASE_FINAL_SETTLE)), None)
        first_free = old_count if cut is None else self._phases[cut].step_index + 2
        if replace_from < first_free:
            raise ConfigError(f'at t_now={t_now} the footsteps before index {first_free} are '
                              f'landed or swinging: replace_from={replace_from} is too early')
        all_footsteps = self._footsteps[:replace_from] + footsteps
        check_footstep_sequence(all_footsteps)
        extended = WalkingReference.__new__(WalkingReference)
        extended._params = self._params
        extended._omega = self._omega
        extended._footsteps = all_footsteps
        extended._step_timings = self._step_timings[:replace_from - 2] + [timing] * len(
            footsteps)
        extended._t_start = self._t_start
        old = self._lipm
        if cut is None:
            cut = len(self._phases)
            cut_knot = old.times.size - 1
            rows = extended._plan(first_step=self.n_steps, t_begin=float(old.times[-1]),
                                  start_zmp=old.zmp[-1], stand_until=t_now,
                                  yaws=self._final_yaws())
        else:
            t_cut = self._phases[cut].t_begin
            cut_knot = int(np.searchsorted(old.times, t_cut))
            rows = extended._plan(first_step=self._phases[cut].step_index - 1, t_begin=t_cut,
                                  start_zmp=None, stand_until=None,
                                  yaws=self._yaws_at_phase(cut))
        tail = PiecewiseLipm(np.array(rows.knot_times), np.array(rows.knot_zmp), self._omega,
                             old.zmp[cut_knot] + old.offsets[cut_knot], old.dcm[cut_knot],
                             (rows.free_knots[0], rows.free_knots[-1]))
        extended._lipm = PiecewiseLipm.concatenate(old, cut_knot, tail)
        extended._set_phases(rows, cut, self)
        return extended

    def _final_yaws(self) -> Tuple[float, float]:
        final = self._feet_start[-1] + self._feet_delta[-1]
        return float(final[2]), float(final[5])

    def _yaws_at_phase(self, index: int) -> Tuple[float, float]:
        start = self._feet_start[index]
        return float(start[2]), float(start[5])

    def _plan(self, first_step: int, t_begin: float, start_zmp: Optional[np.ndarray],
              stand_until: Optional[float], yaws: Optional[Tuple[float, float]]) -> _PhaseRows:
        """Phases and ZMP knots from t_begin to the end of the plan.

        With start_zmp, the plan starts from standing (optional stand until stand_until, then the
        initial shift) before step first_step; without it, it starts with the double support of
        step first_step.
        """
        params = self._params
        fs = self._footsteps
        swing_order = (fs[1], fs[0]) + fs[2:]
        n_steps = len(fs) - 2
        rows = _PhaseRows([], [], [], [], [], [], [], [], [], [])
        foot_yaw = list(yaws) if yaws is not None else [0.0, 0.0]
        if yaws is None:
            for step in fs[:2]:
                foot_yaw[step.side] = step.yaw
        no_landing = [-math.inf, -math.inf, math.inf, math.inf]

        def box(step: Footstep) -> Tuple[np.ndarray, np.ndarray]:
            return scaled_foot_box(step.x, step.y, step.yaw, params.foot_length,
                                   params.foot_width, params.support_scale)

        def pose(step: Footstep) -> List[float]:
            return [step.x, step.y, foot_yaw[step.side]]

        def add_still(kind: str, t0: float, t1: float, feet: Tuple[Footstep, Footstep],
                      zmp0: np.ndarray, zmp1: np.ndarray, step_index: int, free: int) -> None:
            by_side = {feet[0].side: feet[0], feet[1].side: feet[1]}
            rows.phases.append(ReferencePhase(kind, t0, t1, SUPPORT_DOUBLE, step_index, NO_SWING))
            rows.feet_start.append(pose(by_side[LEFT]) + pose(by_side[1 - LEFT]))
            rows.feet_delta.append([0.0] * 6)
            rows.feet_height.append([0.0, 0.0])
            lower, upper = double_support_box(box(feet[0]), box(feet[1]))
            rows.zmp_min.append(lower)
            rows.zmp_max.append(upper)
            rows.landing.append(no_landing + no_landing)
            rows.knot_times.append(t0)
            rows.knot_zmp.append(np.asarray(zmp0, dtype=float))
            for fraction in FREE_KNOT_FRACTIONS.get(free, ()):
                rows.free_knots.append(len(rows.knot_times))
                rows.knot_times.append(t0 + fraction * (t1 - t0))
                rows.knot_zmp.append((1.0 - fraction) * np.asarray(zmp0)
                                     + fraction * np.asarray(zmp1))

        def centre(step: Footstep) -> np.ndarray:
            return np.array([step.x, step.y])

        t = t_begin
        if start_zmp is not None:
            feet = (swing_order[first_step], swing_order[first_step + 1])
            if stand_until is not None and stand_until > t:
                add_still(PHASE_STAND, t, stand_until, feet, start_zmp, start_zmp, first_step,
                          free=0)
                t = stand_until
            t1 = t + params.initial_shift_time
            add_still(PHASE_INITIAL_SHIFT, t, t1, feet, start_zmp, centre(feet[1]), first_step,
                      free=1)
            t = t1
            first_single = first_step
        else:
            first_single = first_step + 1
        for k in range(first_step, n_steps):
            stance, landed = swing_order[k + 1], swing_order[k + 2]
            if k >= first_single:
                lift_off = swing_order[k]
                t1 = t + self._step_timings[k].single_support
                swing_side = lift_off.side
                stance_side = stance.side
                start = pose(lift_off)
                turn = _wrap(landed.yaw - foot_yaw[swing_side])
                end_delta = [landed.x - lift_off.x, landed.y - lift_off.y, turn]
                foot_yaw[swing_side] += turn
                swing_rows = (start, end_delta, [params.swing_height])
                stance_rows = (pose(stance), [0.0, 0.0, 0.0], [0.0])
                left_rows, right_rows = ((swing_rows, stance_rows) if swing_side == LEFT
                                         else (stance_rows, swing_rows))
                rows.phases.append(ReferencePhase(
                    PHASE_SINGLE_SUPPORT, t, t1,
                    SUPPORT_LEFT if stance_side == LEFT else SUPPORT_RIGHT, k + 1, swing_side))
                rows.feet_start.append(left_rows[0] + right_rows[0])
                rows.feet_delta.append(left_rows[1] + right_rows[1])
                rows.feet_height.append(left_rows[2] + right_rows[2])
                lower, upper = box(stance)
                rows.zmp_min.append(lower)
                rows.zmp_max.append(upper)
                landing = [landed.x - params.landing_half_length,
                           landed.y - params.landing_half_width,
                           landed.x + params.landing_half_length,
                           landed.y + params.landing_half_width]
                rows.landing.append(landing + no_landing if swing_side == LEFT
                                    else no_landing + landing)
                rows.knot_times.append(t)
                rows.knot_zmp.append(centre(stance))
                t = t1
            if k < n_steps - 1:
                t1 = t + self._step_timings[k].double_support
                add_still(PHASE_DOUBLE_SUPPORT, t, t1, (stance, landed), centre(stance),
                          centre(landed), k + 1, free=int(k < first_single))
            else:
                t1 = t + params.final_settle_time
                add_still(PHASE_FINAL_SETTLE, t, t1, (stance, landed), centre(stance),
                          0.5 * (centre(stance) + centre(landed)), k + 1,
                          free=1 + int(k < first_single))
                rows.knot_times.append(t1)
                rows.knot_zmp.append(0.5 * (centre(stance) + centre(landed)))
            t = t1
        return rows

    def _set_phases(self, rows: _PhaseRows, keep: int,
                    previous: Optional['WalkingReference'] = None) -> None:
        """Store the phases as arrays: the first keep of previous, then the planned rows."""
        def joined(name: str, new: list, dtype=float) -> np.ndarray:
            new_array = np.array(new, dtype=dtype)
            if previous is None:
                return new_array
            return np.concatenate((getattr(previous, name)[:keep], new_array))

        self._phases = (previous._phases[:keep] if previous is not None else ()) + tuple(
            rows.phases)
        self._phase_t0 = np.array([phase.t_begin for phase in self._phases])
        self._phase_rate = 1.0 / np.array([phase.t_end - phase.t_begin
                                           for phase in self._phases])
        self._support = np.array([phase.support for phase in self._phases], dtype=np.uint8)
        self._step_index = np.array([phase.step_index for phase in self._phases], dtype=np.int64)
        self._feet_start = joined('_feet_start', rows.feet_start)
        self._feet_delta = joined('_feet_delta', rows.feet_delta)
        self._feet_height = joined('_feet_height', rows.feet_height)
        self._zmp_min = joined('_zmp_min', rows.zmp_min)
        self._zmp_max = joined('_zmp_max', rows.zmp_max)
        self._landing = joined('_landing', rows.landing)
        self._build_table()

    def _build_table(self) -> None:
        """One row per ZMP segment with everything sample() needs (see the column slices)."""
        lipm = self._lipm
        knots = lipm.times
        segment_phase = np.searchsorted(self._phase_t0, knots[:-1], side='right') - 1
        np.clip(segment_phase, 0, self._phase_t0.size - 1, out=segment_phase)
        columns = [knots[:-1, None], lipm.span[:, None], lipm.zmp[:-1], lipm.slope,
                   lipm.coef_stable, lipm.coef_unstable, self._phase_t0[segment_phase, None],
                   self._phase_rate[segment_phase, None], self._feet_start[segment_phase],
                   self._feet_delta[segment_phase], self._feet_height[segment_phase],
                   self._zmp_min[segment_phase], self._zmp_max[segment_phase],
                   self._landing[segment_phase], self._support[segment_phase, None],
                   self._step_index[segment_phase, None]]
        self._table = np.hstack([np.asarray(column, dtype=float) for column in columns])
        self._knot_times = knots
        self._segment_count = knots.size - 1


_TABLE_WIDTHS = (('_T0', 1), ('_SPAN', 1), ('_ZMP', 2), ('_SLOPE', 2), ('_STABLE', 2),
                 ('_UNSTABLE', 2), ('_PHASE_T0', 1), ('_PHASE_RATE', 1), ('_FEET_START', 6),
                 ('_FEET_DELTA', 6), ('_FEET_HEIGHT', 2), ('_ZMP_MIN', 2), ('_ZMP_MAX', 2),
                 ('_LEFT_LANDING_MIN', 2), ('_LEFT_LANDING_MAX', 2), ('_RIGHT_LANDING_MIN', 2),
                 ('_RIGHT_LANDING_MAX', 2), ('_SUPPORT', 1), ('_STEP', 1))


def _table_columns() -> dict:
    columns = {}
    first = 0
    for name, width in _TABLE_WIDTHS:
        columns[name] = first if width == 1 else slice(first, first + width)
        first += width
    return columns


_COLUMNS = _table_columns()
_T0, _SPAN, _ZMP, _SLOPE = (_COLUMNS[n] for n in ('_T0', '_SPAN', '_ZMP', '_SLOPE'))
_STABLE, _UNSTABLE = _COLUMNS['_STABLE'], _COLUMNS['_UNSTABLE']
_PHASE_T0, _PHASE_RATE = _COLUMNS['_PHASE_T0'], _COLUMNS['_PHASE_RATE']
_FEET_START, _FEET_DELTA = _COLUMNS['_FEET_START'], _COLUMNS['_FEET_DELTA']
_FEET_HEIGHT, _ZMP_MIN, _ZMP_MAX = (_COLUMNS[n] for n in ('_FEET_HEIGHT', '_ZMP_MIN',
                                                          '_ZMP_MAX'))
_LEFT_LANDING_MIN, _LEFT_LANDING_MAX = (_COLUMNS['_LEFT_LANDING_MIN'],
                                        _COLUMNS['_LEFT_LANDING_MAX'])
_RIGHT_LANDING_MIN, _RIGHT_LANDING_MAX = (_COLUMNS['_RIGHT_LANDING_MIN'],
                                          _COLUMNS['_RIGHT_LANDING_MAX'])
_SUPPORT, _STEP = _COLUMNS['_SUPPORT'], _COLUMNS['_STEP']
_RAMP = np.arange(_PRECOMPUTED_SAMPLES, dtype=float)
