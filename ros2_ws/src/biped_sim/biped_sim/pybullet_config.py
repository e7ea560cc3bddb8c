"""Parameters of the PyBullet backend, each field with its unit and range (the node reads them)."""

from dataclasses import dataclass

from biped_planner.parameter_fields import parameter, validate_fields

from biped_sim.errors import ConfigError

TORQUE_CONTROL = 'torque'
POSITION_CONTROL = 'position'


@dataclass(frozen=True)
class PyBulletConfig:
    """Parameters of the PyBullet backend (see biped_sim.pybullet_backend).

    The PD gains are the gains before the stability cap of biped_sim.pybullet_joint_control:
    Kp dt^2 / M_jj <= gain_cap and Kd dt / M_jj <= gain_cap per joint.
    """

    gui: bool = parameter(False, 'open the PyBullet GUI instead of running headless (DIRECT)')
    time_step: float = parameter(0.001, 'physics time step (s)', low=1e-4, high=0.01)
    control_substeps: int = parameter(20, 'physics steps per control period (20 = 50 Hz at '
                                      '1 kHz)', low=1)
    control_mode: str = parameter(TORQUE_CONTROL, 'joint control: torque (PD + gravity '
                                  'compensation) or position (PyBullet motors)',
                                  choices=(TORQUE_CONTROL, POSITION_CONTROL))
    gravity: float = parameter(9.81, 'gravity acceleration (m/s^2)', low=0.0, low_open=True)
    leg_kp: float = parameter(800.0, 'leg joint PD stiffness in torque mode, capped per joint '
                              'by its inertia (N m/rad)', low=0.0, high=1e5)
    leg_kd: float = parameter(8.0, 'leg joint PD damping in torque mode (N m s/rad)', low=0.0,
                              high=1e3)
    upper_kp: float = parameter(300.0, 'waist and arm PD stiffness in torque mode (N m/rad)',
                                low=0.0, high=1e5)
    upper_kd: float = parameter(3.0, 'waist and arm PD damping in torque mode (N m s/rad)',
                                low=0.0, high=1e3)
    gain_cap: float = parameter(0.5, 'stability cap of the explicit PD, Kp dt^2/M_jj and '
                                'Kd dt/M_jj (1)', low=0.0, high=1.0, low_open=True)
    gravity_compensation: bool = parameter(True, 'add the gravity-compensation torques in '
                                           'torque mode')
    gravity_compensation_period: int = parameter(1, 'physics steps between two computations '
                                                 'of the gravity-compensation torques (held in '
                                                 'between)', low=1)
    position_gain: float = parameter(0.3, 'PyBullet position-motor gain (position mode) (1)',
                                     low=0.0, high=1.0, low_open=True)
    velocity_gain: float = parameter(1.0, 'PyBullet position-motor velocity gain (1)', low=0.0,
                                     high=1.0)
    foot_friction: float = parameter(1.0, 'lateral friction coefficient of the feet and the '
                                     'ground (1)', low=0.0, low_open=True)
    sole_contact_stiffness: float = parameter(
        0.0, 'normal stiffness of each contact point of a sole, a rubber pad (N/m); 0 keeps '
        "PyBullet's rigid contact. 1e5 sinks the standing robot by about 0.8 mm and walks the "
        "paper's tiles further, but costs the open-loop flat-ground figures "
        '(docs/simulator_notes.md)', low=0.0, high=1e9)
    sole_contact_damping: float = parameter(
        1500.0, 'normal damping of each contact point of a sole (N s/m), with the stiffness',
        low=0.0, high=1e7)
    contact_threshold: float = parameter(15.0, 'normal ground force above which a foot is in '
                                         'contact (N)', low=0.0, low_open=True)
    solver_iterations: int = parameter(50, 'iterations of the PyBullet constraint solver',
                                       low=1)

    def __post_init__(self):
        validate_fields(self, ConfigError)
