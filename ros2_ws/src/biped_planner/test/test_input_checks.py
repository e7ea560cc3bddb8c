"""Tests of biped_planner.input_checks."""
import math

import numpy as np
import pytest

from biped_planner.errors import CommandError, ConfigError
from biped_planner.input_checks import (check_finite_array, check_integer, check_number,
                                        check_side, check_type, first_outside_limits,
                                        is_finite_number)
from biped_planner.sides import LEFT, RIGHT


@pytest.mark.parametrize('value, finite', [(1, True), (-2.5, True), (np.float32(0.5), True),
                                           (np.int64(3), True), (True, False), (math.nan, False),
                                           (math.inf, False), ('1', False), (None, False)])
def test_is_finite_number(value, finite):
    assert is_finite_number(value) == finite


def test_check_number_returns_a_float_within_the_bounds():
    assert check_number('x', 2) == 2.0 and isinstance(check_number('x', 2), float)
    assert check_number('x', 0.0, low=0.0, high=1.0) == 0.0
    assert check_number('x', 1.0, low=0.0, high=1.0) == 1.0


@pytest.mark.parametrize('kwargs, message', [
    (dict(value=math.nan), 'dt must be a finite number, got nan'),
    (dict(value=0.0, low=0.0, low_open=True, unit=' s'), r'dt must be a finite number > 0.0 s'),
    (dict(value=-1.0, low=0.0), 'dt must be a finite number >= 0.0, got -1.0'),
    (dict(value=2.0, low=0.0, high=1.0), r'dt must be a finite number in \[0.0, 1.0\], got 2.0'),
    (dict(value=0.0, low=0.0, high=1.0, low_open=True), r'in \(0.0, 1.0\]'),
    (dict(value=5.0, high=1.0), 'dt must be a finite number <= 1.0'),
    (dict(value=False), 'dt must be a finite number, got False'),
])
def test_check_number_names_the_argument_and_the_bounds(kwargs, message):
    with pytest.raises(ConfigError, match=message):
        check_number('dt', **kwargs)


def test_checks_raise_the_error_type_asked_for():
    with pytest.raises(CommandError):
        check_number('vx', math.inf, error=CommandError)
    with pytest.raises(CommandError):
        check_type('command', 3, str, error=CommandError)


@pytest.mark.parametrize('value', [1.5, True, '2', 0, 11])
def test_check_integer_refuses_non_integers_and_out_of_range(value):
    with pytest.raises(ConfigError, match='n must be an integer in'):
        check_integer('n', value, 1, 10)


def test_check_integer_accepts_numpy_integers():
    assert check_integer('n', np.int32(4), low=1) == 4


@pytest.mark.parametrize('value', [2, -1, True, 0.5, None])
def test_check_side_refuses_anything_but_a_foot(value):
    with pytest.raises(ConfigError, match='side must be LEFT'):
        check_side('side', value)
    assert check_side('side', LEFT) == LEFT and check_side('side', RIGHT) == RIGHT


def test_check_type_names_the_type_received():
    with pytest.raises(ConfigError, match='params must be a dict, got list'):
        check_type('params', [], dict)


@pytest.mark.parametrize('value, shape, message', [
    ([1.0, math.nan], None, 'must be finite'), (['a', 'b'], None, 'must hold finite numbers'),
    ([1.0, 2.0, 3.0], (2,), r'must have shape \(2,\)'), ([[1.0], [2.0, 3.0]], None, 'finite')])
def test_check_finite_array_refuses_bad_arrays(value, shape, message):
    with pytest.raises(ConfigError, match=message):
        check_finite_array('hip0', value, shape)


def test_check_finite_array_returns_a_float_copy():
    source = np.array([1, 2])
    array = check_finite_array('hip0', source, (2,))
    assert array.dtype == float and array is not source


def test_first_outside_limits_widens_the_limits_by_the_margin_and_names_the_first():
    lower, upper = [-1.0, -1.0, -math.inf], [1.0, 1.0, math.inf]
    assert first_outside_limits([1.05, -1.05, 1e9], lower, upper, 0.1) is None
    assert first_outside_limits([0.0, -1.2, 5.0], lower, upper, 0.1) == \
        (1, pytest.approx(-1.1), pytest.approx(1.1))
    assert first_outside_limits([1.2, math.nan, 0.0], lower, upper, 0.1)[0] == 0
    assert first_outside_limits([0.0, 0.0, math.nan], lower, upper, 0.1)[0] == 2  # NaN: out
