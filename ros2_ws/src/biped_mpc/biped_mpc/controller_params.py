"""Parameters of the walking controller: which model, feedback, pelvis source and IK it uses."""
from dataclasses import dataclass

from biped_mpc.errors import ConfigError
from biped_mpc.mpc_params import LEG_OUTPUTS_TORSO_RELATIVE, MpcParams
from biped_mpc.robot_model import RobotModel
from biped_mpc.state_estimator import EstimatorParams
from biped_planner.parameter_fields import parameter, validate_fields

MODEL_THREE_MASS = 'three_mass'
MODEL_LIPM = 'lipm'
FEEDBACK_ESTIMATOR = 'estimator'
FEEDBACK_PREDICTION = 'prediction'
PELVIS_GROUND_TRUTH = 'ground_truth'
PELVIS_IMU_KINEMATICS = 'imu_kinematics'
IK_ANALYTIC = 'analytic'
IK_PINOCCHIO = 'pinocchio'
MODELS = (MODEL_THREE_MASS, MODEL_LIPM)
FEEDBACKS = (FEEDBACK_ESTIMATOR, FEEDBACK_PREDICTION)
PELVIS_SOURCES = (PELVIS_GROUND_TRUTH, PELVIS_IMU_KINEMATICS)
IK_SOLVERS = (IK_ANALYTIC, IK_PINOCCHIO)
# The humanoid's MPC tracks torso-relative leg outputs (MpcParams.leg_outputs).
CONTROLLER_MPC_PARAMS = MpcParams(leg_outputs=LEG_OUTPUTS_TORSO_RELATIVE)


@dataclass(frozen=True)
class WalkingControllerParams:
    """Parameters of the walking controller (biped_mpc.walking_controller).

    :param robot: the humanoid: leg geometry (analytic IK and kinematics), the three-mass
        model's masses and heights (the LIPM uses their total mass at the height of their
        centre of mass), pelvis height above the soles, centre-of-mass offset, and for the
        Pinocchio IK its URDF, leg joint names and sole frames
    :param model: 'three_mass' (the paper) or 'lipm' (the baseline of the same shape)
    :param mpc: MPC parameters (Ts, horizons, weights, constraints, QP backend); the default
        tracks torso-relative leg outputs (MpcParams.leg_outputs)
    :param estimator: Kalman filter noise model
    :param feedback: 'prediction' (the MPC starts from the commanded state) or 'estimator'
        (from its blend with the Kalman estimate)
    :param feedback_gain: g of x = x_cmd + g (x_kalman - x_cmd) with feedback='estimator',
        [0, 1]
    :param pelvis_source: 'ground_truth' (simulator base) or 'imu_kinematics' (IMU orientation,
        position from the latched stance feet)
    :param ik: 'analytic' (needs robot.leg_geometry) or 'pinocchio' (needs robot.urdf_path)
    :param stance_leg_projection: put the state of each stance leg's mass midway between its
        latched sole and the torso (biped_mpc.stance_feet)
    :param pelvis_velocity_gain: pelvis servo damping: the IK's pelvis target moves by this
        times the pelvis velocity error (s), [0, 1]; 0 disables it
    :param tilt_gain: posture feedback: the IK's pelvis orientation leans against the measured
        pelvis roll and pitch by tilt_gain times them, [0, 5]; 0 disables it
    :raises ConfigError: naming the field, for a value out of its range or a robot that lacks
        what the chosen IK needs
    """

    robot: RobotModel
    model: str = parameter(MODEL_THREE_MASS, 'three_mass (the paper) or lipm (the baseline)',
                           choices=MODELS)
    mpc: MpcParams = CONTROLLER_MPC_PARAMS
    estimator: EstimatorParams = EstimatorParams()
    feedback: str = parameter(FEEDBACK_PREDICTION, 'where the MPC starts: prediction (the '
                              'commanded state) or estimator (blend with the Kalman estimate)',
                              choices=FEEDBACKS)
    feedback_gain: float = parameter(1.0, 'blend of the Kalman estimate into the commanded '
                                     'state with feedback estimator', low=0.0, high=1.0)
    pelvis_source: str = parameter(PELVIS_GROUND_TRUTH, 'ground_truth (odom) or imu_kinematics '
                                   '(IMU + latched stance feet)', choices=PELVIS_SOURCES)
    ik: str = parameter(IK_ANALYTIC, 'leg inverse kinematics', choices=IK_SOLVERS)
    stance_leg_projection: bool = parameter(True, 'stance leg mass state projected midway '
                                            'between its latched sole and the torso')
    pelvis_velocity_gain: float = parameter(0.05, 'pelvis velocity servo gain (s)', low=0.0,
                                            high=1.0)
    tilt_gain: float = parameter(0.2, 'posture feedback against the measured roll and pitch',
                                 low=0.0, high=5.0)

    def __post_init__(self) -> None:
        if not isinstance(self.robot, RobotModel):
            raise ConfigError(f'WalkingControllerParams.robot must be a RobotModel, got '
                              f'{type(self.robot).__name__}')
        validate_fields(self, ConfigError)
        if self.ik == IK_ANALYTIC and self.robot.leg_geometry is None:
            raise ConfigError('WalkingControllerParams.ik = analytic needs robot.leg_geometry; '
                              'use ik = pinocchio for this robot')
        if self.ik == IK_PINOCCHIO and not self.robot.urdf_path:
            raise ConfigError('WalkingControllerParams.ik = pinocchio needs robot.urdf_path')
        for name, kind in (('mpc', MpcParams), ('estimator', EstimatorParams)):
            if not isinstance(getattr(self, name), kind):
                raise ConfigError(f'WalkingControllerParams.{name} must be a {kind.__name__}, '
                                  f'got {type(getattr(self, name)).__name__}')
