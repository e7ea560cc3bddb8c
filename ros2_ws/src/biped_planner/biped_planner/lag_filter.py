"""First-order lag filter for step actions and walk commands (the paper's smooth set-point update).

Continuous model tau y_dot + y = u with u held over each update interval dt; its exact
discretisation is y_k = y_k-1 + (1 - a) (u_k - y_k-1) with a = exp(-dt / tau). A step in u from
y_0 gives y_k = u + (y_0 - u) a^k. tau = 0 passes u through.
"""
import math
from typing import Union

import numpy as np

from biped_planner.errors import CommandError
from biped_planner.input_checks import check_finite_array, check_number

ArrayLike = Union[float, np.ndarray]


class FirstOrderLag:
    """First-order lag on a scalar or a vector."""

    def __init__(self, time_constant: float, initial: ArrayLike = 0.0) -> None:
        """Create the filter.

        :param time_constant: tau (s), [0, 100]; 0 disables the filtering
        :param initial: initial output (any shape), finite
        :raises ConfigError: if tau is out of range or the initial value is not finite
        """
        self._time_constant = check_number('time_constant', time_constant, 0.0, 100.0,
                                           unit=' s')
        self._value = check_finite_array('initial', initial)

    @property
    def time_constant(self) -> float:
        """tau (s)."""
        return self._time_constant

    @property
    def value(self) -> np.ndarray:
        """The current output (a copy)."""
        return self._value.copy()

    def reset(self, value: ArrayLike) -> None:
        """Set the output without filtering.

        :param value: new output, finite
        :raises CommandError: if the value is not finite
        """
        self._value = check_finite_array('value', value, error=CommandError)

    def gain(self, dt: float) -> float:
        """The fraction 1 - exp(-dt / tau) of the error removed by one update of length dt.

        :param dt: update interval (s), > 0
        :return: the gain in (0, 1]
        :raises ConfigError: if dt is not a finite number > 0
        """
        check_number('dt', dt, low=0.0, low_open=True, unit=' s')
        if self._time_constant == 0.0:
            return 1.0
        return 1.0 - math.exp(-dt / self._time_constant)

    def update(self, target: ArrayLike, dt: float) -> np.ndarray:
        """Move the output towards the target over one interval.

        :param target: the input u held over the interval (the shape of the output), finite
        :param dt: interval (s), > 0
        :return: the new output (a copy)
        :raises CommandError: if the target is not finite or has another shape
        :raises ConfigError: if dt is not a finite number > 0
        """
        gain = self.gain(dt)
        target = check_finite_array('target', target, error=CommandError)
        if target.shape != self._value.shape:
            raise CommandError(f'target must have shape {self._value.shape}, got '
                               f'{target.shape}')
        self._value = self._value + gain * (target - self._value)
        return self._value.copy()
