"""Where the closed-loop runner gets its reference windows: a fixed plan or live commands.

:class:`PlannedWalk` samples a WalkingReference of a footstep plan. :class:`CommandedWalk`
plans footsteps from omnidirectional step commands (OmnidirectionalStepper, the paper's
tele-operation mode), appended with WalkingReference.extend so that the plan stays a fixed
number of steps ahead of the step being walked: the planner's advice is one or two, which keeps
the splice correction of the hip small because the footsteps that change are at least a step
after the splice.
"""
from typing import Callable

from biped_planner.walking_reference import WalkingReference

from biped_sim.errors import ConfigError


class PlannedWalk:
    """Reference source of a fixed plan: a WalkingReference (duck typed: sample, t_end).

    :param reference: the walking reference
    """

    def __init__(self, reference) -> None:
        if not hasattr(reference, 'sample'):
            raise ConfigError(f'reference must have sample(t0, n, dt), got '
                              f'{type(reference).__name__}')
        self.reference = reference

    def window(self, t: float, n: int, dt: float):
        """The reference window of n samples from t.

        :param t: first sample time (s)
        :param n: number of samples
        :param dt: sample period (s)
        :return: a ReferenceWindow
        """
        return self.reference.sample(t, n, dt)


class CommandedWalk:
    """Reference source of omnidirectional commands (the paper's tele-operation mode).

    At every window request the plan is extended, if needed, so that at least steps_ahead
    footsteps beyond the one being walked are planned with the command of that time (the
    stepper's lag filter smooths the command changes, one update per step). With a zero command
    the robot walks in place.

    :param stepper: an OmnidirectionalStepper (biped_planner) at the start pose
    :param timing: StepTiming of every step
    :param reference_params: ReferenceParams of the WalkingReference
    :param command: function of the time (s) returning the StepCommand to walk
    :param reference_factory: the reference class, WalkingReference by default
    :param steps_ahead: planned steps beyond the current one, [1, 10]
    :param t_start: time the walk starts from standing (s)
    """

    def __init__(self, stepper, timing, reference_params, command: Callable,
                 reference_factory=WalkingReference, steps_ahead: int = 2,
                 t_start: float = 0.0) -> None:
        if not (isinstance(steps_ahead, int) and 1 <= steps_ahead <= 10):
            raise ConfigError(f'steps_ahead must be an integer in [1, 10], got {steps_ahead!r}')
        if not callable(command):
            raise ConfigError('command must be a function of the time returning a StepCommand')
        self._stepper = stepper
        self._timing = timing
        self._command = command
        self._steps_ahead = steps_ahead
        step_time = timing.single_support + timing.double_support
        self._step_time = step_time
        for _ in range(steps_ahead + 1):
            stepper.next_footstep(command(t_start), step_time)
        self.reference = reference_factory(stepper.footsteps, timing, reference_params,
                                           t_start=t_start)

    def window(self, t: float, n: int, dt: float):
        """The reference window of n samples from t, after extending the plan if needed.

        :param t: first sample time (s)
        :param n: number of samples
        :param dt: sample period (s)
        :return: a ReferenceWindow
        """
        current = int(self.reference.sample(t, 1, dt).step_index[0])
        planned_ahead = self.reference.n_steps - max(current, 1)
        if planned_ahead < self._steps_ahead:
            landings = [self._stepper.next_footstep(self._command(t), self._step_time)
                        for _ in range(self._steps_ahead - planned_ahead)]
            self.reference = self.reference.extend(landings, t, self._timing)
        return self.reference.sample(t, n, dt)
