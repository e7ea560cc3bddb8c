"""Vertical drift compensation: the integrator's ramp, the closed loop's decay, hold and limit."""
import math

import pytest

from biped_mpc.balance.vertical_drift import VerticalDrift, VerticalDriftParams
from biped_mpc.errors import ConfigError, InputError

DT = 0.02


def test_open_loop_error_is_integrated():
    drift = VerticalDrift(VerticalDriftParams(frequency=1.0))
    for k in range(1, 10):
        result = drift.update(DT, True, -0.5, -0.51)
        assert result.offset == pytest.approx(0.01 * k * DT, abs=1e-15)
        assert result.error == pytest.approx(0.01)


def test_closed_loop_error_decays_at_the_frequency():
    frequency = 1.0
    drift = VerticalDrift(VerticalDriftParams(frequency=frequency))
    sag = -0.02  # the legs came out 2 cm short of their reference
    measured = -0.5 + sag
    for k in range(1, 200):
        result = drift.update(DT, True, -0.5, measured)
        measured = -0.5 + sag + result.offset
        assert measured + 0.5 == pytest.approx(sag * (1.0 - frequency * DT) ** k, abs=1e-15)
    # The sampled decay is the continuous exp(-f t) to first order in dt.
    assert (measured + 0.5) / sag == pytest.approx(math.exp(-frequency * 199 * DT), rel=0.05)


def test_inactive_holds_and_the_limit_and_reset():
    drift = VerticalDrift(VerticalDriftParams(frequency=5.0, max_offset=0.01))
    drift.update(DT, True, 0.0, -0.05)
    held = drift.offset
    result = drift.update(DT, False, 0.0, -0.05)
    assert result.offset == held and result.error == 0.0
    for _ in range(100):
        result = drift.update(DT, True, 0.0, -0.05)
    assert result.offset == 0.01 and result.limited
    drift.reset()
    assert drift.offset == 0.0


@pytest.mark.parametrize('change', [{'frequency': -1.0}, {'max_offset': math.nan}])
def test_bad_parameters_are_refused(change):
    with pytest.raises(ConfigError):
        VerticalDriftParams(**change)


@pytest.mark.parametrize('args', [(0.0, True, 0.0, 0.0), (DT, True, math.nan, 0.0),
                                  (DT, True, 0.0, '0')])
def test_bad_inputs_are_refused(args):
    with pytest.raises(InputError):
        VerticalDrift().update(*args)
