"""The stabilizer in the controller's cycle: F/T wrenches, contacts, landing, target offsets.

The walking controller (biped_mpc.walking_controller) calls, every control period,

1. sense: each ankle F/T reading (what a real sensor gives: the wrench of the foot on the leg
   in the sensor frame) becomes the ground reaction about the sole centre with the foot's
   weight and inertia removed (ft_filter, the foot acceleration from the second difference of
   the measured sole positions), low-passed; the touchdown detectors turn the normal forces
   into contact states, gated by the plan's swing (late in the swing, near the landing
   point); the filtered centre of pressure of the feet in contact is the measured ZMP;
2. update: the Stabilizer (DCM feedback at full gain around the MPC's commanded state,
   wrench distribution, foot damping, foot force difference, vertical drift) and the
   contact-aware landing (swing_landing) turn the IK targets of the MPC into stabilized ones:
   sole roll and pitch offsets, sole height offsets, a swing foot that stops where it met the
   ground or keeps descending after its planned landing, and the pelvis moved by the COM
   admittance (measured - desired ZMP).

The joint servos stay stiff: only the references move.
"""
import collections
from dataclasses import dataclass, replace
import math
from typing import Optional, Sequence, Tuple

import numpy as np

from biped_mpc.balance.dcm_feedback import DcmFeedbackParams
from biped_mpc.balance.foot_damping import FootDampingParams
from biped_mpc.balance.foot_force_difference import FootForceDifferenceParams
from biped_mpc.balance.ft_filter import cop_of_feet, FootWrenchFilter, FtFilterParams
from biped_mpc.balance.ground_conformance import GroundConformance, GroundConformanceParams
from biped_mpc.balance.hip_strategy import HipStrategy, HipStrategyParams
from biped_mpc.balance.lift_off_gate import LiftOffGate, LiftOffGateParams
from biped_mpc.balance.partial_foothold import PartialFoothold, PartialFootholdParams
from biped_mpc.balance.stabilizer import (
    Stabilizer, StabilizerMeasurement, StabilizerOutput, StabilizerParams, StabilizerReference)
from biped_mpc.balance.swing_landing import (
    FAILED, LANDED, SEEKING, SwingLanding, SwingLandingParams, SwingLandingResult)
from biped_mpc.balance.touchdown_detector import TouchdownDetector, TouchdownParams
from biped_mpc.balance.vertical_drift import VerticalDriftParams
from biped_mpc.balance.wrench_distribution import WrenchDistributionParams
from biped_mpc.ik_targets import IkTargets
from biped_mpc.stance_feet import on_support
from biped_planner.footsteps import SIDE_NAMES
from biped_planner.landing_hold import LANDING_NONE
from biped_planner.rotations import yaw_of_matrix
from biped_planner.sides import RIGHT, SIDES

PLANNED_SUPPORT = 'support'


def landing_report(modes: Sequence[str], depths) -> Tuple[list, list]:
    """(left, right) landing modes and search depths in the words of the plan's landing hold
    (biped_planner.landing_hold): a foot the plan has on the ground is 'none' there."""
    return ([LANDING_NONE if mode == PLANNED_SUPPORT else str(mode) for mode in modes],
            [float(depth) for depth in depths])


