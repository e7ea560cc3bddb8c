"""Walking references from footsteps: ZMP, hip, swing feet, leg masses and MPC bounds.

This is the paper's section "ZMP, Hip and Swing Reference Trajectories" and "Masses Reference
Trajectories", sampled at any times the MPC asks for. The pieces: the parameters
(biped_planner.reference_params), the phases and ZMP knots of a plan
(biped_planner.reference_phases), the hip of the LIPM (biped_planner.lipm_trajectory), the
table that samples them (biped_planner.reference_table) and the window handed to the MPC
(biped_planner.reference_window).
"""
import math
from typing import Optional, Sequence, Tuple

import numpy as np

from biped_planner.errors import ConfigError
from biped_planner.footsteps import check_footstep_sequence, Footstep
from biped_planner.input_checks import (check_finite_array, check_integer, check_number,
                                        check_type)
from biped_planner.lipm_trajectory import PiecewiseLipm
from biped_planner.reference_params import ReferenceParams
from biped_planner.reference_phases import (PHASE_DOUBLE_SUPPORT, PHASE_FINAL_SETTLE,
                                            PHASE_SINGLE_SUPPORT, PhaseRows, PhaseTable,
                                            plan_phases, ReferencePhase)
from biped_planner.reference_table import ReferenceTable
from biped_planner.reference_window import ReferenceWindow
from biped_planner.rotations import wrap_angle
# Support labels and the window, importable from here by the packages that used to find them
# here; biped_planner.sides and biped_planner.reference_window define them.
from biped_planner.sides import SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT  # noqa: F401
from biped_planner.step_timing import StepTiming


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
        check_type('timing', timing, StepTiming)
        check_type('params', params, ReferenceParams)
        check_number('t_start', t_start)
        footsteps = tuple(footsteps)
        check_footstep_sequence(footsteps)
        if hip0 is None:
            hip0 = np.array([0.5 * (footsteps[0].x + footsteps[1].x),
                             0.5 * (footsteps[0].y + footsteps[1].y)])
        else:
            hip0 = check_finite_array('hip0 (x, y)', hip0, shape=(2,))
        self._params = params
        self._omega = params.omega
        self._footsteps = footsteps
        self._step_timings = [timing] * (len(footsteps) - 2)
        self._t_start = float(t_start)
        rows = plan_phases(footsteps, self._step_timings, params, first_step=0,
                           t_begin=self._t_start, start_zmp=hip0, stand_until=None, yaws=None)
        self._lipm = PiecewiseLipm(np.array(rows.knot_times), np.array(rows.knot_zmp),
                                   self._omega, hip0, hip0,
                                   (rows.free_knots[0], rows.free_knots[-1]))
        self._revision = 0
        self._set_phases(rows, keep=0)

    @property
    def revision(self) -> int:
        """Plan revision: 0 as built, one more at every extend or adjust_step that changes it."""
        return self._revision

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
        return self._phases.phases[-1].t_end

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
        return self._phases.phases

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
        check_number('t0', t0)
        check_number('dt', dt, low=0.0, low_open=True, unit=' s')
        check_integer('n', n, low=1)
        return self._table.sample(t0, n, dt)

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
        check_number('t_now', t_now)
        footsteps = tuple(footsteps)
        old_count = len(self._footsteps)
        if replace_from is None:
            replace_from = old_count
        check_integer('replace_from', replace_from, low=2, high=old_count)
        if not footsteps and replace_from == old_count:
            return self
        if timing is None:
            timing = self._step_timings[replace_from - 3] if replace_from > 2 \
                else self._step_timings[0]
        else:
            check_type('timing', timing, StepTiming)
        phases = self._phases.phases
        cut = next((index for index, phase in enumerate(phases)
                    if phase.t_begin >= t_now
                    and phase.kind in (PHASE_DOUBLE_SUPPORT, PHASE_FINAL_SETTLE)), None)
        first_free = old_count if cut is None else phases[cut].step_index + 2
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
        extended._revision = self._revision + 1
        old = self._lipm
        if cut is None:
            cut = len(phases)
            cut_knot = old.times.size - 1
            rows = plan_phases(all_footsteps, extended._step_timings, self._params,
                               first_step=self.n_steps, t_begin=float(old.times[-1]),
                               start_zmp=old.zmp[-1], stand_until=t_now,
                               yaws=self._phases.final_yaws())
        else:
            t_cut = phases[cut].t_begin
            cut_knot = int(np.searchsorted(old.times, t_cut))
            rows = plan_phases(all_footsteps, extended._step_timings, self._params,
                               first_step=phases[cut].step_index - 1, t_begin=t_cut,
                               start_zmp=None, stand_until=None,
                               yaws=self._phases.yaws_at(cut))
        tail = PiecewiseLipm(np.array(rows.knot_times), np.array(rows.knot_zmp), self._omega,
                             old.zmp[cut_knot] + old.offsets[cut_knot], old.dcm[cut_knot],
                             (rows.free_knots[0], rows.free_knots[-1]))
        extended._lipm = PiecewiseLipm.concatenate(old, cut_knot, tail)
        extended._set_phases(rows, cut, self)
        return extended

    def single_support_at(self, t: float) -> Optional[int]:
        """Index into phases of the single support under way at t, None outside single support.

        :param t: time (s)
        :return: the phase index or None
        """
        check_number('t', t)
        for index, phase in enumerate(self._phases.phases):
            if phase.t_begin <= t < phase.t_end:
                return index if phase.kind == PHASE_SINGLE_SUPPORT else None
        return None

    def adjust_step(self, t_now: float, footsteps: Sequence[Footstep], touchdown: float,
                    hip: Optional[Sequence[float]] = None,
                    dcm: Optional[Sequence[float]] = None,
                    dcm_from_footsteps: bool = False) -> 'WalkingReference':
        """A new reference in which the foot swinging now lands elsewhere and at another time.

        The step adjustment's replan, mid single support (extend cannot change a swinging
        foot). Step k, under way at t_now, lands footsteps[0] at touchdown instead of its
        planned landing and time; footsteps[1:] replace the later landings, and every later
        phase keeps its duration. The swing foot's curve keeps its lift-off and is stretched to
        the new landing and time, so it moves at once towards the new target.

        The hip is replanned from (hip, dcm) at t_now, the robot's state when given (default:
        this reference's own): the ZMP stays at the stance centre until touchdown, and the
        free knot of the next double support (the final settle's second one when the step is
        the last) bends the ZMP so that the hip passes through that state and still ends at
        rest (start_correction reports the bend). With dcm_from_footsteps the DCM at t_now is
        instead the one the new footsteps ask for (run back from the walk's end over their ZMP)
        and only the hip's position is kept: the reference's DCM jumps to where the moved step
        catches it, and no ZMP near the step is bent (the final settle's free knot still takes
        the hip's lag behind that DCM, so the walk ends at rest). The phases before the current
        single support are kept; the hip before t_now is the pendulum run backwards from the
        state, which sampling never asks for.

        :param t_now: current time, inside a single support phase (s)
        :param footsteps: the new landing of the swinging foot, then the later landings
        :param touchdown: new end of the single support (s), > t_now
        :param hip: (2,) hip position at t_now (m), None for this reference's own
        :param dcm: (2,) DCM hip + hip velocity / omega at t_now (m), with hip
        :param dcm_from_footsteps: the DCM from the new footsteps instead of the ZMP's bend
            (dcm is then not used)
        :return: the adjusted reference, revision one higher
        :raises ConfigError: if t_now is not in single support, the footsteps break the
            convention, the touchdown is not after t_now or hip and dcm are not both given
        """
        check_number('t_now', t_now)
        check_number('touchdown', touchdown, low=t_now, low_open=True, unit=' s')
        footsteps = tuple(footsteps)
        cut = self.single_support_at(t_now)
        if cut is None:
            raise ConfigError(f't_now={t_now} s is not in a single support phase')
        hip, dcm = self._state_at(t_now, hip, dcm)
        phase = self._phases.phases[cut]
        step = phase.step_index - 1
        all_footsteps = self._footsteps[:step + 2] + footsteps
        check_footstep_sequence(all_footsteps)
        old_timing = self._step_timings[step]
        timings = self._step_timings[:step] + [
            StepTiming(single_support=touchdown - phase.t_begin,
                       double_support=old_timing.double_support)]
        later = self._step_timings[step + 1:]
        timings += [later[min(i, len(later) - 1)] if later else old_timing
                    for i in range(len(all_footsteps) - 3 - step)]

        landed = all_footsteps[step + 2]
        swing = phase.swing_side
        yaws = list(self._phases.yaws_at(cut))
        start = self._phases.feet_start[cut]
        column = 3 * swing
        delta = self._phases.feet_delta[cut].copy()
        delta[column:column + 3] = [landed.x - start[column], landed.y - start[column + 1],
                                    wrap_angle(landed.yaw - yaws[swing])]
        yaws[swing] += delta[column + 2]
        params = self._params
        landing = self._phases.landing[cut].copy()
        landing[4 * swing:4 * swing + 4] = [
            landed.x - params.landing_half_length, landed.y - params.landing_half_width,
            landed.x + params.landing_half_length, landed.y + params.landing_half_width]
        after = plan_phases(all_footsteps, timings, params, first_step=step, t_begin=touchdown,
                            start_zmp=None, stand_until=None, yaws=tuple(yaws))
        stance = self._knot_zmp_at(phase.t_begin)
        rows = PhaseRows(
            phases=[ReferencePhase(phase.kind, phase.t_begin, touchdown, phase.support,
                                   phase.step_index, swing)] + after.phases,
            feet_start=[list(start)] + after.feet_start,
            feet_delta=[list(delta)] + after.feet_delta,
            feet_height=[list(self._phases.feet_height[cut])] + after.feet_height,
            zmp_min=[self._phases.zmp_min[cut]] + after.zmp_min,
            zmp_max=[self._phases.zmp_max[cut]] + after.zmp_max,
            landing=[list(landing)] + after.landing,
            knot_times=[phase.t_begin] + after.knot_times,
            knot_zmp=[stance] + after.knot_zmp,
            free_knots=[index + 1 for index in after.free_knots])
        if dcm_from_footsteps:
            # the unbent knots' own DCM (run back from the end; the hip's start plays no part)
            times, zmp = np.array(rows.knot_times), np.array(rows.knot_zmp)
            _, dcm = PiecewiseLipm(times, zmp, self._omega, zmp[0]).state_at(t_now)
        return self._replanned_from(cut, rows, all_footsteps, timings, t_now, hip, dcm)

    def hold_landing(self, t_now: float, touchdown: float,
                     hip: Optional[Sequence[float]] = None,
                     dcm: Optional[Sequence[float]] = None) -> 'WalkingReference':
        """A new reference in which the single support of the latest swing lasts until touchdown.

        A late contact: the swing foot of step k reached its planned landing time t_L without
        touching the ground, so the single support goes on (the controller lowers the foot until
        it meets the ground) and the double support and every later phase start at touchdown
        instead, keeping their durations. Before t_L the swing is as planned; from t_L to
        touchdown a second single-support phase of the same step holds the swing foot at its
        planned landing pose (zero swing height) and the ZMP at the stance centre. Called again
        on a held step it moves the end of the hold: to the time the foot met the ground (a
        touchdown earlier than the held one), or later.

        The step is the one in single support at t_now, or the one whose single support ended
        last when t_now is in the double support right after it (the controller learns that
        the landing is late only at t_L). The hip is replanned from (hip, dcm) at t_now as in
        adjust_step: the ZMP on the stance centre from the lift-off until touchdown, and the
        free knot of the next double support bends the ZMP to join the plan.

        :param t_now: current time (s)
        :param touchdown: new end of the single support (s), > t_now and > t_L
        :param hip: (2,) hip position at t_now (m), None for this reference's own
        :param dcm: (2,) DCM at t_now (m), with hip
        :return: the held reference, revision one higher
        :raises ConfigError: if no swing has just ended or is under way at t_now, the touchdown
            is not after t_now and t_L, or hip and dcm are not both given
        """
        check_number('t_now', t_now)
        check_number('touchdown', touchdown, low=t_now, low_open=True, unit=' s')
        cut = self.swing_of_late_landing(t_now)
        if cut is None:
            raise ConfigError(f't_now={t_now} s is neither in a single support nor in the '
                              f'double support right after one')
        phases = self._phases
        swing_phase = phases.phases[cut]
        landing_time = swing_phase.t_end
        if not touchdown > landing_time:
            raise ConfigError(f'touchdown {touchdown} s must be after the planned landing '
                              f'{landing_time} s')
        hip, dcm = self._state_at(t_now, hip, dcm)
        step = swing_phase.step_index - 1
        old_timing = self._step_timings[step]
        timings = list(self._step_timings)
        timings[step] = StepTiming(single_support=touchdown - swing_phase.t_begin,
                                   double_support=old_timing.double_support)
        landed = [float(v) for v in phases.feet_start[cut] + phases.feet_delta[cut]]
        after = plan_phases(self._footsteps, timings, self._params, first_step=step,
                            t_begin=touchdown, start_zmp=None, stand_until=None,
                            yaws=(landed[2], landed[5]))
        stance = self._knot_zmp_at(swing_phase.t_begin)
        rows = PhaseRows(
            phases=[swing_phase,
                    ReferencePhase(PHASE_SINGLE_SUPPORT, landing_time, touchdown,
                                   swing_phase.support, swing_phase.step_index,
                                   swing_phase.swing_side)] + after.phases,
            feet_start=[list(phases.feet_start[cut]), landed] + after.feet_start,
            feet_delta=[list(phases.feet_delta[cut]), [0.0] * 6] + after.feet_delta,
            feet_height=[list(phases.feet_height[cut]), [0.0, 0.0]] + after.feet_height,
            zmp_min=[phases.zmp_min[cut]] * 2 + after.zmp_min,
            zmp_max=[phases.zmp_max[cut]] * 2 + after.zmp_max,
            landing=[list(phases.landing[cut])] * 2 + after.landing,
            knot_times=[swing_phase.t_begin, landing_time] + after.knot_times,
            knot_zmp=[stance, stance] + after.knot_zmp,
            free_knots=[index + 2 for index in after.free_knots])
        return self._replanned_from(cut, rows, self._footsteps, timings, t_now, hip, dcm)

    def _knot_zmp_at(self, t: float) -> np.ndarray:
        """The ZMP knot at time t (a phase's start: in single support, the stance centre)."""
        return np.asarray(self._lipm.zmp[np.searchsorted(self._lipm.times, t)])

    def swing_of_late_landing(self, t: float) -> Optional[int]:
        """Index into phases of the swing (single support) whose landing may be late at t.

        The single support under way at t (the first of a held step's two), or the one that
        ended last when t is in the double support (or final settle) right after it.

        :param t: time (s)
        :return: the phase index or None
        """
        check_number('t', t)
        phases = self._phases.phases
        index = next((i for i, phase in enumerate(phases) if phase.t_begin <= t < phase.t_end),
                     None)
        if index is None:
            return None
        if phases[index].kind in (PHASE_DOUBLE_SUPPORT, PHASE_FINAL_SETTLE):
            index -= 1
        if index < 0 or phases[index].kind != PHASE_SINGLE_SUPPORT:
            return None
        if index > 0 and phases[index - 1].kind == PHASE_SINGLE_SUPPORT and \
                phases[index - 1].step_index == phases[index].step_index:
            index -= 1  # the hold of a held step: its swing is the phase before
        return index

    def _state_at(self, t: float, hip, dcm) -> Tuple[np.ndarray, np.ndarray]:
        """(hip, dcm) given for a replan at t, checked, or this reference's own."""
        if (hip is None) != (dcm is None):
            raise ConfigError('hip and dcm are given together or not at all')
        if hip is None:
            hip, dcm = self._lipm.state_at(t)
        return (check_finite_array('hip (x, y)', hip, shape=(2,)),
                check_finite_array('dcm (x, y)', dcm, shape=(2,)))

    def _replanned_from(self, cut: int, rows: PhaseRows, footsteps: Tuple[Footstep, ...],
                        timings: list, t_now: float, hip: np.ndarray,
                        dcm: np.ndarray) -> 'WalkingReference':
        """A reference that keeps the phases before cut and walks rows from there, its hip the
        pendulum through (hip, dcm) at t_now with the ZMP on the stance centre since the
        lift-off of the single support rows start with."""
        lift_off = rows.phases[0].t_begin
        stance = np.asarray(rows.knot_zmp[0])
        # the pendulum on the stance centre, run back from t_now to the lift-off knot
        elapsed = self._omega * (t_now - lift_off)
        hip_start = stance + (hip - stance) * math.cosh(elapsed) - (dcm - hip) * math.sinh(
            elapsed)
        dcm_start = stance + (dcm - stance) * math.exp(-elapsed)
        tail = PiecewiseLipm(np.array(rows.knot_times), np.array(rows.knot_zmp), self._omega,
                             hip_start, dcm_start, (rows.free_knots[0], rows.free_knots[-1]))
        replanned = WalkingReference.__new__(WalkingReference)
        replanned._params = self._params
        replanned._omega = self._omega
        replanned._footsteps = tuple(footsteps)
        replanned._step_timings = list(timings)
        replanned._t_start = self._t_start
        replanned._revision = self._revision + 1
        cut_knot = int(np.searchsorted(self._lipm.times, lift_off))
        replanned._lipm = PiecewiseLipm.concatenate(self._lipm, cut_knot, tail)
        replanned._set_phases(rows, cut, self)
        return replanned

    def _set_phases(self, rows: PhaseRows, keep: int,
                    previous: Optional['WalkingReference'] = None) -> None:
        """Store the phases: the first keep of previous, then the planned rows."""
        self._phases = PhaseTable.from_rows(
            rows, keep, previous._phases if previous is not None else None)
        self._table = ReferenceTable(self._lipm, self._phases)
