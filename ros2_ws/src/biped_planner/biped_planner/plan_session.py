"""The footstep plan a walking robot follows, kept up to date as commands arrive.

Three ways to walk (the paper's "Dynamic Planner" inputs): to a goal around obstacles (A* path,
then footsteps), by omnidirectional step commands (teleop, the paper's X, Y, alpha), and in place
(a zero command). Teleop plans are continuous: they are kept `lookahead` steps ahead of the step
the robot is taking, so a new command changes only steps that have not started, and the reference
can be extended smoothly. A stop replaces everything after the current step by one closing step
that puts the feet side by side. When a step adjuster moved a landing, the plan goes on from
where the foot lands: a goal walk is planned anew from there, a teleop walk steps on from it.

Step indices are those of the walking state machine: during single support of step k (0-based),
the swing foot is moving to footsteps[k + 2].
"""
from dataclasses import dataclass
import enum
from typing import List, Optional, Sequence, Tuple

from biped_planner.astar import AStarPlanner
from biped_planner.errors import InputError, PlanningError
from biped_planner.footstep_planner import FootstepPlanner
from biped_planner.footsteps import foot_beside, Footstep
from biped_planner.input_checks import check_integer
from biped_planner.omnidirectional_stepper import (OmnidirectionalStepper, StepCommand,
                                                   StepperParams)
from biped_planner.pose2d import Pose2D
from biped_planner.sides import LEFT, other_side


LOOKAHEAD_RANGE = (1, 10)  # teleop steps planned beyond the one being taken


class PlanMode(enum.IntEnum):
    NONE = 0
    GOTO = 1
    TELEOP = 2


@dataclass(frozen=True)
class PlanUpdate:
    """A plan to publish.

    :param plan_id: increases with every new walk's plan; a stop or a teleop extension keeps it
    :param footsteps: the full footstep list (initial feet, then landings)
    :param continuous: more steps will follow (teleop); False: the plan ends standing
    :param path: (K, 2) path the footsteps follow (empty for teleop)
    """

    plan_id: int
    footsteps: Tuple[Footstep, ...]
    continuous: bool
    path: Tuple[Tuple[float, float], ...] = ()


def closing_footstep(stance: Footstep, step_width: float) -> Footstep:
    """:return: the other foot placed beside the stance foot, with its heading."""
    return foot_beside(stance.x, stance.y, stance.yaw, other_side(stance.side), step_width)


