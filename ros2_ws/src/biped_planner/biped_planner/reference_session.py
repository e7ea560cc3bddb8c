"""The walking reference of the current walk, kept consistent with plans and the state machine.

The walking state machine owns the timeline: a walk starts (Initialize) at walk_start, and its
reference is the WalkingReference of the walk's footstep plan with t_start = walk_start, so the
reference's initial shift, single and double supports line up with the state machine's phases
(given the same durations). A plan that changes while walking (teleop extension, a stop's closing
step) is spliced in with WalkingReference.extend from its first changed footstep. An extension
that names when it applies (the planner's own, from the phase that asked for it) waits for that
time (the planner's plan after a step adjustment too, from the adjustment's time; changes
wait in time order), so the splice does not depend on when the message arrived. Between walks
the last reference holds its final standing pose. With an online step adjuster, the step under
way moves (location and touchdown) when the measured DCM asks for it: the session's reference is
then the adjusted one, and the adjustment is returned for the rest of the graph to follow. With
a landing hold, a swing foot late to meet the ground holds its single support the same way.
"""
from dataclasses import dataclass
import math
from typing import List, Optional, Sequence, Tuple

from biped_planner.errors import ConfigError, InputError
from biped_planner.footsteps import Footstep
from biped_planner.landing_hold import EARLY, LandingHold
from biped_planner.plan_adjustment import swing_step_at
from biped_planner.reference_params import ReferenceParams
from biped_planner.reference_window import joined_at, ReferenceWindow
from biped_planner.sides import LEFT
from biped_planner.standing_reference import standing_window
from biped_planner.step_adjuster import OnlineStepAdjuster
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import WalkingReference


def check_footsteps(footsteps: Sequence[Footstep], workspace: float, max_step: float) -> None:
    """A plan the robot can walk: at least the two initial feet, every footstep inside the
    workspace, and no footstep farther than max_step from the one before it.

    :param workspace: largest |x| and |y| of a footstep (m)
    :param max_step: largest distance between consecutive footsteps (m)
    :raises ConfigError: naming the first footstep that breaks a rule
    """
    if len(footsteps) < 2:
        raise ConfigError(f'a plan needs at least the 2 initial feet, got {len(footsteps)}')
    for index, step in enumerate(footsteps):
        if max(abs(step.x), abs(step.y)) > workspace:
            raise ConfigError(f'footstep {index} at ({step.x:.4g}, {step.y:.4g}) is outside '
                              f'the workspace (|x|, |y| <= {workspace} m)')
        if index:
            before = footsteps[index - 1]
            distance = math.hypot(step.x - before.x, step.y - before.y)
            if distance > max_step:
                raise ConfigError(f'footstep {index} is {distance:.3f} m from footstep '
                                  f'{index - 1} (> {max_step} m)')


def check_plan_start(footsteps: Sequence[Footstep], feet: Sequence[Footstep],
                     max_offset: float) -> None:
    """A new plan starts where the feet stand: its two initial feet are within max_offset of
    the feet of the same side (a reference from elsewhere would jump the feet there at once).

    :param feet: the standing feet (any order, one per side)
    :raises ConfigError: naming the foot and how far off it starts
    """
    standing = {foot.side: foot for foot in feet}
    for index, start in enumerate(footsteps[:2]):
        foot = standing.get(start.side)
        if foot is None:
            continue
        offset = math.hypot(start.x - foot.x, start.y - foot.y)
        if offset > max_offset:
            side = 'left' if start.side == LEFT else 'right'
            raise ConfigError(f'its initial footstep {index} ({side} foot) is {offset:.3f} m '
                              f'from where that foot stands (> {max_offset} m): a plan starts '
                              'from the feet the robot stands on')


WALK_NOTICE = 1.0  # s: a scheduled walk enters the references this long before its start
MAX_ESTIMATE_OFFSET = 0.5  # m: a COM estimate farther from the plan's is not the walking robot's
# AppliedAdjustment.kind: the step adjuster moved the step, a late landing's hold retimed it,
# or an early landing ended its single support
KIND_MOVED = 'moved'
KIND_HELD = 'held'
KIND_EARLY = 'early'


