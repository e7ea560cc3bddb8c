"""Turn the planner's reference window into the MPC's per-plane output references and bounds."""
from dataclasses import dataclass

import numpy as np

from biped_mpc.errors import InputError
from biped_mpc.linear_model import (
    N_OUTPUTS, N_PLANES, OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG, OUTPUT_ZMP)
from biped_mpc.mpc_params import LEG_OUTPUTS, LEG_OUTPUTS_ABSOLUTE, LEG_OUTPUTS_TORSO_RELATIVE

_REQUIRED = ('zmp', 'left_mass', 'right_mass', 'hip', 'zmp_min', 'zmp_max', 'left_landing_min',
             'left_landing_max', 'right_landing_min', 'right_landing_max')
_N_REFERENCES = 4  # the first four must be finite; the bounds may be infinite, never NaN


def outputs_from_window(window, leg_outputs: str = LEG_OUTPUTS_ABSOLUTE) -> tuple:
    """References and bounds of y = [left leg mass, right leg mass, ZMP] for both planes.

    The window is used by duck typing (biped_planner.walking_reference.ReferenceWindow: arrays
    of N samples). Sample it at the predicted times t + Ts, ..., t + Np Ts.

    * y_ref: left_mass, right_mass and zmp of the window.
    * ZMP bounds: zmp_min / zmp_max (the support polygon box, foot scaled by 0.9).
    * Leg bounds (eq. SwingConstraints, the reachable rectangle of the landing): the planner's
      landing box bounds the swing foot around its planned landing point; the leg mass is
      midway between the foot and the hip, so the box of the leg mass is
      (landing box + hip) / 2. It is applied at the touch-down sample of each swing in the
      window (the last sample at which that leg's landing box is finite, followed by one where
      it is not): during the rest of the swing the foot is far from its landing point by
      design, so the landing box does not apply there. Every other leg bound is +-inf. A swing
      still in progress at the end of the window gets its bound in a later cycle.

    With leg_outputs 'torso_relative' (biped_mpc.mpc_params.MpcParams.leg_outputs) the leg
    outputs are the leg masses minus half the hip: their references are half the planned feet
    and their landing bounds half the landing boxes.

    :param window: an object with the ReferenceWindow attributes (N samples)
    :param leg_outputs: 'absolute' or 'torso_relative'
    :return: (y_ref, y_min, y_max), each of shape (2, N, 3) (m), planes x then y
    :raises InputError: if an attribute is missing, has the wrong shape, a reference is not
        finite or a bound is NaN, or leg_outputs is unknown
    """
    if leg_outputs not in LEG_OUTPUTS:
        raise InputError(f'leg_outputs must be one of {LEG_OUTPUTS}, got {leg_outputs!r}')
    arrays = dict(zip(_REQUIRED, _window_arrays(window)))
    n = arrays['zmp'].shape[0]
    y_ref = np.empty((N_PLANES, n, N_OUTPUTS))
    y_ref[:, :, OUTPUT_LEFT_LEG] = arrays['left_mass'].T
    y_ref[:, :, OUTPUT_RIGHT_LEG] = arrays['right_mass'].T
    y_ref[:, :, OUTPUT_ZMP] = arrays['zmp'].T
    y_min = np.full((N_PLANES, n, N_OUTPUTS), -np.inf)
    y_max = np.full((N_PLANES, n, N_OUTPUTS), np.inf)
    y_min[:, :, OUTPUT_ZMP] = arrays['zmp_min'].T
    y_max[:, :, OUTPUT_ZMP] = arrays['zmp_max'].T
    hip = arrays['hip']
    for output, prefix in ((OUTPUT_LEFT_LEG, 'left'), (OUTPUT_RIGHT_LEG, 'right')):
        lower, upper = arrays[prefix + '_landing_min'], arrays[prefix + '_landing_max']
        swinging = np.isfinite(lower).all(axis=1) & np.isfinite(upper).all(axis=1)
        touchdown = np.flatnonzero(swinging[:-1] & ~swinging[1:])
        y_min[:, touchdown, output] = (0.5 * (lower[touchdown] + hip[touchdown])).T
        y_max[:, touchdown, output] = (0.5 * (upper[touchdown] + hip[touchdown])).T
    if leg_outputs == LEG_OUTPUTS_TORSO_RELATIVE:
        half_hip = 0.5 * hip.T[:, :, None]
        legs = [OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG]
        y_ref[:, :, legs] -= half_hip
        y_min[:, :, legs] -= half_hip
        y_max[:, :, legs] -= half_hip
    if not (y_min <= y_max).all():
        raise InputError('the window has a lower bound above its upper bound')
    return y_ref, y_min, y_max


