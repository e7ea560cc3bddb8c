"""Where the closed-loop runner gets its reference windows: a fixed plan or live commands.

:class:`PlannedWalk` samples a WalkingReference of a footstep plan; :class:`AdjustedWalk` does
too, after letting an online step adjuster (biped_planner.step_adjuster) move the step
under way from the robot's estimated DCM. :class:`CommandedWalk`
plans footsteps from omnidirectional step commands (OmnidirectionalStepper, the paper's
tele-operation mode), appended with WalkingReference.extend so that the plan stays a fixed
number of steps ahead of the step being walked: the planner's advice is one or two, which keeps
the splice correction of the hip small because the footsteps that change are at least a step
after the splice.
"""
import math
from typing import Callable, Optional

import numpy as np

from biped_mpc.balance.balance_loop import landing_report
from biped_planner.landing_hold import LandingHold
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


class AdjustedWalk:
    """Reference source of a plan that an online step adjuster may change at every cycle.

    Either the controller calls adjust(t, com, dcm) with its estimate of the cycle before it
    samples (no delay), or a loop that only sees the controller's output calls observe() after
    each cycle and the next window() adjusts with that estimate, its DCM carried over the
    period by the pendulum on the reference ZMP.

    :param reference: the WalkingReference of the plan
    :param adjuster: an OnlineStepAdjuster (update(t, reference, com, dcm) -> output with
        reference, revision, applied)
    """

    def __init__(self, reference, adjuster) -> None:
        if not hasattr(reference, 'adjust_step'):
            raise ConfigError(f'reference must be a WalkingReference, got '
                              f'{type(reference).__name__}')
        self.reference = reference
        self.adjuster = adjuster
        self.last = None
        self.history = []
        self._observed: Optional[tuple] = None

    @property
    def revision(self) -> int:
        """Plan revisions made by the adjuster so far."""
        return self.adjuster.revision

    def adjust(self, t: float, com, dcm, zmp=None):
        """Let the adjuster move the step under way for the estimate at t.

        :param t: time of the estimate (s)
        :param com: (2,) estimated horizontal centre of mass (m)
        :param dcm: (2,) estimated DCM (m)
        :param zmp: (2,) measured ZMP (m), None to let the adjuster predict it
        :return: the adjuster's output (applied: the reference changed)
        """
        output = self.adjuster.update(t, self.reference, com, dcm, zmp)
        self.reference = output.reference
        self.last = output
        if output.applied:
            self.history.append((float(t), output.adjustment))
        return output

    def observe(self, t: float, com, dcm) -> None:
        """Keep the estimate of time t for the next window."""
        self._observed = (float(t), np.asarray(com, dtype=float), np.asarray(dcm, dtype=float))

    def window(self, t: float, n: int, dt: float):
        """The reference window of n samples from t, after adjusting with the last estimate.

        :param t: first sample time (s)
        :param n: number of samples
        :param dt: sample period (s)
        :return: a ReferenceWindow
        """
        if self._observed is not None:
            t_seen, com, dcm = self._observed
            self._observed = None
            zmp = np.asarray(self.reference.sample(t_seen, 1, dt).zmp[0])
            growth = math.exp(self.reference.omega * (t - t_seen))
            dcm_now = zmp + (dcm - zmp) * growth
            # the convergent component 2 c - xi decays towards the ZMP as the DCM grows
            com_now = 0.5 * (dcm_now + zmp + (2.0 * com - dcm - zmp) / growth)
            self.adjust(t, com_now, dcm_now)
        return self.reference.sample(t, n, dt)


class HeldWalk:
    """Reference source of a plan that waits for late landings (biped_planner.landing_hold).

    The runner hands it each cycle's controller output (observe_output); the next window
    first lets the LandingHold answer the swing foot's landing state of that cycle, one period
    late as through the node graph, and replans from the plan's own hip.

    :param reference: the WalkingReference of the plan
    :param hold: a LandingHold
    """

    def __init__(self, reference, hold: LandingHold) -> None:
        if not hasattr(reference, 'hold_landing'):
            raise ConfigError(f'reference must be a WalkingReference, got '
                              f'{type(reference).__name__}')
        self.reference = reference
        self.hold = hold
        self.changes = []  # (t, LandingHoldChange) in order
        self._observed: Optional[tuple] = None

    def observe_output(self, t: float, output) -> None:
        """Keep the feet's landing report of the cycle at t (output.landing_modes and
        landing_depths)."""
        self._observed = (float(t), *landing_report(output.landing_modes,
                                                    output.landing_depths))

    def window(self, t: float, n: int, dt: float):
        """The reference window of n samples from t, after the hold answered the last state."""
        if self._observed is not None:
            t_seen, modes, depths = self._observed
            self._observed = None
            change = self.hold.update(t_seen, self.reference, modes, depths)
            if change is not None:
                self.reference = change.reference
                self.changes.append((t_seen, change))
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