@dataclass(frozen=True)
class AppliedAdjustment:
    """A step the adjuster moved: what the planner and the state machine must follow.

    :param plan_id: the walked plan
    :param revision: adjustments of this walk so far
    :param step_index: the step under way (it lands footsteps[step_index + 2])
    :param touchdown: its adjusted touchdown time (s)
    :param planned_touchdown: its touchdown before the adjustment (s)
    :param footsteps: the whole adjusted footstep list
    :param dcm_error: (x, y) estimated DCM minus the plan's at the time (m), what moved it
    :param kind: KIND_MOVED (the step adjuster), KIND_HELD (a late landing's hold: the
        touchdown moved, the footsteps did not) or KIND_EARLY (an early landing: the same)
    """

    plan_id: int
    revision: int
    step_index: int
    touchdown: float
    planned_touchdown: float
    footsteps: Tuple[Footstep, ...]
    dcm_error: Tuple[float, float] = (0.0, 0.0)
    kind: str = KIND_MOVED


@dataclass(frozen=True)
class _Plan:
    plan_id: int
    footsteps: Tuple[Footstep, ...]
    timing: StepTiming


class ReferenceSession:
    """Builds and updates the reference of the current walk."""

    def __init__(self, params: ReferenceParams,
                 adjuster: Optional[OnlineStepAdjuster] = None,
                 landing_hold: Optional[LandingHold] = None) -> None:
        """:param adjuster: the online step adjuster, None (or disabled) to walk plans as
            they are
        :param landing_hold: waits for late landings, None (or disabled) to keep the plan's
            timing"""
        self._params = params
        self._adjuster = adjuster if adjuster is not None and adjuster.params.enabled else None
        self._landing_hold = landing_hold if landing_hold is not None else LandingHold()
        self._walk_holds = 0
        self._adjustments = 0
        self._walk_adjustments = 0
        self._plan: Optional[_Plan] = None
        self._reference: Optional[WalkingReference] = None
        self._reference_plan_id: Optional[int] = None
        self._walk_start: Optional[float] = None
        self._last_walked_plan_id: Optional[int] = None
        # (when, plan) of the walked plan's changes not yet spliced in, oldest first
        self._changes_due: List[Tuple[float, _Plan]] = []
        # (index, footstep) of the adjuster's newest landing: a plan of the planner without it
        # was made before that move and would undo it
        self._adjusted: Optional[Tuple[int, Footstep]] = None

    @property
    def reference(self) -> Optional[WalkingReference]:
        return self._reference

    @property
    def plan_timing(self) -> Optional[StepTiming]:
        """The timing of the newest plan set (None: no plan)."""
        return self._plan.timing if self._plan is not None else None

    @property
    def plan_id(self) -> int:
        return self._reference_plan_id or 0

    @property
    def plan_revision(self) -> int:
        """Revision of the walked reference: one more at every extension or step adjustment."""
        return self._reference.revision if self._reference is not None else 0

    @property
    def adjustments(self) -> int:
        """Steps the online adjuster moved in this session (every walk)."""
        return self._adjustments

    @property
    def walk_adjustments(self) -> int:
        """Steps the online adjuster moved in the walk under way (0 while standing)."""
        return self._walk_adjustments

    def adjust(self, t: float, com: Sequence[float], dcm: Sequence[float],
               zmp: Optional[Sequence[float]] = None) -> Optional[AppliedAdjustment]:
        """Let the online step adjuster answer the balance estimated at t.

        :param t: time of the estimate (s)
        :param com: (2,) estimated horizontal centre of mass (m)
        :param dcm: (2,) estimated DCM (m)
        :param zmp: (2,) measured ZMP (m) or None
        :return: the adjustment when the step under way moved, else None (no adjuster, no
            walk, not in single support, or the step stays)
        :raises InputError: for non-finite estimates, or a COM farther than
            MAX_ESTIMATE_OFFSET from the plan's
        """
        if self._adjuster is None or self._reference is None or self._walk_start is None or \
                t < self._walk_start:
            return None
        before = self._reference
        planned = before.lipm.state_at(t)[0]
        offset = math.hypot(float(com[0]) - planned[0], float(com[1]) - planned[1])
        if not offset <= MAX_ESTIMATE_OFFSET:
            raise InputError(f'the estimated COM {tuple(com)} is {offset:.3g} m from the plan\'s '
                             f'(> {MAX_ESTIMATE_OFFSET} m): not a robot walking it')
        output = self._adjuster.update(t, before, com, dcm, zmp)
        if not output.applied:
            return None
        self._reference = output.reference
        self._adjustments += 1
        self._walk_adjustments += 1
        swing = swing_step_at(before, t)
        index = swing.step + 2
        self._adjusted = (index, output.reference.footsteps[index])
        planned_dcm = swing.reference_dcm(t)
        return AppliedAdjustment(self.plan_id, output.revision + self._walk_holds, swing.step,
                                 swing.lift_off + output.adjustment.duration, swing.touchdown,
                                 tuple(output.reference.footsteps),
                                 (float(dcm[0]) - planned_dcm[0], float(dcm[1]) - planned_dcm[1]))

    @property
    def walk_holds(self) -> int:
        """Holds and resumes of late landings and early ends in the walk under way."""
        return self._walk_holds

    def hold_landing(self, t: float, modes: Sequence[str], depths: Sequence[float],
                     com: Optional[Sequence[float]] = None,
                     dcm: Optional[Sequence[float]] = None) -> Optional[AppliedAdjustment]:
        """Let the landing hold answer the swing landing reported at t.

        :param t: time of the report (s)
        :param modes: (left, right) landing states (biped_planner.landing_hold.LANDING_STATES)
        :param depths: (left, right) search depths below the planned landings (m)
        :param com: (2,) estimated COM to replan the hip from, None for the plan's
        :param dcm: (2,) estimated DCM, with com
        :return: the hold or resume (kind KIND_HELD) or early end (KIND_EARLY), for the graph
            to follow, else None
        :raises InputError: for modes or depths that are not two valid values (LandingHold)
        """
        walking = self._walk_start is not None and t >= self._walk_start
        change = self._landing_hold.update(t, self._reference if walking else None, modes,
                                           depths, com, dcm)
        if change is None:
            return None
        self._reference = change.reference
        self._walk_holds += 1
        return AppliedAdjustment(self.plan_id, self._walk_adjustments + self._walk_holds,
                                 change.step, change.touchdown, change.planned_touchdown,
                                 tuple(change.reference.footsteps),
                                 kind=KIND_EARLY if change.kind == EARLY else KIND_HELD)

    def adjust_step(self, t_now: float, landings: Sequence[Footstep], touchdown: float,
                    hip: Optional[Sequence[float]] = None,
                    dcm: Optional[Sequence[float]] = None) -> None:
        """The step adjuster moved the step under way (WalkingReference.adjust_step).

        :raises ConfigError: when no walk is under way or the adjustment cannot be used; the
            current reference is kept
        """
        if self._reference is None or self._walk_start is None:
            raise ConfigError('no walk under way to adjust')
        self._reference = self._reference.adjust_step(t_now, landings, touchdown, hip, dcm)

    def set_plan(self, plan_id: int, footsteps: Sequence[Footstep], timing: StepTiming,
                 t_now: float, apply_at: Optional[float] = None) -> str:
        """A footstep plan arrived.

        :param t_now: the latest time whose reference may already be out (s)
        :param apply_at: when a change of the walked plan (the planner's extension, or its
            plan after a step adjustment) applies (s): the splice waits for the first window at
            or after it (apply_due) instead of t_now, so the reference is the same whenever the
            plan arrived before then; changes wait in the order of their times. None or a time
            not after t_now: applied at t_now, and the waiting changes are dropped
        A change of the walked plan without the adjuster's newest landing (the planner made it
        before it learnt of that move) is dropped, here and when its time comes: spliced in, it
        would undo the move; the planner's plan after the move follows.

        :return: what was done ('stored', 'built', 'extended', 'unchanged', 'queued',
            'superseded')
        :raises ConfigError: when the plan cannot be used (malformed, or it changes steps that
            have already started); the current reference is kept
        """
        if self._walk_start is not None and plan_id == self._reference_plan_id and \
                not self._has_newest_adjustment(footsteps):
            return 'superseded'
        self._plan = _Plan(plan_id, tuple(footsteps), timing)
        if self._walk_start is not None and plan_id == self._reference_plan_id and \
                apply_at is not None and apply_at > t_now:
            self._changes_due.append((float(apply_at), self._plan))
            self._changes_due.sort(key=lambda change: change[0])
            return 'queued'
        self._changes_due = []  # a plan is the whole list: it replaces the waiting changes
        if self._walk_start is not None and self._reference_plan_id is None:
            self._build()
            return 'built'
        if self._walk_start is not None and plan_id == self._reference_plan_id:
            return self._splice(self._plan.footsteps, timing, t_now)
        return 'stored'

    def apply_due(self, t: float) -> Optional[str]:
        """Splice the waiting plan changes whose times came, oldest first (before the window of
        t is taken).

        :return: what the last splice did ('extended', 'unchanged'), None when nothing was due
        :raises ConfigError: when a change no longer fits the reference (dropped; later ones
            wait for the next call)
        """
        done = None
        while self._changes_due and self._changes_due[0][0] <= t:
            due, plan = self._changes_due.pop(0)
            if self._walk_start is None or plan.plan_id != self._reference_plan_id or \
                    not self._has_newest_adjustment(plan.footsteps):
                continue
            done = self._splice(plan.footsteps, plan.timing, due)
        return done

    def start_walk(self, walk_start: float) -> bool:
        """The state machine started a walk at walk_start (idempotent).

        :return: whether a reference was built for it (False: waiting for its plan)
        """
        if walk_start == self._walk_start:
            return self._reference_plan_id is not None
        self._walk_start = walk_start
        self._reference_plan_id = None
        self._changes_due, self._adjusted = [], None
        self._walk_adjustments = self._walk_holds = 0
        if self._plan is not None and self._plan.plan_id != self._last_walked_plan_id:
            self._build()
            return True
        return False

    def end_walk(self) -> None:
        """The robot stands again; the reference keeps holding its final pose."""
        self._walk_start = None
        self._changes_due, self._adjusted = [], None
        self._walk_adjustments = self._walk_holds = 0

    def window(self, t: float, n: int, dt: float,
               standing_feet: Optional[Tuple[Footstep, Footstep]]) -> Optional[ReferenceWindow]:
        """References for n samples from t: the walk's, or standing on standing_feet.

        Before a walk's start (a start_time ahead of the clock) the samples are the standing
        ones, and the walk shows in the window from WALK_NOTICE before its start on, whenever
        its plan and its walking_state arrived: what the robot tracks does not depend on those
        arrival times.

        :return: the window, or None when there is neither a reference nor standing feet
        """
        if self._reference is not None:
            if standing_feet is None or self._walk_start is None or t >= self._walk_start:
                return self._reference.sample(t, n, dt)
            standing = standing_window(*standing_feet, self._params, t, n, dt)
            if t < self._walk_start - WALK_NOTICE:
                return standing
            return joined_at(standing, self._reference.sample(t, n, dt), self._walk_start)
        if standing_feet is None:
            return None
        return standing_window(*standing_feet, self._params, t, n, dt)

    def _build(self) -> None:
        plan = self._plan
        self._reference = WalkingReference(plan.footsteps, plan.timing, self._params,
                                           t_start=self._walk_start)
        self._reference_plan_id = plan.plan_id
        self._last_walked_plan_id = plan.plan_id
        if self._adjuster is not None:
            self._adjuster.reset()

    def _has_newest_adjustment(self, footsteps: Sequence[Footstep]) -> bool:
        if self._adjusted is None:
            return True
        index, landing = self._adjusted
        return len(footsteps) > index and footsteps[index] == landing

    def _splice(self, footsteps: Tuple[Footstep, ...], timing: StepTiming, t_now: float) -> str:
        old = self._reference.footsteps
        first_change = next((i for i, (a, b) in enumerate(zip(old, footsteps)) if a != b),
                            min(len(old), len(footsteps)))
        if first_change == len(old) == len(footsteps):
            return 'unchanged'
        if first_change < 2:
            raise ConfigError('a plan update may not move the initial feet')
        self._reference = self._reference.extend(footsteps[first_change:], t_now, timing,
                                                 replace_from=first_change)
        return 'extended'