@dataclass(frozen=True)
class BalanceLoopParams:
    """Parameters of the balance loop (the controller builds them from its flat fields).

    :param stabilizer: the Stabilizer's modules
    :param ft: foot below the sensor and the wrench low-pass
    :param touchdown: contact thresholds and gates
    :param landing: descent after a late planned landing
    :param ft_sensor_height: F/T sensor origin above the sole centre, along the sole z (m)
    :param contact_aware_landing: stop early feet, lower late ones
    :param gate_follows_plan: a swing's landing point and time (the touchdown gate's, the
        landing logic's) follow the plan each cycle; false: fixed at lift-off
    :param gate_from_stance: the distance gate compares the step (landing foot - measured
        stance foot) with the plan's (landing point - planned stance foot); false: the foot
        with the landing point in the world
    :param gate_needs_other_foot: the distance gate refuses a foot only while the other foot
        is in contact: past its planned landing a loaded foot is confirmed wherever it stands
        when nothing else holds the robot; false: refused as long as it is off its plan
    :param com_admittance: pelvis target speed per metre of measured - desired ZMP (1/s)
    :param com_admittance_time_constant: leak of that offset (s)
    :param com_admittance_limit: largest offset per axis (m)
    :param hip: the hip strategy's trunk swing (its gain 0: none)
    :param ground_conformance: loaded soles take the ground's tilt (ground_conformance)
    :param conformance: its deadband, lag and limit
    :param partial_foothold: a sole seen rotating about a line under it is cut there, and
        the stabilizer keeps the CoP on the side that has ground (partial_foothold)
    :param foothold: its thresholds
    :param lift_off_gate: a foot the plan lifts stays down while the robot stands on it
        (lift_off_gate; it reads the plan's supports, so it acts only with the stabilizer's
        planned support)
    :param lift_gate: its conditions and longest hold
    """

    stabilizer: StabilizerParams
    ft: FtFilterParams
    touchdown: TouchdownParams
    landing: SwingLandingParams
    ft_sensor_height: float = 0.04
    contact_aware_landing: bool = True
    gate_follows_plan: bool = True
    gate_from_stance: bool = False
    gate_needs_other_foot: bool = False
    com_admittance: float = 0.0
    com_admittance_time_constant: float = 1.0
    com_admittance_limit: float = 0.03
    hip: HipStrategyParams = HipStrategyParams()
    ground_conformance: bool = True
    conformance: GroundConformanceParams = GroundConformanceParams()
    partial_foothold: bool = False
    foothold: PartialFootholdParams = PartialFootholdParams()
    lift_off_gate: bool = False
    lift_gate: LiftOffGateParams = LiftOffGateParams()

    @classmethod
    def from_controller(cls, params, mass: float, com_height: float) -> 'BalanceLoopParams':
        """The loop's parameters from the controller's flat fields.

        :param params: biped_mpc.controller_params.WalkingControllerParams (duck typed)
        :param mass: total mass of the robot (kg)
        :param com_height: LIPM centre-of-mass height (m)
        :return: the parameters
        """
        p = params
        damping = FootDampingParams(
            roll_gain=p.ankle_damping_gain, pitch_gain=p.ankle_damping_gain,
            single_support_gain=p.ankle_damping_single_support_gain,
            spring_time_constant=p.ankle_spring_time_constant,
            rate_limit=p.ankle_damping_rate_limit, angle_limit=p.ankle_damping_angle_limit)
        stabilizer = StabilizerParams(
            mass=mass,
            dcm=DcmFeedbackParams(
                com_height=com_height, proportional_gain=p.dcm_gain,
                integral_gain=p.dcm_integral_gain,
                integral_time_constant=p.dcm_integral_time_constant,
                integral_limit=p.dcm_integral_limit),
            distribution=WrenchDistributionParams(
                friction=p.wrench_friction, min_force=p.wrench_min_force,
                sole_length=p.sole_length, sole_width=p.sole_width, cop_margin=p.cop_margin),
            damping=damping,
            force_difference=FootForceDifferenceParams(
                gain=p.force_difference_gain, leak_rate=p.force_difference_leak_rate,
                max_offset=p.force_difference_max_offset,
                swing_return_rate=p.force_difference_swing_return_rate),
            vertical_drift=VerticalDriftParams(frequency=p.vertical_drift_frequency,
                                               max_offset=p.vertical_drift_max_offset))
        return cls(
            stabilizer=stabilizer,
            ft=FtFilterParams(foot_mass=p.foot_mass, foot_com=(0.0, 0.0, p.foot_com_height),
                              cutoff_frequency=p.ft_cutoff_frequency),
            touchdown=TouchdownParams(
                on_force=p.touchdown_on_force, off_force=p.touchdown_off_force,
                dwell_time=p.touchdown_dwell_time, gate_phase=p.touchdown_gate_phase,
                gate_distance=p.touchdown_gate_distance),
            landing=SwingLandingParams(descent_speed=p.landing_descent_speed,
                                       max_extra_depth=p.landing_max_extra_depth,
                                       max_lead=p.landing_max_lead, seek=p.landing_seek),
            ft_sensor_height=p.ft_sensor_height, contact_aware_landing=p.contact_aware_landing,
            gate_follows_plan=p.touchdown_gate_follows_plan,
            gate_from_stance=p.touchdown_gate_from_stance,
            gate_needs_other_foot=p.touchdown_gate_needs_other_foot,
            com_admittance=p.com_admittance,
            com_admittance_time_constant=p.com_admittance_time_constant,
            com_admittance_limit=p.com_admittance_limit,
            hip=HipStrategyParams(
                gain=p.hip_strategy_gain, mass=mass, inertia=p.hip_strategy_inertia,
                return_frequency=p.hip_strategy_return_frequency,
                rate_limit=p.hip_strategy_rate_limit, angle_limit=p.hip_strategy_angle_limit),
            ground_conformance=p.ground_conformance,
            conformance=GroundConformanceParams(
                deadband=p.ground_conformance_deadband,
                time_constant=p.ground_conformance_time_constant,
                angle_limit=p.ground_conformance_angle_limit),
            partial_foothold=p.partial_foothold,
            foothold=PartialFootholdParams(
                sole_length=p.sole_length, sole_width=p.sole_width,
                rotation_threshold=p.partial_foothold_rotation_threshold,
                detection_time=p.partial_foothold_detection_time,
                min_force=p.partial_foothold_min_force,
                min_area_fraction=p.partial_foothold_min_area_fraction,
                restore_distance=p.partial_foothold_restore_distance),
            lift_off_gate=p.lift_off_gate,
            lift_gate=LiftOffGateParams(
                load_share=p.lift_off_gate_load_share, dcm_margin=p.lift_off_gate_dcm_margin,
                max_hold=p.lift_off_gate_max_hold, sole_length=p.sole_length,
                sole_width=p.sole_width))


