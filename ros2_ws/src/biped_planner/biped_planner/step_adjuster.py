"""Online step adjustment: each control cycle, the next footstep from the DCM and the plan.

Wraps the QP of biped_planner.step_adjustment around a WalkingReference: it reads the
step under way (biped_planner.plan_adjustment), solves the QP against the step as first
planned, and when the answer moves the landing or its time beyond a threshold (a bounded
number of times per step) it returns a reference replanned mid-step
(WalkingReference.adjust_step) with a higher plan revision.
Pure numpy, time is an argument.
"""
from dataclasses import dataclass
import math
from typing import Optional, Sequence

import numpy as np

from biped_planner.errors import ConfigError, InputError
from biped_planner.input_checks import check_finite_array
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.plan_adjustment import moved_landings, swing_step_at
from biped_planner.step_adjustment import (STATUS_BLOCKED, STATUS_FAILED, StepAdjuster,
                                           StepAdjustment, StepAdjustmentParams)


def _cancelling_shift(error: float, growth: float, limit: float) -> float:
    """The stance ZMP shift that brings a DCM error e back to the reference's at touchdown,
    e a / (a - 1) with a = growth = exp(omega T_remaining), clipped to +-limit (m)."""
    return min(max(error * growth / (growth - 1.0), -limit), limit)


@dataclass(frozen=True)
class OnlineStepAdjusterParams:
    """When the step adjuster acts and how it hands its answer to the reference."""

    enabled: bool = parameter(True, 'adjust the next footstep online; off walks the plan as '
                              "it is (the paper's framework)")
    ankle_authority: float = parameter(
        0.5, 'fraction of the ZMP box half size the prediction lets the ankle use against a DCM '
        'error before the step moves (1)', low=0.0, high=1.0)
    dcm_deadband: float = parameter(
        0.05, "DCM error from the reference's, per axis, that is left to the controller: the "
        'error beyond it is what the step answers (m)', low=0.0, high=1.0)
    location_threshold: float = parameter(
        0.02, 'change of the landing from the current plan that triggers a replan (m)',
        low=0.0, high=1.0)
    timing_threshold: float = parameter(
        0.02, 'change of the touchdown time from the current plan that triggers a replan (s)',
        low=0.0, high=1.0)
    freeze_time: float = parameter(
        0.2, 'the landing is no longer changed this close to the planned touchdown: a swing '
        'leg cannot follow a late change (s)',
        low=0.0, high=1.0)
    max_replans_per_step: int = parameter(
        2, 'replans of one step at most: the first answers the push, a second corrects what '
        'the DCM did after it; more only chase the estimate', low=1, high=1000)
    replan_interval: float = parameter(
        0.04, 'shortest time between two replans of a step: the DCM estimate settles after a '
        'replan before the next is considered (s)', low=0.0, high=1.0)
    capture_gate: bool = parameter(
        False, 'move the step only when the stance ankle, using its whole ZMP box, cannot '
        'bring the DCM at touchdown within capture_tolerance of the plan (an uneven floor '
        "keeps the estimate centimetres off the reference without a threat to balance)")
    capture_tolerance: float = parameter(
        0.03, 'with capture_gate: the DCM at touchdown may miss the plan by this much, per '
        "axis, and the next stance ankle catches it (m)", low=0.0, high=1.0)
    replan_hip_from_estimate: bool = parameter(
        True, "replan the hip from the estimated COM and DCM (else from the reference's own)")
    replan_dcm_from_footsteps: bool = parameter(
        False, "the replanned reference's DCM is the one the moved steps ask for, its hip "
        "position kept (else the ZMP of the next double support is bent to join the state)")

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


@dataclass(frozen=True)
class StepAdjusterOutput:
    """One cycle of the online step adjuster.

    :param reference: the reference to walk (the input one when nothing changed)
    :param revision: plan revisions the adjuster has made so far
    :param applied: this cycle replanned the reference
    :param adjustment: the QP's answer, None when it did not run (off, no swing, frozen)
    """

    reference: object
    revision: int
    applied: bool
    adjustment: Optional[StepAdjustment] = None


