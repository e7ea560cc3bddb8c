"""The next step's location and timing chosen with the step after it in view (two steps).

The one-step QP (biped_planner.step_adjustment) asks the step under way to land the DCM at its
nominal offset. When a push drives the DCM towards the stance foot's outer side, that step
cannot help (it may not cross the stance foot) and the one-step answer is indifferent to what
matters: how soon the stance foot is free to step out, and how far the DCM will have run by
then. Looking one step further (the N-step idea of Khadiv et al. 2020, Sec. V) makes the
timing of the first step and the reach of the second part of one problem. Pure numpy, time is
an argument.
"""
import importlib
import math
from typing import Sequence

import numpy as np

from biped_planner.errors import InputError, SolverUnavailableError
from biped_planner.sides import LEFT, SIDES
from biped_planner.step_adjustment import (_floats, STATUS_FAILED, STATUS_OPTIMAL,
                                           STATUS_SATURATED, StepAdjustment, StepAdjustmentParams)

_DAQP_OPTIMAL = (1, 2)
_DAQP_EQUALITY = 5
_INFINITY = 1e9
_N = 7  # (d1x, d1y, tau1, d2x, d2y, beta2x, beta2y)
_BOUNDED = 5  # the first five variables have bounds, the offset is free
_BOUND_NAMES = (('reach_backward', 'reach_forward'), ('width_min', 'width_max'),
                ('time_min', 'time_max'), ('second_reach_backward', 'second_reach_forward'),
                ('second_width_min', 'second_width_max'))


