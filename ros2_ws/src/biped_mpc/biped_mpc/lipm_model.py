"""The LIPM (cart-table) model of the baseline controller, in the three-mass layout."""
from dataclasses import dataclass

from biped_mpc.errors import ConfigError
from biped_mpc.linear_model import LinearModel
from biped_mpc.three_mass_model import ThreeMassParams
from biped_planner.parameter_fields import parameter, validate_fields

# Legs of the LIPM are massless; a height is still needed by the shared layout and never used.
_MASSLESS_LEG_HEIGHT = 1.0


@dataclass(frozen=True)
class LipmParams:
    """The single mass of the LIPM.

    :param mass: total mass of the robot (kg), (0, 1000]
    :param com_height: constant height of the centre of mass (m), (0, 10]
    :param gravity: gravitational acceleration (m/s^2), (0, 100]
    """

    mass: float = parameter(80.0, 'total mass of the robot (kg)', low=0.0, high=1000.0,
                            low_open=True)
    com_height: float = parameter(0.9375, 'constant height of the centre of mass (m)', low=0.0,
                                  high=10.0, low_open=True)
    gravity: float = parameter(9.81, 'gravitational acceleration (m/s^2)', low=0.0, high=100.0,
                               low_open=True)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)

    @classmethod
    def from_three_mass(cls, params: ThreeMassParams) -> 'LipmParams':
        """The LIPM of a three-mass robot: its total mass at the height of its centre of mass.

        :param params: the three-mass robot
        :return: LIPM parameters (paper values give 80 kg at 0.9375 m)
        """
        total = params.left_leg_mass + params.torso_mass + params.right_leg_mass
        height = (params.left_leg_mass * params.left_leg_height
                  + params.torso_mass * params.torso_height
                  + params.right_leg_mass * params.right_leg_height) / total
        return cls(mass=total, com_height=height, gravity=params.gravity)


def lipm_model(params: LipmParams = LipmParams()) -> LinearModel:
    """Build the LIPM baseline model of one plane in the shared nine-state layout.

    The whole mass M sits at the torso slot (the centre of mass) at height z_c: the ZMP row is
    the cart-table model p = c - (z_c / g) c'' (Kajita's preview-control form of the LIPM with
    jerk input). The baseline treats the legs as massless: their triple integrators stay in the
    state only so that the leg rows of the outputs follow the leg references kinematically,
    which lets the same MPC class, estimator and reference adapter run unchanged; the legs do
    not enter the ZMP.

    :param params: mass and centre-of-mass height
    :return: the continuous model (name 'lipm')
    """
    return LinearModel(
        name='lipm',
        masses=(0.0, params.mass, 0.0),
        heights=(_MASSLESS_LEG_HEIGHT, params.com_height, _MASSLESS_LEG_HEIGHT),
        gravity=params.gravity)
