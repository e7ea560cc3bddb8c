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
BALANCE_STABILIZER = 'stabilizer'
BALANCE_OPEN_LOOP = 'open_loop'
BALANCE_MODES = (BALANCE_STABILIZER, BALANCE_OPEN_LOOP)
SWING_TARGET_PLANNED = 'planned'
SWING_TARGET_MASSES = 'masses'
SWING_TARGETS = (SWING_TARGET_PLANNED, SWING_TARGET_MASSES)
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

    The balance fields (balance ... landing_max_extra_depth) configure the stabilizer between
    the MPC and the IK (biped_mpc.balance.balance_loop); with balance 'open_loop' they are
    unused and the cycle is the feed-forward one. Each carries its unit and range below.
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
    command_leash_along: float = parameter(
        0.0, "the MPC's commanded hip is kept within this distance of the measured one along "
        'the pelvis heading: beyond it the commanded state moves towards the robot, so the '
        'servos pull a pushed robot back by at most this (biped_mpc.command_leash, m); 0: '
        'unbounded', low=0.0, high=1.0)
    command_leash_across: float = parameter(
        0.0, 'the same across the pelvis heading, where the sole is half as wide (m); 0: '
        'unbounded', low=0.0, high=1.0)
    adjusted_walk_dcm_leash: float = parameter(
        0.05, "at each step the step adjuster moves, the MPC's commanded DCM is brought once "
        'within this distance of the measured one by moving the commanded velocities, so the '
        "MPC's model is pushed as the robot was (biped_mpc.command_leash, m); 0: off",
        low=0.0, high=1.0)
    # --- balance: the stabilizer between the MPC and the IK (biped_mpc.balance)
    balance: str = parameter(BALANCE_STABILIZER, 'stabilizer (DCM feedback, wrench distribution, '
                             'foot damping, force difference, drift, contact-aware landing) or '
                             'open_loop (the feed-forward cycle)', choices=BALANCE_MODES)
    swing_target: str = parameter(SWING_TARGET_PLANNED, 'horizontal swing foot target: planned '
                                  '(the reference trajectory) or masses (2 leg mass - hip)',
                                  choices=SWING_TARGETS)
    swing_start_time_constant: float = parameter(
        0.1, 'with the planned swing target: a swing starts where the foot was latched and '
        'this is the decay time of that lift-off offset from the planned swing (s); 0: the '
        'planned swing from its planned start', low=0.0, high=10.0)
    swing_retarget: bool = parameter(
        False, 'with the planned swing target: when the plan moves a swinging foot\'s landing '
        '(step adjustment), the target\'s jump fades out by the touchdown instead of whipping '
        'the foot (biped_mpc.swing_retarget)')
    pelvis_ground_at_zmp: bool = parameter(
        True, 'the pelvis stands pelvis_height above the ground under the commanded ZMP (the '
        'held feet\'s heights weighed by where the ZMP is between them), so a touchdown or '
        'lift-off on tiles of different heights does not step the legs\' length; false: above '
        'the held feet\'s mean height')
    height_continuity_time_constant: float = parameter(
        0.0, 'lag of the held soles\' and the pelvis\'s height targets behind the latched '
        'ground: a touchdown on a lower or higher tile does not step the stiff legs\' length '
        '(biped_mpc.height_continuity); 0: none (s)', low=0.0, high=10.0)
    height_continuity_deadband: float = parameter(
        0.005, 'the part of a height target step taken at once (m): a landing on flat ground '
        'steps the targets by less, and the leg must press the foot down', low=0.0, high=0.1)
    swing_smoothing_time_constant: float = parameter(
        0.07, 'with the planned swing target: each swing foot follows its target through a '
        'first-order lag of this time constant, for a softer lift-off and landing (s); 0: off',
        low=0.0, high=1.0)
    swing_attitude_gain: float = parameter(
        0.0, 'a swing foot is placed for this fraction of the measured pelvis roll and pitch '
        'instead of the commanded ones, so a tilting body does not hold it over the ground '
        '(biped_mpc.swing_attitude); 0: off', low=0.0, high=1.0)
    dcm_gain: float = parameter(3.0, 'DCM feedback proportional gain k_p (1/s)', low=0.0,
                                high=50.0)
    dcm_integral_gain: float = parameter(2.0, 'DCM feedback integral gain k_i (1/s^2)',
                                         low=0.0, high=100.0)
    dcm_integral_time_constant: float = parameter(5.0, 'leak time constant of the DCM error '
                                                  'integral (s)', low=0.01, high=1000.0)
    dcm_integral_limit: float = parameter(0.05, 'bound of the DCM error integral per axis (m s)',
                                          low=0.0, high=10.0)
    com_admittance: float = parameter(0.0, 'COM admittance: the pelvis target moves at this '
                                      'times the measured - desired ZMP (1/s); 0 disables it',
                                      low=0.0, high=50.0)
    com_admittance_time_constant: float = parameter(1.0, 'leak of the COM admittance offset '
                                                    'back to zero (s)', low=0.01, high=1000.0)
    com_admittance_limit: float = parameter(0.03, 'largest COM admittance offset per axis (m)',
                                            low=0.0, high=0.2)
    hip_strategy_gain: float = parameter(
        0.0, 'hip strategy: fraction of the desired ZMP beyond the soles produced as a moment '
        'by swinging the trunk (the IK\'s pelvis orientation) about the hips; 0 disables it',
        low=0.0, high=5.0)
    hip_strategy_inertia: float = parameter(0.8, 'inertia of the trunk (pelvis and above) about '
                                            'the hips, roll and pitch (kg m^2)', low=0.01,
                                            high=100.0)
    hip_strategy_return_frequency: float = parameter(
        6.0, 'natural frequency of the trunk\'s critically damped return upright (rad/s)',
        low=0.0, high=100.0)
    hip_strategy_rate_limit: float = parameter(5.0, 'largest trunk swing speed (rad/s)',
                                               low=0.01, high=50.0)
    hip_strategy_angle_limit: float = parameter(0.45, 'largest trunk swing angle (rad)',
                                                low=0.0, high=1.0)
    ft_cutoff_frequency: float = parameter(15.0, 'low-pass cut-off of the ankle F/T wrenches '
                                           '(Hz)', low=0.1, high=1000.0)
    ft_sensor_height: float = parameter(0.04, 'ankle F/T sensor origin above the sole (m)',
                                        low=0.0, high=0.5)
    foot_mass: float = parameter(0.75, 'mass of the foot below the F/T sensor (kg)', low=0.0,
                                 high=20.0)
    foot_com_height: float = parameter(-0.0275, 'foot centre of mass along the sensor z axis '
                                       '(m)', low=-0.5, high=0.5)
    sole_length: float = parameter(0.2, 'sole length (m)', low=0.01, high=1.0)
    sole_width: float = parameter(0.1, 'sole width (m)', low=0.01, high=1.0)
    cop_margin: float = parameter(0.01, 'distance the desired CoP keeps from the sole edges (m)',
                                  low=0.0, high=0.04)
    wrench_friction: float = parameter(0.7, 'friction coefficient of the wrench distribution '
                                       'QP, below the real one (1)', low=0.05, high=2.0)
    wrench_min_force: float = parameter(15.0, 'minimum normal force of a supporting foot in the '
                                        'wrench distribution (N)', low=0.0, high=1000.0)
    ankle_damping_gain: float = parameter(0.015, 'foot damping: ankle roll and pitch admittance '
                                          'on the torque error (rad/(N m s))', low=0.0,
                                          high=1.0)
    ankle_damping_single_support_gain: float = parameter(
        0.01, 'foot damping of the only supporting foot (rad/(N m s)): a single support needs '
        'a stiffer ankle than two feet settling on uneven ground', low=0.0, high=1.0)
    ankle_damping_rate_limit: float = parameter(1.0, 'largest ankle offset speed (rad/s)',
                                                low=0.001, high=10.0)
    ankle_damping_angle_limit: float = parameter(0.3, 'largest ankle offset (rad)', low=0.0,
                                                 high=0.6)
    ankle_spring_time_constant: float = parameter(1.0, 'weak spring of the ankle offsets back to '
                                                  'nominal (s)', low=0.01, high=1000.0)
    ground_conformance: bool = parameter(
        True, 'in single support the loaded sole\'s tilt beyond a deadband becomes its '
        'target\'s tilt, so the ankle takes the ground\'s tilt and the body stays upright on a '
        'tile edge (biped_mpc.balance.ground_conformance)')
    ground_conformance_deadband: float = parameter(
        0.035, 'sole tilt the ground conformance leaves alone (rad)', low=0.0, high=0.5)
    ground_conformance_time_constant: float = parameter(
        0.04, 'lag of the ground conformance (s)', low=0.001, high=10.0)
    ground_conformance_angle_limit: float = parameter(
        0.3, 'largest ground conformance offset per axis (rad)', low=0.0, high=0.6)
    partial_foothold: bool = parameter(
        False, 'a loaded sole seen rotating about a line under it (a tile edge) is cut along '
        'that line and the stabilizer keeps its CoP on the side that has ground '
        '(biped_mpc.balance.partial_foothold)')
    partial_foothold_rotation_threshold: float = parameter(
        0.5, 'sole angular velocity about a horizontal axis that counts as rotating (rad/s)',
        low=0.01, high=100.0)
    partial_foothold_detection_time: float = parameter(
        0.04, 'time the rotation must last before the sole is cut (s)', low=0.0, high=1.0)
    partial_foothold_min_force: float = parameter(
        50.0, 'normal force below which a sole is neither cut nor proves ground (N)', low=0.0,
        high=1e4)
    partial_foothold_min_area_fraction: float = parameter(
        0.2, 'smallest foothold a cut may leave, as a share of the sole', low=0.0, high=1.0)
    partial_foothold_restore_distance: float = parameter(
        0.01, 'a CoP measured this far beyond a cut removes it (m)', low=0.0, high=0.2)
    lift_off_gate: bool = parameter(
        False, 'a foot the plan lifts stays on the ground while the robot stands on it (most '
        'of the load on it, the DCM over it), so a robot pushed onto its stance foot is not '
        'dropped by that foot\'s swing (biped_mpc.balance.lift_off_gate)')
    lift_off_gate_load_share: float = parameter(
        0.75, 'share of both feet\'s normal load on the lifting foot above which it stays down',
        low=0.5, high=1.0)
    lift_off_gate_dcm_margin: float = parameter(
        0.0, 'the DCM may be this far outside the lifting sole for a hold (m)', low=-0.05,
        high=0.2)
    lift_off_gate_max_hold: float = parameter(
        0.3, 'longest hold of one swing (s): then the plan lifts the foot', low=0.0, high=1.0)
    force_difference_gain: float = parameter(1e-4, 'foot force difference admittance '
                                             '(m/(N s))', low=0.0, high=0.01)
    force_difference_leak_rate: float = parameter(0.1, 'leak of the feet height difference '
                                                  '(1/s)', low=0.0, high=100.0)
    force_difference_max_offset: float = parameter(0.05, 'largest feet height difference (m)',
                                                   low=0.0, high=0.3)
    force_difference_swing_return_rate: float = parameter(
        10.0, "rate at which a swinging foot's force difference offset returns to zero, so "
        'that it lands where planned (1/s); 0: it keeps its offset', low=0.0, high=1000.0)
    vertical_drift_frequency: float = parameter(1.0, 'vertical drift compensation rate (1/s)',
                                                low=0.0, high=50.0)
    vertical_drift_max_offset: float = parameter(0.05, 'largest common feet height offset (m)',
                                                 low=0.0, high=0.3)
    touchdown_on_force: float = parameter(50.0, 'normal force above which a foot touches down '
                                          '(N)', low=0.1, high=5000.0)
    touchdown_off_force: float = parameter(25.0, 'normal force below which a foot has lifted '
                                           '(N), below touchdown_on_force', low=0.0,
                                           high=5000.0)
    touchdown_dwell_time: float = parameter(0.01, 'time a force crossing must hold to count (s)',
                                            low=0.0, high=1.0)
    touchdown_gate_phase: float = parameter(0.5, 'share of the swing after which a touchdown is '
                                            'accepted (1)', low=0.0, high=1.0)
    touchdown_gate_distance: float = parameter(0.05, 'largest horizontal distance of the foot '
                                               'from its landing point for a touchdown (m)',
                                               low=0.001, high=1.0)
    touchdown_gate_follows_plan: bool = parameter(
        True, "the gate's landing point and time follow the plan while the foot swings (a step "
        'adjustment moves them); false: the landing planned at lift-off, and a foot landing '
        'where an adjusted step put it more than touchdown_gate_distance from that point is '
        'never confirmed')
    touchdown_gate_from_stance: bool = parameter(
        False, 'the distance gate measures the step: the landing foot from the measured stance '
        "foot against the plan's landing from the plan's stance foot, so a robot whose feet "
        'drifted from a blind plan still has its touchdowns confirmed; false: the distance from '
        "the plan's landing point in the world")
    touchdown_gate_needs_other_foot: bool = parameter(
        False, 'the distance gate refuses a foot only while the other foot is in contact: past '
        'its planned landing a loaded foot is confirmed wherever it stands when the robot has no '
        'other foot down; false: a foot off its plan is refused whatever holds the robot')
    stabilizer_planned_support: bool = parameter(
        True, 'the stabilizer distributes the wrench, damps the ankles and levels the feet '
        'on the feet the plan has on the ground (Kajita), not only on detected contacts: a '
        'landed foot hovering over a lower tile is pressed down by the force difference')
    contact_aware_landing: bool = parameter(False, 'an early contact stops the swing foot, a late '
                                            'one makes it keep descending')
    landing_descent_speed: float = parameter(0.15, 'descent speed of a late swing foot seeking '
                                             'the ground (m/s)', low=0.01, high=1.0)
    landing_max_extra_depth: float = parameter(0.06, 'deepest search below the planned landing '
                                               'height (m)', low=0.0, high=0.3)
    landing_max_lead: float = parameter(0.003, 'largest distance a seeking swing foot target '
                                        'runs below the measured sole (m)', low=0.0, high=0.3)
    landing_seek: bool = parameter(
        True, 'with contact_aware_landing: a swing foot without contact at its planned landing '
        'descends until it meets the ground (false: it ends its planned swing, and only a '
        'sole that touches early is held where it touches)')

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
        if self.touchdown_off_force >= self.touchdown_on_force:
            raise ConfigError(f'WalkingControllerParams.touchdown_off_force must be below '
                              f'touchdown_on_force = {self.touchdown_on_force!r} N, got '
                              f'{self.touchdown_off_force!r}')
        if 2.0 * self.cop_margin >= min(self.sole_length, self.sole_width):
            raise ConfigError(f'WalkingControllerParams.cop_margin must be below half the sole '
                              f'width, got {self.cop_margin!r}')
        for name, kind in (('mpc', MpcParams), ('estimator', EstimatorParams)):
            if not isinstance(getattr(self, name), kind):
                raise ConfigError(f'WalkingControllerParams.{name} must be a {kind.__name__}, '
                                  f'got {type(getattr(self, name)).__name__}')
