"""The paper's three-mass model (section "Three-mass Dynamics Model", eq. statespace_3lipm)."""
from dataclasses import dataclass

from biped_mpc.errors import ConfigError
from biped_mpc.linear_model import LinearModel
from biped_planner.parameter_fields import parameter, validate_fields


@dataclass(frozen=True)
class ThreeMassParams:
    """Masses and constant heights of the three-mass model (paper Table Params).

    The paper writes m_1 (stance leg), m_2 (torso), m_3 (swing leg). Here the legs are labelled
    left and right, which is what a physical leg is; with the paper's equal legs (m_1 = m_3,
    z_1 = z_3) the two labellings give the same C, and with unequal legs the left/right form
    is the physically right one (a leg keeps its mass when it becomes the stance leg).

    :param left_leg_mass: mass of the left leg (kg), (0, 1000]
    :param torso_mass: mass of the torso (kg), (0, 1000]
    :param right_leg_mass: mass of the right leg (kg), (0, 1000]
    :param left_leg_height: height of the left leg mass (m), (0, 10]
    :param torso_height: height of the torso mass (m), (0, 10]
    :param right_leg_height: height of the right leg mass (m), (0, 10]
    :param gravity: gravitational acceleration (m/s^2), (0, 100]
    """

    left_leg_mass: float = parameter(15.0, 'mass of the left leg (kg)', low=0.0, high=1000.0,
                                     low_open=True)
    torso_mass: float = parameter(50.0, 'mass of the torso (kg)', low=0.0, high=1000.0,
                                  low_open=True)
    right_leg_mass: float = parameter(15.0, 'mass of the right leg (kg)', low=0.0, high=1000.0,
                                      low_open=True)
    left_leg_height: float = parameter(0.5, 'height of the left leg mass (m)', low=0.0,
                                       high=10.0, low_open=True)
    torso_height: float = parameter(1.2, 'height of the torso mass (m)', low=0.0, high=10.0,
                                    low_open=True)
    right_leg_height: float = parameter(0.5, 'height of the right leg mass (m)', low=0.0,
                                        high=10.0, low_open=True)
    gravity: float = parameter(9.81, 'gravitational acceleration (m/s^2)', low=0.0, high=100.0,
                               low_open=True)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


def three_mass_model(params: ThreeMassParams = ThreeMassParams()) -> LinearModel:
    """Build the continuous three-mass model of one plane.

    Per plane (the sagittal and frontal equations are identical and independent):
    dX/dt = A X + B U with X = [c_l, c_l', c_l'', c_t, c_t', c_t'', c_r, c_r', c_r''] and
    U = [c_l''', c_t''', c_r'''] (jerks); y = C X with the rows left leg position, right leg
    position and ZMP p = sum_k m_k c_k / M - sum_k m_k z_k c_k'' / (M g) (eq. zmp, z_k'' = 0),
    M = m_l + m_t + m_r.

    :param params: masses and heights
    :return: the continuous model (name 'three_mass')
    """
    return LinearModel(
        name='three_mass',
        masses=(params.left_leg_mass, params.torso_mass, params.right_leg_mass),
        heights=(params.left_leg_height, params.torso_height, params.right_leg_height),
        gravity=params.gravity)