class TwoStepAdjuster:
    """Step 1 (under way) and step 2 (the stance foot's next) against the DCM, each cycle.

    The ZMP p is held on the stance foot until step 1 lands at u1 after T1 (tau1 =
    exp(omega T1)); from then on, for the step time T2 of the next double and single support
    (tau2 = exp(omega T2), fixed: the problem stays linear), it is held at u1; step 2 lands
    at u2. The DCM then is xi2 = u1 + (xi1 - u1) tau2 with xi1 = p + (xi0 - p) tau1. In the
    stance foot's yaw frame R (d1 = R'(u1 - s), d2 = R'(u2 - u1), beta2 = R'(xi2 - u2)):

        min  w_u |d1 - d1_nom|^2 + w_tau (tau1 - tau1_nom)^2 + w_u |d2 - d2_nom|^2
             + w_b |beta2 - beta2_nom|^2
        s.t. tau2 d1 - tau2 R'(xi0 - p) tau1 + d2 + beta2 = tau2 R'(p - s)
             step 1's reach, width (towards its own side, no crossing) and timing bounds
             step 2's reach and width, from u1 towards the other side

    The nominal offset beta2_nom is the model's own for the reference's DCM and ZMP, so that
    an unpushed walk is the optimum and only the DCM's deviation is answered. Step 2 is not
    committed: it is solved again, as a step under way, once it lifts off.

    :param params: weights and limits (the one-step QP's; its keep-out boxes are not
        considered here)
    """

    def __init__(self, params: StepAdjustmentParams = StepAdjustmentParams()) -> None:
        try:
            self._solver = importlib.import_module(params.solver)
        except ImportError as error:
            raise SolverUnavailableError(f'the step adjuster needs the Python package '
                                         f'{params.solver!r}: pip install {params.solver}'
                                         ) from error
        self.params = params
        self._omega = params.omega
        u, tau, b = params.location_weight, params.timing_weight, params.offset_weight
        self._weights = np.array([u, u, tau, u, u, b, b])
        self._multiplier_tolerance = 1e-7 * float(self._weights.max())

    def solve(self, t_in_step: float, stance_foot: Sequence[float], nominal_next_step,
              nominal_duration: float, dcm, zmp, nominal_second_step,
              second_step_time: float, reference_dcm, reference_zmp) -> StepAdjustment:
        """Adjust the step under way for the DCM estimated now, the one after it in view.

        :param t_in_step: time since the swing foot lifted off (s), >= 0
        :param stance_foot: (x, y, yaw, side) of the stance ankle (m, m, rad, LEFT/RIGHT)
        :param nominal_next_step: planned touchdown of the swing ankle (2,), world (m)
        :param nominal_duration: planned step duration, lift-off to touchdown (s), > 0
        :param dcm: estimated DCM xi0 (2,), world (m)
        :param zmp: ZMP p held until touchdown (2,), world (m)
        :param nominal_second_step: planned touchdown of the stance foot's next step (2,),
            world (m)
        :param second_step_time: from step 1's touchdown to step 2's (double support and
            single support), s, > 0
        :param reference_dcm: the reference's DCM now (2,), world (m)
        :param reference_zmp: the reference's ZMP now (2,), world (m)
        :return: step 1 adjusted (its dcm_offset the predicted DCM at its touchdown minus
            its location); active_limits may name step 2's limits ('second_width_max', ...)
        :raises InputError: for wrong shapes, non-finite values or an unknown side
        """
        params, omega = self.params, self._omega
        x, y, yaw, side = _floats('stance_foot', stance_foot, 4)
        if side not in SIDES:
            raise InputError(f'stance_foot side must be one of {SIDES}, got {side!r}')
        if not math.isfinite(t_in_step) or t_in_step < 0.0:
            raise InputError(f't_in_step must be finite and >= 0, got {t_in_step!r}')
        for name, value in (('nominal_duration', nominal_duration),
                            ('second_step_time', second_step_time)):
            if not math.isfinite(value) or value <= 0.0:
                raise InputError(f'{name} must be finite and > 0, got {value!r}')
        first = _floats('nominal_next_step', nominal_next_step, 2)
        second = _floats('nominal_second_step', nominal_second_step, 2)
        xi, p = _floats('dcm', dcm, 2), _floats('zmp', zmp, 2)
        xi_ref, p_ref = _floats('reference_dcm', reference_dcm, 2), _floats('reference_zmp',
                                                                              reference_zmp, 2)
        rotation = np.array([[math.cos(yaw), -math.sin(yaw)], [math.sin(yaw), math.cos(yaw)]])
        stance = np.array([x, y])

        def local(vector):
            return rotation.T @ np.asarray(vector, dtype=float)

        d1_nominal = local(np.array(first) - stance)
        d2_nominal = local(np.array(second) - np.array(first))
        t_low = max(params.step_time_min - t_in_step, params.min_remaining_time)
        t_high = max(params.step_time_max - t_in_step, t_low)
        t_nominal = min(max(nominal_duration - t_in_step, t_low), t_high)
        tau1_nominal = math.exp(omega * t_nominal)
        tau2 = math.exp(omega * second_step_time)
        # the offset of the unpushed walk, by the same model: the nominal is the optimum
        beta2_nominal = (tau2 * local(np.array(p_ref) - stance)
                         + tau2 * local(np.array(xi_ref) - np.array(p_ref)) * tau1_nominal
                         - tau2 * d1_nominal - d2_nominal)
        sigma = 1.0 if side != LEFT else -1.0  # +1: step 1 is the left foot's
        first_widths = sorted((sigma * params.width_min, sigma * params.width_max))
        second_widths = sorted((-sigma * params.width_min, -sigma * params.width_max))
        lower = np.array([-params.reach_backward, first_widths[0], math.exp(omega * t_low),
                          -params.reach_backward, second_widths[0]])
        upper = np.array([params.reach_forward, first_widths[1], math.exp(omega * t_high),
                          params.reach_forward, second_widths[1]])
        target = np.concatenate([d1_nominal, [tau1_nominal], d2_nominal, beta2_nominal])
        spread = local(np.array(xi) - np.array(p))
        equality = np.zeros((2, _N))
        equality[0, [0, 2, 3, 5]] = (tau2, -tau2 * spread[0], 1.0, 1.0)
        equality[1, [1, 2, 4, 6]] = (tau2, -tau2 * spread[1], 1.0, 1.0)
        equality_rhs = tau2 * local(np.array(p) - stance)
        z, signs = self._qp(-self._weights * target, lower, upper, equality, equality_rhs)
        if z is None:
            return StepAdjustment(np.array(first), nominal_duration, nominal_duration - t_in_step,
                                  np.zeros(2), STATUS_FAILED, False)
        flips = (False, sigma < 0.0, False, False, sigma > 0.0)
        names = tuple(_BOUND_NAMES[i][int((sign > 0) != flips[i])]
                      for i, sign in enumerate(signs) if sign)
        location = stance + rotation @ z[:2]
        remaining = math.log(z[2]) / omega
        xi1 = np.array(p) + (np.array(xi) - np.array(p)) * z[2]
        tolerance = params.adjustment_tolerance
        adjusted = bool(np.hypot(*(location - np.array(first))) > tolerance
                        or abs(t_in_step + remaining - nominal_duration) > tolerance)
        return StepAdjustment(location, t_in_step + remaining, remaining, xi1 - location,
                              STATUS_SATURATED if names else STATUS_OPTIMAL, adjusted, names)

    def _qp(self, linear, lower, upper, equality, equality_rhs):
        """(z, signs of the binding bounds: +1 upper, -1 lower, 0 free) or (None, None)."""
        hessian = np.diag(self._weights)
        if self.params.solver == 'daqp':
            bounds_upper = np.concatenate([upper, equality_rhs])
            bounds_lower = np.concatenate([lower, equality_rhs])
            sense = np.array([0] * _BOUNDED + [_DAQP_EQUALITY] * 2, dtype=np.int32)
            rows = np.vstack([np.eye(_N)[:_BOUNDED], equality])
            z, _, exitflag, info = self._solver.solve(hessian, linear, rows, bounds_upper,
                                                      bounds_lower, sense)
            if exitflag not in _DAQP_OPTIMAL:
                return None, None
            multipliers = np.asarray(info['lam'])[:_BOUNDED]
            return np.asarray(z), [0.0 if abs(m) <= self._multiplier_tolerance
                                   else math.copysign(1.0, m) for m in multipliers]
        identity = np.eye(_N)[:_BOUNDED]
        constraints = np.vstack([equality, identity, -identity]).T.copy()
        rhs = np.concatenate([equality_rhs, lower, -upper])
        try:
            z, _, _, _, multipliers, _ = self._solver.solve_qp(hessian, -linear, constraints,
                                                               rhs, 2)
        except ValueError:
            return None, None
        binding = multipliers > self._multiplier_tolerance
        return z, [float(binding[2 + _BOUNDED + i]) - float(binding[2 + i])
                   for i in range(_BOUNDED)]

