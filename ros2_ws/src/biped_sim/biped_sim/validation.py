"""Checks shared by the biped_sim modules: arrays and vectors at the inputs, numbers in setups.

Parameter dataclasses declare their ranges with biped_planner.parameter_fields.parameter() and
call validate_fields; what a field spec cannot say (a vector's length, an optional value, a
bound that depends on another field) is checked with the helpers here.
"""
import math
import numbers

from biped_mpc import validation as mpc_validation
import numpy as np

from biped_sim.errors import ConfigError


def finite_array(name: str, value, shape: tuple, error=ConfigError) -> np.ndarray:
    """:return: value as a float array of the given shape.

    :param error: the exception type to raise (ConfigError, or InputError at run time)
    :raises error: naming the argument, for a wrong shape or a NaN / inf entry
    """
    array = np.asarray(value, dtype=float)
    if array.shape != shape:
        raise error('%s has shape %s, expected %s' % (name, array.shape, shape))
    if not np.all(np.isfinite(array)):
        raise error('%s = %r has NaN or inf' % (name, value))
    return array


def number_tuple(name: str, value, size: int) -> tuple:
    """:return: value as a tuple of size finite floats (biped_mpc's check, this package's error).

    :raises ConfigError: naming the parameter, for a wrong length or a non-finite entry
    """
    return mpc_validation.number_tuple(name, value, size, ConfigError)


def finite_number(name: str, value, positive: bool = False) -> float:
    """:return: value as a float.

    :param positive: also require value > 0
    :raises ConfigError: naming the parameter, for a non-number, NaN, inf (or value <= 0)
    """
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise ConfigError('%s = %r must be a finite number' % (name, value))
    value = float(value)
    if not math.isfinite(value) or (positive and value <= 0.0):
        raise ConfigError('%s = %r must be finite%s' % (name, value, ' and > 0' if positive
                                                          else ''))
    return value


def substep_count(n_substeps, default: int) -> int:
    """:return: the physics steps of a backend's step call (default when n_substeps is None).

    :raises ConfigError: unless n_substeps is None or an int >= 1
    """
    n = default if n_substeps is None else n_substeps
    if isinstance(n, bool) or not isinstance(n, numbers.Integral) or n < 1:
        raise ConfigError('n_substeps = %r must be an int >= 1' % (n_substeps,))
    return int(n)
