"""Checks of the arguments that cross biped_planner's public functions.

Parameter dataclasses check themselves (biped_planner.parameter_fields); these helpers check the
other inputs at the library boundary: times, counts, feet sides, points, arrays and argument
types. Each raises the error type the caller names (ConfigError unless told), and its message
names the argument, its value and what is allowed.
"""
import math
import numbers
from typing import Optional, Tuple

import numpy as np

from biped_planner.errors import ConfigError
from biped_planner.sides import SIDES


def is_finite_number(value) -> bool:
    """Whether value is a real finite number (bools are not numbers)."""
    return not isinstance(value, bool) and isinstance(value, numbers.Real) and \
        math.isfinite(value)


def _allowed(low: Optional[float], high: Optional[float], low_open: bool) -> str:
    if high is None:
        return f'{">" if low_open else ">="} {low}'
    if low is None:
        return f'<= {high}'
    return f'in {"(" if low_open else "["}{low}, {high}]'


def check_number(name: str, value, low: Optional[float] = None, high: Optional[float] = None,
                 low_open: bool = False, unit: str = '', error=ConfigError) -> float:
    """A finite real number, optionally within [low, high] ((low, high] with low_open).

    :param name: the argument's name, for the message
    :param value: the value to check
    :param low: smallest allowed value (None: unbounded)
    :param high: largest allowed value (None: unbounded)
    :param low_open: low itself is not allowed
    :param unit: unit shown after the bounds, e.g. ' s'
    :param error: exception type to raise
    :return: the value as a float
    :raises error: if value is not a finite number or out of bounds
    """
    bounded = low is not None or high is not None
    allowed = f' {_allowed(low, high, low_open)}{unit}' if bounded else ''
    if not is_finite_number(value) or (low is not None and (
            value < low or (low_open and value == low))) or (high is not None and value > high):
        raise error(f'{name} must be a finite number{allowed}, got {value!r}')
    return float(value)


def check_integer(name: str, value, low: Optional[int] = None, high: Optional[int] = None,
                  error=ConfigError) -> int:
    """An integer (not a bool), optionally within [low, high].

    :return: the value as an int
    :raises error: if value is not an integer or out of bounds
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Integral) or (
            low is not None and value < low) or (high is not None and value > high):
        allowed = f' {_allowed(low, high, False)}' if low is not None or high is not None else ''
        raise error(f'{name} must be an integer{allowed}, got {value!r}')
    return int(value)


def check_side(name: str, value, error=ConfigError) -> int:
    """A foot side, LEFT (0) or RIGHT (1) of biped_planner.sides.

    :raises error: for anything else (bools included)
    """
    if isinstance(value, bool) or value not in SIDES:
        raise error(f'{name} must be LEFT (0) or RIGHT (1), got {value!r}')
    return value


def check_type(name: str, value, expected: type, error=ConfigError):
    """An instance of the expected type.

    :raises error: naming the type received
    """
    if not isinstance(value, expected):
        raise error(f'{name} must be a {expected.__name__}, got {type(value).__name__}')
    return value


def check_finite_array(name: str, value, shape: Optional[Tuple[int, ...]] = None,
                       error=ConfigError) -> np.ndarray:
    """A float array (a new one) of finite values, optionally of a given shape.

    :raises error: if value is not numeric, has another shape or holds NaN or inf
    """
    try:
        array = np.array(value, dtype=float)
    except (TypeError, ValueError) as cause:
        raise error(f'{name} must hold finite numbers, got {value!r}') from cause
    if shape is not None and array.shape != shape:
        raise error(f'{name} must have shape {shape}, got {array.shape}')
    if not np.all(np.isfinite(array)):
        raise error(f'{name} must be finite, got {value!r}')
    return array


def first_outside_limits(values, lower, upper, margin: float):
    """The first of values that is not finite or lies outside its limits widened by margin.

    :param values: (n,) values; lower, upper: (n,) limits (-inf / inf for none)
    :return: None when every value is inside, else (index, widened low, widened high)
    """
    values = np.asarray(values, dtype=float)
    low = np.asarray(lower, dtype=float) - margin
    high = np.asarray(upper, dtype=float) + margin
    bad = ~np.isfinite(values) | (values < low) | (values > high)
    if not np.any(bad):
        return None
    i = int(np.flatnonzero(bad)[0])
    return i, float(low[i]), float(high[i])