@dataclass(frozen=True)
class SensedFeet:
    """The feet as the balance loop measures them.

    :param wrenches: (left, right) filtered ground reactions (ft_filter.FootWrench)
    :param contacts: (left, right) touchdown detector states
    :param zmp: (2,) filtered CoP of the feet in contact (m), NaN when none is
    """

    wrenches: tuple
    contacts: tuple
    zmp: np.ndarray


@dataclass(frozen=True)
class BalanceResult:
    """The stabilized IK targets and what the node can publish about them.

    :param targets: the IK targets with the offsets applied
    :param stabilizer: the Stabilizer's output of the cycle
    :param landing_modes: (left, right) swing_landing mode, or 'support'
    :param landing_depths: (left, right) how far below its planned landing height a late swing
        foot's target has descended (m), 0 for a foot not seeking
    :param conformance: (2, 2) roll and pitch offsets of the sole targets for the ground's
        tilt (rad), added to the stabilizer's foot damping offsets in the targets
    :param lift_held: (left, right) a foot the plan lifts kept on the ground (lift_off_gate)
    """

    targets: IkTargets
    stabilizer: StabilizerOutput
    landing_modes: tuple
    conformance: np.ndarray
    landing_depths: tuple = (0.0, 0.0)
    lift_held: tuple = (False, False)


# A loaded foot refused by the detector's distance gate this long after its planned landing is
# reported: the swing then never ends and the foot is never latched (docs/controller_notes.md,
# "Touchdowns that are never confirmed"); a late landing of a normal step clears in a cycle or
# two.
UNCONFIRMED_REPORT_TIME = 0.2  # s


