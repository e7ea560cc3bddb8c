"""Ground conformance: the tilt of a loaded sole beyond the deadband, low-passed."""
import math

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from biped_mpc.balance.ground_conformance import GroundConformance, GroundConformanceParams
from biped_mpc.errors import ConfigError, InputError
from biped_planner.rotations import roll_pitch_of_zxy_matrix, rotation_x, rotation_y, rotation_z

FLAT = np.eye(3)


def tilted(roll: float, pitch: float, yaw: float = 0.0) -> np.ndarray:
    return rotation_z(yaw) @ rotation_x(roll) @ rotation_y(pitch)


@pytest.mark.parametrize('roll, pitch, yaw', [(0.1, -0.2, 0.0), (-0.3, 0.05, 2.5),
                                              (0.0, 0.4, -1.0), (0.7, 0.9, 3.0)])
def test_the_tilt_is_the_roll_and_pitch_of_the_iks_composition_whatever_the_yaw(roll, pitch,
                                                                                 yaw):
    rotation = tilted(roll, pitch, yaw)
    assert roll_pitch_of_zxy_matrix(rotation) == pytest.approx([roll, pitch], abs=1e-12)
    # scipy's intrinsic z-x-y angles of the same rotation, an independent decomposition
    assert roll_pitch_of_zxy_matrix(rotation) == pytest.approx(
        Rotation.from_matrix(rotation).as_euler('ZXY')[1:], abs=1e-12)


def test_a_loaded_sole_tilted_beyond_the_deadband_is_followed_as_a_first_order_lag():
    params = GroundConformanceParams(deadband=0.035, time_constant=0.05, angle_limit=0.3)
    conformance = GroundConformance(params)
    soles = (tilted(0.0, 0.15), tilted(-0.02, 0.0))   # left pitched 0.15 rad, right within
    pitches = [conformance.update(0.02, soles, (True, True))[0, 1] for _ in range(10)]
    excess = 0.15 - 0.035
    expected = [excess * (1.0 - math.exp(-0.02 * k / 0.05)) for k in range(1, 11)]
    assert pitches == pytest.approx(expected, rel=1e-9)
    assert np.all(conformance.offsets[1] == 0.0)  # the right sole within the deadband
    assert conformance.offsets[0, 0] == 0.0


def test_a_sole_that_is_not_loaded_goes_back_to_nominal_and_the_offset_is_limited():
    conformance = GroundConformance(GroundConformanceParams(deadband=0.0, time_constant=0.02,
                                                            angle_limit=0.1))
    soles = (tilted(-0.4, 0.0), FLAT)
    for _ in range(50):
        conformance.update(0.02, soles, (True, False))
    assert conformance.offsets[0] == pytest.approx([-0.1, 0.0], abs=1e-9)  # at the limit
    offsets = conformance.update(0.02, soles, (False, False))
    assert offsets[0, 0] == pytest.approx(-0.1 * math.exp(-1.0), rel=1e-9)
    conformance.reset()
    assert np.all(conformance.offsets == 0.0)


@pytest.mark.parametrize('dt', [0.0, -0.02, math.nan, math.inf])
def test_a_period_that_is_not_positive_and_finite_is_refused(dt):
    with pytest.raises(InputError, match='dt'):
        GroundConformance().update(dt, (FLAT, FLAT), (True, True))


@pytest.mark.parametrize('field, value', [('deadband', -0.01), ('time_constant', 0.0),
                                          ('angle_limit', 1.0), ('deadband', math.nan)])
def test_parameters_out_of_range_are_refused(field, value):
    with pytest.raises(ConfigError, match=field):
        GroundConformanceParams(**{field: value})
