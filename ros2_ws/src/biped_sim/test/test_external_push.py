"""Tests of the external push description."""

import math

import pytest

from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush


def test_values_are_kept_as_floats():
    push = ExternalPush((100, 0, 0), 0.1, point=(0, 0, 0.05), start_time=1.6)
    assert push.force == (100.0, 0.0, 0.0)
    assert push.point == (0.0, 0.0, 0.05)


@pytest.mark.parametrize('kwargs, field', [
    ({'force': (1.0, 2.0)}, 'force'),
    ({'force': (1.0, math.nan, 0.0)}, 'force'),
    ({'force': (1.0, 0.0, 0.0), 'duration': 0.0}, 'duration'),
    ({'force': (1.0, 0.0, 0.0), 'point': (0.0, 0.0, math.inf)}, 'point'),
    ({'force': (1.0, 0.0, 0.0), 'start_time': math.nan}, 'start_time'),
])
def test_bad_pushes_raise(kwargs, field):
    with pytest.raises(ConfigError, match=field):
        ExternalPush(**kwargs)