class OnlineStepAdjuster:
    """The next step's location and timing from the estimated DCM, each control cycle.

    The QP (StepAdjuster) predicts the DCM at touchdown with the ZMP held until then. Held at
    the stance centre, the centimetres by which the estimated DCM strays from the reference's
    without any push (estimate noise and the MPC's loose tracking of the COM) grow by
    exp(omega T), 34 times over the paper's 0.8 s single support, and would move every step.
    Two things keep them from it: the error e = xi - xi_ref is first shrunk by dcm_deadband
    per axis (the MPC's feedback answers small errors); and the ankle can hold the ZMP anywhere
    in the foot, which cancels an error up to about the foot's half size, so the predicted ZMP
    is the reference ZMP moved by the shift that would cancel the shrunk error,
    e a / (a - 1) with a = exp(omega T_remaining), clipped to ankle_authority of the ZMP box.
    The step moves only for what the ankle cannot do. With capture_gate the QP does not even
    run until the ankle's whole box (not its ankle_authority share) misses the plan's DCM at
    touchdown by more than capture_tolerance: on uneven ground the estimate strays without a
    threat to balance.

    The QP's nominal is the step as first planned (landing, duration, and the reference's DCM
    at touchdown minus the landing as the offset), kept until that step lands, so that repeated
    replans do not drift. The QP runs every cycle of a single support (about 40 us); the
    reference is replanned (milliseconds) only when its answer leaves the current plan by more
    than the thresholds, at most max_replans_per_step times per step and replan_interval
    apart: a push is answered at once and decisively, and the answer is not chased cycle by
    cycle as the estimate moves. A replan moves the landing and carries the later landings
    with it. The step under way is read from the plan once (biped_planner.plan_adjustment)
    and kept while the reference is the one this adjuster last saw.

    :param params: when to act
    :param qp: the QP's model, weights and limits
    :param keep_out_boxes: (xmin, ymin, xmax, ymax) map obstacles grown by half the foot (m)
    """

    def __init__(self, params: OnlineStepAdjusterParams = OnlineStepAdjusterParams(),
                 qp: StepAdjustmentParams = StepAdjustmentParams(),
                 keep_out_boxes: Sequence[Sequence[float]] = ()) -> None:
        self.params = params
        self.qp = StepAdjuster(qp)
        self._omega = qp.omega
        self._boxes = [tuple(float(v) for v in box) for box in keep_out_boxes]
        self.reset()

    def reset(self) -> None:
        """Forget the nominal step and the revision count (a new walk)."""
        self.revision = 0
        self._nominal = None
        self._swing = None
        self._seen = None
        self._replans = 0
        self._last_replan = -math.inf

    def update(self, t: float, reference, com, dcm, zmp=None) -> StepAdjusterOutput:
        """Adjust the step under way for the COM and DCM estimated at t.

        :param t: time (s)
        :param reference: the WalkingReference being walked
        :param com: (2,) estimated horizontal centre of mass (m)
        :param dcm: (2,) estimated DCM, com + com velocity / omega (m)
        :param zmp: (2,) measured ZMP (m), or None (or NaN) to predict with the reference's
            moved by the ankle's share; a measured one sees a swing foot that has not yet
            unloaded, which holds the DCM where the stance foot alone would not
        :return: the reference to walk and what was done
        :raises InputError: for non-finite estimates
        """
        if not self.params.enabled:
            return StepAdjusterOutput(reference, self.revision, False)
        com = check_finite_array('com', com, (2,), InputError)
        dcm = check_finite_array('dcm', dcm, (2,), InputError)
        swing = self._swing_step(reference, t)
        if swing is None:
            self._nominal = None
            return StepAdjusterOutput(reference, self.revision, False)
        if self._nominal is None or self._nominal[0] != swing.step:
            self._nominal = (swing.step, swing.landing, swing.duration,
                             swing.dcm_at_touchdown - [swing.landing.x, swing.landing.y])
            self._replans = 0
            self._last_replan = -math.inf
        if t > swing.touchdown - self.params.freeze_time:
            return StepAdjusterOutput(reference, self.revision, False)
        if self.params.capture_gate and self._capturable(t, swing, dcm):
            return StepAdjusterOutput(reference, self.revision, False)
        measured_zmp = None
        if zmp is not None:
            zmp = np.asarray(zmp, dtype=float).reshape(-1)
            if zmp.shape == (2,) and np.all(np.isfinite(zmp)):
                measured_zmp = (float(zmp[0]), float(zmp[1]))
        result = self._solve(t, swing, dcm, measured_zmp)
        if result.status in (STATUS_FAILED, STATUS_BLOCKED) or not self._may_replan(t):
            return StepAdjusterOutput(reference, self.revision, False, result)
        moved = math.hypot(result.location[0] - swing.landing.x,
                           result.location[1] - swing.landing.y)
        retimed = abs(result.duration - swing.duration)
        if moved <= self.params.location_threshold and retimed <= self.params.timing_threshold:
            return StepAdjusterOutput(reference, self.revision, False, result)
        landings = moved_landings(reference.footsteps, swing.step + 2, result.location)
        state = (com, dcm) if self.params.replan_hip_from_estimate else (None, None)
        adjusted = reference.adjust_step(
            t, landings, swing.lift_off + result.duration, *state,
            dcm_from_footsteps=self.params.replan_dcm_from_footsteps)
        self.revision += 1
        self._replans += 1
        self._last_replan = t
        return StepAdjusterOutput(adjusted, self.revision, True, result)

    def _swing_step(self, reference, t: float):
        """The step under way, read from the plan only when the plan or the step changed."""
        swing = self._swing
        if reference is self._seen and swing is not None and \
                swing.lift_off <= t < swing.touchdown:
            return swing
        swing = swing_step_at(reference, t)
        self._swing, self._seen = swing, reference
        return swing

    def _may_replan(self, t: float) -> bool:
        return (self._replans < self.params.max_replans_per_step
                and t - self._last_replan >= self.params.replan_interval - 1e-9)

    def _capturable(self, t: float, swing, dcm: np.ndarray) -> bool:
        """Whether the planned step still catches the DCM: the stance ZMP held anywhere in its
        box, the DCM at touchdown misses the reference's by capture_tolerance at most."""
        reference_dcm = swing.reference_dcm(t)
        growth = math.exp(self._omega * (swing.touchdown - t))
        for axis in range(2):
            error = float(dcm[axis]) - reference_dcm[axis]
            shift = _cancelling_shift(error, growth, float(swing.zmp_half_size[axis]))
            # xi_td - xi_td_ref = (error - shift) growth + shift
            if abs((error - shift) * growth + shift) > self.params.capture_tolerance:
                return False
        return True

    def _solve(self, t: float, swing, dcm: np.ndarray, measured_zmp=None) -> StepAdjustment:
        """The QP for the DCM error beyond the deadband and what the ankle cannot take."""
        _, landing, duration, offset = self._nominal
        reference_dcm = swing.reference_dcm(t)
        params = self.params
        deadband = params.dcm_deadband
        growth = math.exp(self._omega * (swing.touchdown - t))
        errors, ankle = [], []
        for axis in range(2):
            error = float(dcm[axis]) - reference_dcm[axis]
            error = math.copysign(max(abs(error) - deadband, 0.0), error)
            limit = params.ankle_authority * float(swing.zmp_half_size[axis])
            errors.append(error)
            ankle.append(_cancelling_shift(error, growth, limit))
        stance = swing.stance
        held = ((float(swing.zmp[0]) + ankle[0], float(swing.zmp[1]) + ankle[1])
                if measured_zmp is None else measured_zmp)
        return self.qp.solve(t - swing.lift_off, (stance.x, stance.y, stance.yaw, stance.side),
                             (landing.x, landing.y), duration,
                             (reference_dcm[0] + errors[0], reference_dcm[1] + errors[1]),
                             held, nominal_offset=offset, keep_out_boxes=self._boxes)