class _Swing:
    """One foot's planned swing: lift-off time, landing time and point (world)."""

    def __init__(self, start: float, landing_time: float, landing_point: np.ndarray) -> None:
        self.start = start
        self.landing_time = landing_time
        self.landing_point = landing_point
        self.lifted = False  # the detector saw the foot leave the ground: contacts now count
        self.refused_since: Optional[float] = None  # loaded but gated, after the landing time
        self.reported = False

    def follow(self, landing_time: float, landing_point: np.ndarray) -> None:
        """The plan moved the landing (x, y) and its time; the height stays the lift-off's."""
        self.landing_time = landing_time
        self.landing_point[:2] = landing_point[:2]

    def phase(self, t: float) -> float:
        duration = self.landing_time - self.start
        return 1.0 if duration <= 0.0 else min(max((t - self.start) / duration, 0.0), 1.0)


def planned_landing(window, side: int, t: float, dt: float) -> Optional[tuple]:
    """The next planned landing of a foot in a reference window sampled at t, t + dt, ...

    :param window: reference window (duck typed: support (N,), left_foot, right_foot (N, 3))
    :param side: LEFT or RIGHT
    :param t: time of sample 0 (s)
    :param dt: sample period (s)
    :return: (landing time (s), landing point (3,): x, y (m), height above the stance soles
        (m)), or None when the window has no landing of this foot
    """
    support = np.asarray(window.support)
    feet = np.asarray(window.left_foot if side == 0 else window.right_foot, dtype=float)
    for k in range(1, support.shape[0]):
        if on_support(side, int(support[k])):
            return t + k * dt, feet[k].copy()
    return None


