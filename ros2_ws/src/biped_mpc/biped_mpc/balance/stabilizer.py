"""One stabilizer cycle between the MPC and the IK: the balance modules wired together."""
from dataclasses import dataclass, field
from typing import Optional, Tuple

import numpy as np

from biped_mpc.balance.dcm_feedback import (
    convex_hull, DcmFeedback, DcmFeedbackParams, rectangle_vertices)
from biped_mpc.balance.foot_damping import FootDamping, FootDampingParams
from biped_mpc.balance.foot_force_difference import (
    FootForceDifference, FootForceDifferenceParams)
from biped_mpc.balance.ft_filter import cop_of_feet, FootWrench
from biped_mpc.balance.partial_foothold import foothold_polygon
from biped_mpc.balance.vertical_drift import VerticalDrift, VerticalDriftParams
from biped_mpc.balance.wrench_distribution import (
    DistributionStatus, WrenchDistributionParams, WrenchDistributor)
from biped_mpc.errors import ConfigError, InputError
from biped_mpc.validation import check_period, finite_array
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.rotations import rotation_z
from biped_planner.sides import LEFT, RIGHT, SIDES, SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT


@dataclass(frozen=True)
class StabilizerParams:
    """The robot's mass and each module's parameters (see Stabilizer)."""

    mass: float = parameter(30.95, 'total mass of the robot (kg)', low=0.1, high=1000.0)
    dcm: DcmFeedbackParams = field(default_factory=DcmFeedbackParams)
    distribution: WrenchDistributionParams = field(default_factory=WrenchDistributionParams)
    damping: FootDampingParams = field(default_factory=FootDampingParams)
    force_difference: FootForceDifferenceParams = field(
        default_factory=FootForceDifferenceParams)
    vertical_drift: VerticalDriftParams = field(default_factory=VerticalDriftParams)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        for name, kind in (('dcm', DcmFeedbackParams),
                           ('distribution', WrenchDistributionParams),
                           ('damping', FootDampingParams),
                           ('force_difference', FootForceDifferenceParams),
                           ('vertical_drift', VerticalDriftParams)):
            if not isinstance(getattr(self, name), kind):
                raise ConfigError(f'StabilizerParams.{name} must be a {kind.__name__}, got '
                                  f'{getattr(self, name)!r}')


@dataclass(frozen=True)
class StabilizerReference:
    """What the MPC asks for this cycle.

    :param zmp: (2,) reference ZMP p_ref (m)
    :param dcm: (2,) reference DCM xi_ref = c_ref + c_ref_dot / omega (m)
    :param mean_sole_height: reference mean sole height relative to the pelvis (m); None
        switches the vertical drift compensation off for the cycle
    """

    zmp: np.ndarray
    dcm: np.ndarray
    mean_sole_height: Optional[float] = None


@dataclass(frozen=True)
class StabilizerMeasurement:
    """What the robot measures this cycle.

    :param com: (3,) estimated centre of mass (m)
    :param dcm: (2,) estimated DCM (m)
    :param wrenches: (left, right) ft_filter.FootWrench of each foot, torques about the sole
        centres
    :param contacts: (left, right) touchdown_detector states
    :param feet_positions: (2, 3) measured sole centres (m)
    :param feet_yaws: (2,) measured sole headings (rad)
    :param mean_sole_height: measured mean sole height relative to the pelvis (m), or None
    :param planned_feet: (left, right) feet the plan has on the ground, or None. When given,
        the support polygon, the wrench distribution, the foot damping and the force
        difference act on these feet (Kajita's and lipm_walking_controller's contact state is
        the plan's): a foot the plan has put down carries its share before its touchdown is
        detected, and the force difference presses a foot that hovers a few millimetres
        above a lower tile onto it. The measured ZMP always comes from the detected contacts.
    """

    com: np.ndarray
    dcm: np.ndarray
    wrenches: Tuple[FootWrench, FootWrench]
    contacts: Tuple[bool, bool]
    feet_positions: np.ndarray
    feet_yaws: np.ndarray
    mean_sole_height: Optional[float] = None
    planned_feet: Optional[Tuple[bool, bool]] = None
    footholds: Optional[Tuple[list, list]] = None