class PlanSession:
    """Keeps the current footstep plan for goto, teleop and stop commands."""

    def __init__(self, planner: FootstepPlanner, stepper_params: StepperParams,
                 lookahead: int = 2, first_swing: int = LEFT) -> None:
        """:param lookahead: teleop steps planned beyond the one being taken, in
            LOOKAHEAD_RANGE."""
        check_integer('lookahead', lookahead, *LOOKAHEAD_RANGE)
        self._planner = planner
        self._stepper_params = stepper_params
        self._lookahead = lookahead
        self._first_swing = first_swing
        self._mode = PlanMode.NONE
        self._plan_id = 0
        self._footsteps: List[Footstep] = []
        self._stepper: Optional[OmnidirectionalStepper] = None
        self._command = StepCommand()
        self._step_time = 0.5
        self._continuous = False
        self._path: Tuple[Tuple[float, float], ...] = ()
        self._goal: Optional[Tuple[AStarPlanner, Pose2D]] = None
        # (footsteps kept, step width) of the walk's stop: its closing step, None: not stopping
        self._stop_end: Optional[Tuple[int, float]] = None

    @property
    def mode(self) -> PlanMode:
        return self._mode

    @property
    def plan_id(self) -> int:
        return self._plan_id

    def _update(self) -> PlanUpdate:
        return PlanUpdate(self._plan_id, tuple(self._footsteps), self._continuous, self._path)

    def goto(self, astar: AStarPlanner, start: Pose2D, goal: Pose2D) -> PlanUpdate:
        """Plan a new walk to the goal.

        :raises PlanningError: (a subclass) when no plan exists; the session is unchanged
        """
        plan = self._planner.plan_on_map(astar, start, goal)
        self._plan_id += 1
        self._mode = PlanMode.GOTO
        self._stop_end = None
        self._footsteps = list(plan.footsteps)
        self._continuous = False
        self._path = tuple((float(x), float(y)) for x, y in plan.path)
        self._stepper = None
        self._goal = (astar, goal)
        return self._update()

    def adopt_adjustment(self, plan_id: int, step_index: int,
                         footsteps: Sequence[Footstep]) -> Optional[PlanUpdate]:
        """A step adjuster moved the landing of step step_index (and the later landings with
        it): plan on from where that foot lands.

        A goal walk is planned anew from the adjusted landing to its goal (the translated
        later landings would end the walk off the goal by the adjustment); when no path is
        found from there, the translated landings are kept. A teleop walk steps on from the
        adjusted footsteps; a stopping walk keeps them up to its last step and closes beside
        it (an adjustment of the plan before the stop, made before the stop was spliced in,
        has that plan's later steps).

        :param plan_id: the adjusted plan; another plan's adjustment changes nothing
        :param step_index: the adjusted step (it lands footsteps[step_index + 2])
        :param footsteps: the whole adjusted footstep list
        :return: the plan to publish, None for another plan's adjustment
        :raises InputError: when the adjustment changes footsteps before the adjusted landing
            or its step index is outside the plan
        """
        if plan_id != self._plan_id or not self._footsteps:
            return None
        footsteps = tuple(footsteps)
        check_integer('step_index', step_index, 0, max(0, len(footsteps) - 3),
                      error=InputError)
        landing = step_index + 2
        if footsteps[:landing] != tuple(self._footsteps[:landing]):
            raise InputError(f'the adjustment of step {step_index} changes footsteps before '
                             f'its landing (footsteps[{landing}])')
        self._footsteps = list(footsteps)
        if self._stop_end is not None and len(footsteps) > self._stop_end[0] + 1:
            keep, width = self._stop_end
            self._footsteps = self._footsteps[:keep] + [closing_footstep(footsteps[keep - 1],
                                                                         width)]
        elif self._mode == PlanMode.GOTO and self._goal is not None:
            astar, goal = self._goal
            try:
                plan = self._planner.plan_from_footsteps(astar, footsteps[:landing + 1], goal)
            except PlanningError:
                return self._update()
            self._footsteps = list(plan.footsteps)
            self._path = tuple((float(x), float(y)) for x, y in plan.path)
        elif self._mode == PlanMode.TELEOP and self._stepper is not None:
            self._stepper.adopt(self._footsteps)
        return self._update()

    def teleop(self, command: StepCommand, step_time: float, start: Pose2D,
               step_index: int = 0) -> PlanUpdate:
        """Walk by step commands: start a continuous plan, or change the command of one.

        The new command applies to the steps appended from now on.

        :raises InputError: for a step index beyond the current continuous plan
        """
        if self._mode == PlanMode.TELEOP and self._continuous:
            self._check_step(step_index)
        self._command = command
        self._step_time = step_time
        if self._mode != PlanMode.TELEOP or not self._continuous:
            self._plan_id += 1
            self._mode = PlanMode.TELEOP
            self._continuous = True
            self._stop_end = None
            self._path = ()
            self._stepper = OmnidirectionalStepper(start, self._stepper_params,
                                                   self._first_swing)
            self._footsteps = self._stepper.footsteps
            step_index = 0
        self._fill_to(step_index)
        return self._update()

    def set_command(self, command: StepCommand, step_time: float) -> bool:
        """Change the command of the steps a continuous teleop plan appends from now on, without
        appending any (the next on_step does).

        :return: whether a continuous teleop plan took it (False: no such plan, nothing done)
        """
        if self._mode != PlanMode.TELEOP or not self._continuous:
            return False
        self._command = command
        self._step_time = step_time
        return True

    def on_step(self, step_index: int) -> Optional[PlanUpdate]:
        """The robot started step step_index: keep a teleop plan far enough ahead.

        :return: the extended plan, or None if nothing changed
        """
        if self._mode != PlanMode.TELEOP or not self._continuous:
            return None
        self._check_step(step_index)
        count = len(self._footsteps)
        self._fill_to(step_index)
        return self._update() if len(self._footsteps) != count else None

    def _check_step(self, step_index: int) -> None:
        """A step the robot can be taking: never beyond the end of the plan it walks (the
        plan always reaches past the step being taken, so a larger index is not the robot's;
        extending the plan up to it would never end for a huge one)."""
        check_integer('step_index', step_index, 0, max(0, len(self._footsteps) - 2),
                      error=InputError)

    def _fill_to(self, step_index: int) -> None:
        needed = step_index + 3 + self._lookahead
        while len(self._footsteps) < needed:
            self._stepper.next_footstep(self._command, self._step_time)
            self._footsteps = self._stepper.footsteps

    def stop(self, step_index: int, walking: bool) -> Optional[PlanUpdate]:
        """Finish the step being taken, then one closing step with the feet side by side.

        :param step_index: the last step taken before the closing one: the step being taken,
            or the next one when that is committed already (the caller knows when)
        :param walking: whether the robot is walking; standing robots need no plan change
        :return: the shortened plan, or None when there is nothing to stop
        """
        if self._mode == PlanMode.NONE or not self._footsteps:
            return None
        self._continuous = False
        if not walking:
            self._mode = PlanMode.NONE
            return None
        keep = min(len(self._footsteps), step_index + 3)
        kept = self._footsteps[:keep]
        last = kept[-1]
        width = self._stepper_params.step_width if self._mode == PlanMode.TELEOP else \
            self._planner.params.step_width
        already_closed = len(self._footsteps) == keep and self._mode == PlanMode.GOTO
        self._footsteps = kept if already_closed else kept + [closing_footstep(last, width)]
        self._stop_end = None if already_closed else (keep, width)
        self._mode = PlanMode.NONE
        return self._update()

    def walk_finished(self) -> None:
        """The robot stands again: the next command starts a new plan."""
        self._mode = PlanMode.NONE
        self._stop_end = None
        self._continuous = False