class BalanceLoop:
    """Sense the feet, then stabilize the MPC's IK targets (see the module docstring).

    :param params: the loop's parameters
    """

    def __init__(self, params: BalanceLoopParams) -> None:
        self.params = params
        self.stabilizer = Stabilizer(params.stabilizer)
        self.hip = HipStrategy(params.hip)
        self.conformance = GroundConformance(params.conformance)
        self.lift_gate = LiftOffGate(params.lift_gate)
        self._filters = tuple(FootWrenchFilter(params.ft) for _ in SIDES)
        self._detectors = tuple(TouchdownDetector(params.touchdown) for _ in SIDES)
        self._landings = tuple(SwingLanding(params.landing) for _ in SIDES)
        self.footholds = tuple(PartialFoothold(params.foothold) for _ in SIDES)
        self._sensor_offset = np.array([0.0, 0.0, params.ft_sensor_height])
        self.reset(None)

    def reset(self, soles: Optional[tuple]) -> None:
        """Standing on both feet: contacts on, integrators and filters zero.

        :param soles: ((position, rotation) left, same right) measured, or None
        """
        self.stabilizer.reset()
        self.hip.reset()
        self.conformance.reset()
        self.lift_gate.reset()
        for side in SIDES:
            self.footholds[side].reset()
            self._filters[side].reset()
            self._detectors[side].reset(True)
        self._swings = [None, None]
        self._active = [False, False]  # the landing logic owns the foot's target
        self._history = [[], []]  # last two measured sole positions, for the acceleration
        self._com_offset = np.zeros(2)
        self._last_t = None
        self._events = collections.deque(maxlen=16)  # kept short when no one takes them
        if soles is not None:
            self._history = [[soles[side][0].copy()] for side in SIDES]

    @property
    def contacts(self) -> tuple:
        """(left, right) contact states of the touchdown detectors."""
        return tuple(d.in_contact for d in self._detectors)

    def sense(self, t: float, dt: float, foot_wrenches: np.ndarray, soles: tuple,
              window) -> SensedFeet:
        """Filter the F/T readings, track the plan's swings, update the contact states.

        :param t: time (s)
        :param dt: control period (s)
        :param foot_wrenches: (2, 6) sensor-frame force and torque of the foot on the leg
        :param soles: measured ((position, rotation) left, same right), world
        :param window: the reference window of the cycle, or None
        :return: the filtered wrenches, contacts and measured ZMP
        """
        wrenches = []
        for side in SIDES:
            position, rotation = soles[side]
            history = self._history[side]
            acceleration = np.zeros(3)
            if len(history) >= 2:
                acceleration = (position - 2.0 * history[-1] + history[-2]) / (dt * dt)
            self._history[side] = (history + [position.copy()])[-2:]
            sensor = position + rotation @ self._sensor_offset
            wrenches.append(self._filters[side].update(
                dt, foot_wrenches[side, :3], foot_wrenches[side, 3:], sensor, rotation, position,
                rotation, acceleration))
        if window is not None:
            self._track_swings(t, dt, window, soles)
        for side in SIDES:
            swing = self._swings[side]
            phase = distance = None
            if swing is not None:
                phase = swing.phase(t)
                distance = self._gate_distance(side, swing, soles, window)
                if self._landings[side].mode == SEEKING:
                    # past its planned landing the foot is wherever it met the ground: a foot
                    # stopped 9 cm short by a higher tile's edge was refused for ever, and a
                    # plan holding the single support for it waited for nothing
                    distance = None
                if self._last_foot_down(t, side, swing):
                    distance = None
            state = self._detectors[side].update(t, wrenches[side].normal_force, phase, distance)
            if swing is not None:
                self._watch_refusal(t, side, swing, state, distance)
        contacts = self.contacts
        for side in SIDES:
            if self._swings[side] is not None and not contacts[side]:
                self._swings[side].lifted = True
        if self.params.partial_foothold:
            for side in SIDES:
                wrench = wrenches[side]
                force = wrench.normal_force
                cop = None if force <= 0.0 else (-wrench.local_torque[1] / force,
                                                 wrench.local_torque[0] / force)
                self.footholds[side].update(dt, contacts[side], force, soles[side][1], cop)
        touching = [side for side in SIDES if contacts[side]]
        zmp = np.full(2, np.nan)
        if touching:
            point = np.mean([soles[side][0] for side in touching], axis=0)
            zmp = cop_of_feet([wrenches[s].force for s in touching],
                              [wrenches[s].torque for s in touching],
                              [soles[s][0] for s in touching], point,
                              min_force=self.params.ft.cop_min_force)[:2]
        return SensedFeet(tuple(wrenches), contacts, zmp)

    def _last_foot_down(self, t: float, side: int, swing: '_Swing') -> bool:
        """The foot is past its planned landing and the other foot reads no contact: the robot
        can stand on nothing else, so the distance gate does not apply (with
        gate_needs_other_foot). A foot refused there left the controller with no latched foot
        until the fall (docs/controller_notes.md, "Touchdowns that are never confirmed")."""
        return (self.params.gate_needs_other_foot and t >= swing.landing_time
                and not self._detectors[1 - side].in_contact)

    def _gate_distance(self, side: int, swing: '_Swing', soles: tuple, window) -> float:
        """How far the foot is from its planned landing, for the touchdown gate (m).

        From the stance foot: the blind plan knows the ground no better than the feet do, so a
        robot that slid or was kicked a few centimetres off its plan lands every later step that
        far from the plan's points, and the world distance refused each of them for ever
        (docs/controller_notes.md, "What starts the falls on the tiles now").
        """
        position = soles[side][0][:2]
        if not self.params.gate_from_stance or window is None:
            return float(np.linalg.norm(position - swing.landing_point[:2]))
        other = 1 - side
        planned_stance = np.asarray(window.right_foot if other == RIGHT else window.left_foot,
                                    dtype=float)[0, :2]
        step = position - soles[other][0][:2]
        planned_step = swing.landing_point[:2] - planned_stance
        return float(np.linalg.norm(step - planned_step))

    def take_events(self) -> list:
        """The warnings since the last call (a loaded foot whose touchdown stays unconfirmed)."""
        events = list(self._events)
        self._events.clear()
        return events

    def _watch_refusal(self, t: float, side: int, swing: '_Swing', state, distance) -> None:
        """Report once per swing a loaded foot the distance gate keeps refusing after landing."""
        if not (state.gated and t >= swing.landing_time):
            swing.refused_since = None
            return
        if swing.refused_since is None:
            swing.refused_since = t
        if swing.reported or t - swing.refused_since < UNCONFIRMED_REPORT_TIME - 1e-9:
            return
        swing.reported = True
        where = ('its planned landing' if self.params.gate_follows_plan
                 else 'the landing planned at its lift-off')
        if self.params.gate_from_stance:
            where += ' (from the stance foot)'
        self._events.append(
            f'{SIDE_NAMES[side]} foot: {state.normal_force:.0f} N on it '
            f'{t - swing.landing_time:.2f} s after its planned landing, but {distance:.3f} m from '
            f'{where} (touchdown_gate_distance '
            f'{self.params.touchdown.gate_distance:.3f} m): the touchdown is not confirmed and '
            f'the foot is not latched')

    def _track_swings(self, t: float, dt: float, window, soles: tuple) -> None:
        """Start a swing when the plan lifts a foot; end it when the foot is down again."""
        support_now = int(np.asarray(window.support)[0])
        for side in SIDES:
            swinging = not on_support(side, support_now)
            swing = self._swings[side]
            if swinging and swing is None:
                landing = planned_landing(window, side, t, dt)
                if landing is None:
                    continue
                landing_time, point = landing
                ground = soles[1 - side][0][2]
                point = np.array([point[0], point[1], ground + point[2]])
                self._swings[side] = _Swing(t, landing_time, point)
                self._landings[side].reset(landing_time, float(point[2]))
                self._active[side] = True
            elif swinging and swing is not None and self.params.gate_follows_plan:
                # A step adjustment moves the landing of the swing under way: the gate and the
                # landing logic take the plan as it is now. Held at the lift-off's, a foot
                # landing where an adjusted step put it, more than the gate distance from the
                # old point, was never confirmed, and the walk went on with no foot latched.
                landing = planned_landing(window, side, t, dt)
                if landing is not None:
                    swing.follow(*landing)
                    self._landings[side].retime(landing[0])
            elif not swinging and swing is not None and self._detectors[side].in_contact:
                self._swings[side] = None
                self._active[side] = False

    def update(self, t: float, dt: float, targets: IkTargets, sensed: SensedFeet,
               soles: tuple, pelvis: np.ndarray, reference: StabilizerReference,
               com: np.ndarray, dcm: np.ndarray,
               planned_feet: Optional[tuple] = None) -> BalanceResult:
        """Stabilize the IK targets of the cycle.

        :param t: time (s)
        :param dt: control period (s)
        :param targets: the MPC's IK targets
        :param sensed: the feet of this cycle (sense)
        :param soles: measured ((position, rotation) left, same right), world
        :param pelvis: (3,) measured pelvis position (m)
        :param reference: the MPC's ZMP and DCM (commanded state)
        :param com: (3,) estimated centre of mass (m)
        :param dcm: (2,) estimated DCM (m)
        :param planned_feet: (left, right) feet the plan has on the ground, for the
            stabilizer's support (StabilizerMeasurement.planned_feet); None: the detected ones
        :return: the stabilized targets and the diagnostics
        """
        feet = [targets.left_foot.copy(), targets.right_foot.copy()]
        positions = np.array([soles[side][0] for side in SIDES])
        mean_target = float(np.mean([feet[0][2], feet[1][2]]) - targets.pelvis[2])
        measured_mean = float(np.mean(positions[:, 2]) - pelvis[2])
        reference = replace(reference, mean_sole_height=mean_target)
        measurement = StabilizerMeasurement(
            com, dcm, sensed.wrenches, sensed.contacts, positions,
            np.array([yaw_of_matrix(soles[side][1]) for side in SIDES]), measured_mean,
            planned_feet,
            tuple(list(f.cuts) for f in self.footholds) if self.params.partial_foothold
            else None)
        output = self.stabilizer.update(dt, reference, measurement)
        modes = [PLANNED_SUPPORT, PLANNED_SUPPORT]
        depths = [0.0, 0.0]
        for side in SIDES:
            feet[side][2] += output.vertical_offsets[side]
            if self._active[side] and self.params.contact_aware_landing:
                landing = self._land(t, dt, side, feet[side], sensed, soles)
                modes[side], depths[side] = landing.mode, landing.extra_depth
        held = [False, False]
        if self.params.lift_off_gate and planned_feet is not None:
            held = self.lift_gate.update(
                dt, [not on for on in planned_feet], [w.normal_force for w in sensed.wrenches],
                dcm, positions, measurement.feet_yaws)
            for side in SIDES:
                if held[side]:
                    feet[side][2] = positions[side][2]  # at the ground it stands on
        pelvis_target = targets.pelvis.copy()
        pelvis_target[:2] += self._admittance(dt, sensed.zmp, output.zmp)
        # In single support only: on two feet an excess comes from soles resting on tile edges,
        # which the foot damping settles; a trunk swing then rocked a robot standing on the
        # paper's tiles off them (100 cm^2 seed 2).
        supports = planned_feet if planned_feet is not None else sensed.contacts
        single = sum(bool(c) for c in supports) == 1
        trunk = self.hip.update(dt, output.zmp_excess if single else np.zeros(2), targets.yaw)
        conformance = np.zeros((2, 2))
        if self.params.ground_conformance:
            # In single support only, as the trunk swing: on two feet the foot damping settles
            # soles across tile edges, and the conformance let a robot standing on the tiles
            # creep (2.4 cm in 5 s, 100 cm^2 seed 2).
            loaded = [single and bool(supports[side]) and sensed.contacts[side]
                      for side in SIDES]
            conformance = self.conformance.update(dt, [soles[side][1] for side in SIDES],
                                                  loaded)
        stabilized = IkTargets(pelvis_target, feet[0], feet[1], targets.yaw,
                               output.ankle_offsets + conformance, trunk)
        return BalanceResult(stabilized, output, tuple(modes), conformance, tuple(depths),
                             tuple(held))

    def _land(self, t: float, dt: float, side: int, foot: np.ndarray, sensed: SensedFeet,
              soles: tuple) -> SwingLandingResult:
        """Contact-aware end of a swing on the foot target (in place); returns the landing."""
        swing = self._swings[side]
        touching = swing.lifted and (sensed.wrenches[side].normal_force
                                     > self.params.touchdown.off_force)
        landing = self._landings[side].update(t, dt, float(foot[2]),
                                              sensed.contacts[side] and swing.lifted,
                                              float(soles[side][0][2]), touching)
        if landing.mode in (LANDED, SEEKING, FAILED):
            # The height only: across the plan the foot goes on to its footstep as without
            # the landing logic (a landed foot frozen where its lagging target was stood 1-3
            # cm short of it and slid back).
            foot[2] = landing.height
        return landing

    def _admittance(self, dt: float, measured_zmp: np.ndarray,
                    desired_zmp: np.ndarray) -> np.ndarray:
        """COM admittance: the pelvis moves with the ZMP error, leaking back to zero."""
        p = self.params
        if p.com_admittance <= 0.0:
            return self._com_offset
        error = measured_zmp - desired_zmp
        decay = math.exp(-dt / p.com_admittance_time_constant)
        drive = np.zeros(2) if not np.all(np.isfinite(error)) else p.com_admittance * error
        offset = decay * self._com_offset + p.com_admittance_time_constant * (1.0 - decay) * drive
        self._com_offset = np.clip(offset, -p.com_admittance_limit, p.com_admittance_limit)
        return self._com_offset
