"""Input checks shared by the biped_mpc modules."""
import numpy as np

from biped_mpc.errors import InputError


def finite_array(name: str, value, shape: tuple) -> np.ndarray:
    """:return: value as a float array of the given shape.

    :raises InputError: naming the argument, for a wrong shape or a NaN / inf entry
    """
    array = np.asarray(value, dtype=float)
    if array.shape != shape:
        raise InputError(f'{name} must have shape {shape}, got {array.shape}')
    if not np.isfinite(array).all():
        raise InputError(f'{name} must be finite, got {array.tolist()}')
    return array
