"""parameter() fields validate themselves and describe themselves to the nodes."""
from dataclasses import dataclass
import math

import pytest

from biped_planner.errors import ConfigError
from biped_planner.parameter_fields import field_specs, parameter, validate_fields


@dataclass(frozen=True)
class Example:
    gain: float = parameter(3.0, 'feedback gain (1/s)', low=0.0, high=20.0)
    period: float = parameter(0.02, 'control period (s)', low=0.0, low_open=True)
    offset: tuple = parameter((0.0, 0.1), 'offset (m)', low=-0.5, high=0.5)
    mode: str = parameter('closed', 'loop mode', choices=('closed', 'open'))
    enabled: bool = parameter(True, 'switch')
    count: int = parameter(3, 'samples (1)', low=1, high=10)
    untracked: int = 4

    def __post_init__(self):
        validate_fields(self, ConfigError)


def test_defaults_are_valid_and_specs_are_listed():
    Example()
    specs = field_specs(Example)
    assert set(specs) == {'gain', 'period', 'offset', 'mode', 'enabled', 'count'}
    assert specs['gain'].bounds == (0.0, 20.0)
    assert specs['period'].bounds == (0.0, math.inf)
    assert specs['mode'].bounds == ('closed', 'open')
    assert specs['enabled'].bounds is None


@pytest.mark.parametrize('changes, message', [
    ({'gain': 20.5}, 'Example.gain must be in [0.0, 20.0], got 20.5'),
    ({'gain': -1e-9}, 'gain must be in'),
    ({'gain': math.nan}, 'gain must be a finite number'),
    ({'gain': math.inf}, 'gain must be a finite number'),
    ({'gain': True}, 'gain must be a finite number'),
    ({'gain': '3'}, 'gain must be a finite number'),
    ({'period': 0.0}, 'period must be in (0.0, None]'),
    ({'offset': (0.0, 0.6)}, 'offset must be in [-0.5, 0.5], got 0.6'),
    ({'mode': 'half'}, "mode must be one of ('closed', 'open'), got 'half'"),
    ({'enabled': 1}, 'enabled must be a bool'),
    ({'count': 2.5}, 'count must be an integer, got 2.5'),
    ({'count': 0}, 'count must be in [1, 10], got 0'),
])
def test_every_documented_bad_value_is_refused(changes, message):
    with pytest.raises(ConfigError, match=message.replace('(', r'\(').replace(')', r'\)')
                       .replace('[', r'\[').replace(']', r'\]')):
        Example(**changes)


def test_edges_are_allowed():
    Example(gain=0.0, period=1e-9, offset=(-0.5, 0.5), mode='open', enabled=False, count=10)