def _window_arrays(window) -> np.ndarray:
    """The _REQUIRED attributes of a window as one (10, N, 2) array, checked.

    One stacked array and three checks on it: a window is sampled every control cycle, and
    the twenty checks of the arrays one by one cost more than the rest of the adapter.

    :raises InputError: as outputs_from_window says
    """
    try:
        stacked = np.array([getattr(window, name) for name in _REQUIRED], dtype=float)
    except (AttributeError, ValueError, TypeError):
        stacked = None
    if (stacked is None or stacked.ndim != 3 or stacked.shape[1] < 1
            or stacked.shape[2] != N_PLANES or not np.isfinite(stacked[:_N_REFERENCES]).all()
            or np.isnan(stacked[_N_REFERENCES:]).any()):
        _raise_window_error(window)
    return stacked


def _raise_window_error(window) -> None:
    """Name what is wrong with a window that failed _window_arrays's checks."""
    arrays = {}
    for name in _REQUIRED:
        if not hasattr(window, name):
            raise InputError(f'the reference window has no attribute {name!r}')
        try:
            arrays[name] = np.asarray(getattr(window, name), dtype=float)
        except (ValueError, TypeError) as error:
            raise InputError(f'window.{name} is not an array of numbers: {error}') from None
    n = arrays['zmp'].shape[0] if arrays['zmp'].ndim == 2 else -1
    for name, array in arrays.items():
        if array.shape != (n, N_PLANES) or n < 1:
            raise InputError(f'window.{name} must have shape (N, 2) with the N of window.zmp, '
                             f'got {array.shape}')
    for name in _REQUIRED[:_N_REFERENCES]:
        if not np.isfinite(arrays[name]).all():
            raise InputError(f'window.{name} must be finite')
    for name in _REQUIRED[_N_REFERENCES:]:
        if np.isnan(arrays[name]).any():
            raise InputError(f'window.{name} contains NaN')
    raise InputError('the reference window is malformed')


@dataclass(frozen=True)
class CycleReferences:
    """What one control cycle takes from a reference window sampled at t, t + Ts, ...

    :param y_ref: (2, Np, 3) output references of samples 1 .. Np (m)
    :param y_min: (2, Np, 3) lower output bounds of samples 1 .. Np (m)
    :param y_max: (2, Np, 3) upper output bounds of samples 1 .. Np (m)
    :param feet_next: (2, 4) left and right foot x, y, z (m) and yaw (rad) of sample 1
    :param support_now: support label (biped_planner.sides SUPPORT_*) of sample 0
    :param support_next: support label of sample 1
    """

    y_ref: np.ndarray
    y_min: np.ndarray
    y_max: np.ndarray
    feet_next: np.ndarray
    support_now: int
    support_next: int


def cycle_references(window, leg_outputs: str, n_predict: int) -> CycleReferences:
    """The MPC's references of samples 1 .. Np, and the support, feet and yaws of samples 0, 1.

    A window shorter than Np + 1 samples repeats its last sample.

    :param window: a reference window (duck typed ReferenceWindow) sampled at t, t + Ts, ...
    :param leg_outputs: 'absolute' or 'torso_relative'
    :param n_predict: the MPC's prediction horizon Np
    :return: the references of the cycle
    :raises InputError: for a malformed window (outputs_from_window's checks, fewer than 2
        samples, feet or yaws of the wrong shape, non-finite feet)
    """
    y_ref, y_min, y_max = outputs_from_window(window, leg_outputs)
    n = y_ref.shape[1]
    index = np.minimum(np.arange(1, n_predict + 1), n - 1)
    support = np.asarray(window.support)
    left_foot = np.asarray(window.left_foot, dtype=float)
    right_foot = np.asarray(window.right_foot, dtype=float)
    left_yaw = np.asarray(window.left_yaw, dtype=float)
    right_yaw = np.asarray(window.right_yaw, dtype=float)
    if n < 2 or support.shape[0] != n or left_foot.shape != (n, 3) \
            or right_foot.shape != (n, 3) or left_yaw.shape != (n,) \
            or right_yaw.shape != (n,):
        raise InputError('the reference window needs at least 2 samples of support, feet '
                         'and yaws')
    feet_next = np.array([[*left_foot[1], left_yaw[1]], [*right_foot[1], right_yaw[1]]])
    if not np.all(np.isfinite(feet_next)):
        raise InputError('the reference window has non-finite feet')
    return CycleReferences(y_ref[:, index], y_min[:, index], y_max[:, index], feet_next,
                           int(support[0]), int(support[1]))
