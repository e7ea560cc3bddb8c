"""Tests of biped_planner.lag_filter."""
import math

import numpy as np
import pytest

from biped_planner.errors import CommandError, ConfigError
from biped_planner.lag_filter import FirstOrderLag


@pytest.mark.parametrize('tau, dt', [(0.5, 0.5), (1.0, 0.1), (2.0, 0.6)])
def test_step_response_is_the_closed_form(tau, dt):
    lag = FirstOrderLag(tau, initial=0.2)
    target = 1.5
    outputs = [float(lag.update(target, dt)) for _ in range(30)]
    k = np.arange(1, 31)
    expected = target + (0.2 - target) * np.exp(-k * dt / tau)
    np.testing.assert_allclose(outputs, expected, rtol=1e-12)


def test_vector_filter_and_zero_time_constant():
    lag = FirstOrderLag(1.0, initial=[0.0, 0.0, 0.0])
    out = lag.update([1.0, -2.0, 0.5], 1.0)
    np.testing.assert_allclose(out, np.array([1.0, -2.0, 0.5]) * (1 - math.exp(-1.0)))
    np.testing.assert_allclose(FirstOrderLag(0.0, [0.0, 0.0]).update([3.0, 4.0], 0.1), [3, 4])
    assert FirstOrderLag(0.0).gain(0.2) == 1.0


def test_reset_and_value_copy():
    lag = FirstOrderLag(1.0, [1.0, 2.0])
    value = lag.value
    value[0] = 99.0
    np.testing.assert_allclose(lag.value, [1.0, 2.0])
    lag.reset([0.0, 0.0])
    np.testing.assert_allclose(lag.value, [0.0, 0.0])


@pytest.mark.parametrize('tau', [-1.0, math.nan, 101.0, True])
def test_rejects_bad_time_constant(tau):
    with pytest.raises(ConfigError):
        FirstOrderLag(tau)


def test_rejects_bad_inputs():
    with pytest.raises(ConfigError):
        FirstOrderLag(1.0, initial=math.inf)
    lag = FirstOrderLag(1.0, [0.0, 0.0])
    with pytest.raises(CommandError):
        lag.update([math.nan, 0.0], 0.1)
    with pytest.raises(CommandError):
        lag.update([1.0, 0.0, 0.0], 0.1)
    with pytest.raises(CommandError):
        lag.reset([math.inf, 0.0])
    for dt in (0.0, -0.1, math.nan):
        with pytest.raises(ConfigError):
            lag.update([1.0, 0.0], dt)