@dataclass(frozen=True)
class StabilizerDiagnostics:
    """What the node can publish about a cycle.

    :param measured_zmp: (2,) CoP of the feet in contact (m); NaN in the air
    :param zmp_error: (2,) desired - measured ZMP (m)
    :param dcm_error: (2,) xi_ref - xi (m)
    :param dcm_integral: (2,) the DCM error integral (m s)
    :param zmp_clamped: the desired ZMP was moved into the support polygon
    :param torque_errors: (2, 2) measured - desired roll, pitch ground torques per side (N m)
    :param force_difference_error: (f_L - f_R) - (f_L_des - f_R_des) (N)
    :param contacts: (left, right) contact states used
    :param in_the_air: no foot in contact: only the DCM feedback ran
    :param distribution_status: the wrench distribution's status (None in the air)
    """

    measured_zmp: np.ndarray
    zmp_error: np.ndarray
    dcm_error: np.ndarray
    dcm_integral: np.ndarray
    zmp_clamped: bool
    torque_errors: np.ndarray
    force_difference_error: float
    contacts: Tuple[bool, bool]
    in_the_air: bool
    distribution_status: Optional[DistributionStatus]


@dataclass(frozen=True)
class StabilizerOutput:
    """The reference modifications for the IK.

    :param zmp: (2,) desired net ZMP (m)
    :param wrenches: (2, 6) desired ground wrench per side, world frame, about the sole centre
    :param local_wrenches: (2, 6) the same in each sole frame
    :param ankle_offsets: (2, 2) roll and pitch offsets of each sole orientation target (rad)
    :param vertical_offsets: (2,) offsets of each sole height target (m)
    :param diagnostics: errors and states of the cycle
    :param zmp_excess: (2,) the DCM feedback's desired ZMP beyond the support polygon: before
        the clamp minus after it (m); zero inside it and in the air
    """

    zmp: np.ndarray
    wrenches: np.ndarray
    local_wrenches: np.ndarray
    ankle_offsets: np.ndarray
    vertical_offsets: np.ndarray
    diagnostics: StabilizerDiagnostics
    zmp_excess: np.ndarray = field(default_factory=lambda: np.zeros(2))


