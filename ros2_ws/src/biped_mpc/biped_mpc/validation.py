"""Checks shared by the biped_mpc modules: arrays at the inputs, numbers in the parameters.

Parameter dataclasses declare their ranges with biped_planner.parameter_fields.parameter() and
call validate_fields; what a field spec cannot say (a tuple's length, an integer, a bound that
depends on another field) is checked with the helpers here.
"""
import math

import numpy as np

from biped_mpc.errors import ConfigError, InputError

_SMALL = 16  # arrays up to this size are checked on Python floats


def finite_array(name: str, value, shape: tuple) -> np.ndarray:
    """:return: value as a float array of the given shape.

    :raises InputError: naming the argument, for a wrong shape or a NaN / inf entry
    """
    array = np.asarray(value, dtype=float)
    if array.shape != shape:
        raise InputError(f'{name} must have shape {shape}, got {array.shape}')
    # the controller checks a few dozen small arrays a cycle: on Python floats the check
    # costs a fifth of numpy's isfinite and reduction
    finite = (all(map(math.isfinite, array.ravel().tolist())) if array.size <= _SMALL
              else np.isfinite(array).all())
    if not finite:
        raise InputError(f'{name} must be finite, got {array.tolist()}')
    return array


def finite_vector(name: str, value, size: int, allow_nan: bool = False) -> np.ndarray:
    """:return: value flattened to a (size,) float array.

    :param allow_nan: NaN entries pass (a measurement that is missing); inf never does
    :raises InputError: naming the argument, for a wrong size or a non-finite entry
    """
    array = np.array(value, dtype=float).reshape(-1) if value is not None else None
    if array is None or array.shape != (size,):
        raise InputError(f'{name} must have {size} numbers, got {value!r}')
    bad = np.isinf(array) if allow_nan else ~np.isfinite(array)
    if np.any(bad):
        raise InputError(f'{name} = {array.tolist()} must be finite'
                         + (' (NaN allowed)' if allow_nan else ''))
    return array


def number_tuple(name: str, value, size: int, error=ConfigError) -> tuple:
    """:return: value as a tuple of size finite floats (the ranges are the field spec's).

    :param error: the exception type to raise (the calling package's ConfigError)
    :raises error: naming the parameter, for a wrong length or a non-finite entry
    """
    try:
        array = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        array = None
    if array is None or array.shape != (size,) or not np.all(np.isfinite(array)):
        raise error(f'{name} must be {size} finite numbers, got {value!r}')
    return tuple(float(v) for v in array)


def check_integer(name: str, value, low: int, high: float = math.inf) -> None:
    """:raises ConfigError: naming the parameter, unless value is an int in [low, high]"""
    if not isinstance(value, int) or isinstance(value, bool) or not low <= value <= high:
        raise ConfigError(f'{name} must be an integer in [{low}, {high}], got {value!r}')


def check_positive(name: str, value, high: float = math.inf) -> None:
    """:raises ConfigError: naming the parameter, unless value is a finite number in (0, high]"""
    if (isinstance(value, bool) or not isinstance(value, (int, float))
            or not math.isfinite(value) or not 0.0 < value <= high):
        raise ConfigError(f'{name} = {value!r} must be a finite number in (0, {high}]')


def check_period(dt) -> None:
    """:raises InputError: unless dt, a control cycle's period, is a finite number > 0 (s)"""
    if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0.0):
        raise InputError(f'dt must be a finite number > 0 s, got {dt!r}')


def check_time_constant(value) -> None:
    """:raises ConfigError: unless value is a finite number >= 0 (s; 0: no lag)"""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or \
            not math.isfinite(value) or value < 0.0:
        raise ConfigError(f'time_constant must be a finite number >= 0 s, got {value!r}')


def validated_pose(name: str, position, rotation) -> tuple:
    """Return a pose as float arrays (position (3,), rotation (3, 3)).

    :param name: what the pose is, for the error message.
    :raises InputError: for wrong shapes or NaN/inf.
    """
    p = np.asarray(position, dtype=float)
    r = np.asarray(rotation, dtype=float)
    if p.shape != (3,) or r.shape != (3, 3):
        raise InputError('%s: position shape %s and rotation shape %s, expected (3,) and (3, 3)'
                         % (name, p.shape, r.shape))
    if not (np.all(np.isfinite(p)) and np.all(np.isfinite(r))):
        raise InputError('%s pose has NaN or inf: position %r' % (name, position))
    return p, r