class Stabilizer:
    """DCM feedback -> wrench distribution -> foot damping, force difference, drift.

    Data flow of one control cycle (Kajita 2010; lipm_walking_controller's Stabilizer::run):

    1. upstream, per foot: ft_filter.FootWrenchFilter (inertia removed, low-pass) and
       touchdown_detector.TouchdownDetector (contact states); swing_landing.SwingLanding gives
       the swing foot's height target and the timing events, next to this class;
    2. dcm_feedback: desired ZMP from the DCM error, clamped to the convex hull of the soles
       in contact shrunk by the distribution's cop_margin (its integral held in the air);
    3. desired net wrench of the LIPM through that ZMP: f = m (omega^2 (c - p_d), g), zero
       moment about p_d on the ground (mean height of the soles in contact);
    4. wrench_distribution over the feet in contact (both, one, or none in the air);
    5. foot_damping per foot on the measured - desired sole torques (offsets released when
       the foot is off the ground);
    6. foot_force_difference in double support on the normal forces (a swinging foot's
       offset returns to zero), and vertical_drift on the mean sole height; vertical offsets
       per side = the foot's own offset (+-dz/2 while both support) + the common drift offset.

    The outputs are modifications of the IK's references: the ZMP and wrenches are targets
    (and diagnostics), the ankle and vertical offsets are added to the sole pose targets.
    """

    def __init__(self, params: StabilizerParams = StabilizerParams()) -> None:
        """Create the modules.

        :param params: the robot's mass and the modules' parameters
        """
        self.params = params
        self.dcm_feedback = DcmFeedback(params.dcm)
        self.distributor = WrenchDistributor(params.distribution)
        self.damping = (FootDamping(params.damping), FootDamping(params.damping))
        self.force_difference = FootForceDifference(params.force_difference)
        self.vertical_drift = VerticalDrift(params.vertical_drift)

    def reset(self) -> None:
        """Zero every integrator (DCM integral, ankle and vertical offsets)."""
        self.dcm_feedback.reset()
        for damping in self.damping:
            damping.reset()
        self.force_difference.reset()
        self.vertical_drift.reset()

    def update(self, dt: float, reference: StabilizerReference,
               measurement: StabilizerMeasurement) -> StabilizerOutput:
        """One control cycle.

        :param dt: control period (s), > 0
        :param reference: the MPC's ZMP and DCM references
        :param measurement: estimated state, filtered wrenches, contacts, sole poses
        :return: the reference modifications and the diagnostics
        :raises InputError: for a non-finite or misshaped input or dt <= 0
        """
        check_period(dt)
        com = finite_array('com', measurement.com, (3,))
        positions = finite_array('feet_positions', measurement.feet_positions, (2, 3))
        yaws = finite_array('feet_yaws', measurement.feet_yaws, (2,))
        contacts = tuple(bool(c) for c in measurement.contacts)
        if len(contacts) != 2 or len(measurement.wrenches) != 2:
            raise InputError('contacts and wrenches must have one entry per foot')
        detected = [side for side in SIDES if contacts[side]]
        if measurement.planned_feet is not None:
            if len(measurement.planned_feet) != 2:
                raise InputError('planned_feet must have one entry per foot')
            contacts = tuple(bool(c) for c in measurement.planned_feet)
        touching = [side for side in SIDES if contacts[side]]
        in_the_air = not touching
        rotations = np.array([rotation_z(yaw) for yaw in yaws])
        p = self.params
        polygon = None
        cuts = ([], [])  # of each support sole, those its shrunk foothold still has room for
        if touching:
            corners = []
            for side in touching:
                vertices, cuts[side][:] = self._sole_polygon(
                    positions[side], yaws[side], rotations[side],
                    [] if measurement.footholds is None else measurement.footholds[side])
                corners.append(vertices)
            polygon = convex_hull(np.vstack(corners))
        dcm = self.dcm_feedback.update(dt, reference.dcm, measurement.dcm, reference.zmp,
                                       polygon, in_the_air)

        wrenches, local = np.zeros((2, 6)), np.zeros((2, 6))
        status = None
        measured_zmp = np.full(2, np.nan)
        if touching:
            ground = float(np.mean(positions[touching, 2]))
            point = np.array([dcm.zmp[0], dcm.zmp[1], ground])
            omega_squared = p.dcm.omega ** 2
            force = p.mass * np.array([omega_squared * (com[0] - dcm.zmp[0]),
                                       omega_squared * (com[1] - dcm.zmp[1]), p.dcm.gravity])
            support = (SUPPORT_DOUBLE if len(touching) == 2
                       else SUPPORT_LEFT if touching[0] == LEFT else SUPPORT_RIGHT)
            distribution = self.distributor.update(
                support, force, np.zeros(3), point, positions, rotations, footholds=cuts)
            wrenches, local, status = (distribution.wrenches, distribution.local_wrenches,
                                       distribution.status)
            if detected:
                measured_zmp = cop_of_feet(
                    [measurement.wrenches[s].force for s in detected],
                    [measurement.wrenches[s].torque for s in detected], positions[detected],
                    point)[:2]

        ankle_offsets, torque_errors = np.zeros((2, 2)), np.zeros((2, 2))
        for side in SIDES:
            result = self.damping[side].update(dt, contacts[side], local[side, 3:5],
                                               measurement.wrenches[side].local_torque[:2],
                                               single_support=len(touching) == 1)
            ankle_offsets[side], torque_errors[side] = result.offset, result.torque_error
        double = len(touching) == 2
        difference = self.force_difference.update(
            dt, double, local[:, 2], [measurement.wrenches[LEFT].normal_force,
                                      measurement.wrenches[RIGHT].normal_force],
            swinging=tuple(not contacts[side] for side in SIDES))
        drift_active = double and None not in (reference.mean_sole_height,
                                               measurement.mean_sole_height)
        drift = self.vertical_drift.update(
            dt, drift_active, reference.mean_sole_height if drift_active else 0.0,
            measurement.mean_sole_height if drift_active else 0.0)
        vertical = difference.offsets + drift.offset
        diagnostics = StabilizerDiagnostics(
            measured_zmp, dcm.zmp - measured_zmp, dcm.dcm_error, dcm.integral, dcm.clamped,
            torque_errors, difference.error, tuple(bool(c) for c in measurement.contacts),
            in_the_air, status)
        excess = dcm.unclamped_zmp - dcm.zmp if dcm.clamped else np.zeros(2)
        return StabilizerOutput(dcm.zmp, wrenches, local, ankle_offsets, vertical, diagnostics,
                                excess)

    def _sole_polygon(self, position: np.ndarray, yaw: float, rotation: np.ndarray,
                      foothold_cuts) -> Tuple[np.ndarray, list]:
        """A support sole shrunk by the CoP margin in the ground plane, and the cuts of its
        foothold (partial_foothold) that the shrunk sole keeps."""
        d = self.params.distribution
        if not foothold_cuts:
            shrink = 2.0 * d.cop_margin
            return rectangle_vertices(position, yaw, d.sole_length - shrink,
                                      d.sole_width - shrink), []
        local, used = foothold_polygon(d.sole_length, d.sole_width, foothold_cuts, d.cop_margin)
        return position[:2] + np.asarray(local) @ rotation[:2, :2].T, used
