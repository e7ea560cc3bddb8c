"""The weight-shift trial: proof that a controlled humanoid can step, in joint space only.

Stand, shift the centre of mass over the left foot, lift the right foot, hold it, put it down
and shift back, each phase on a cosine profile, with the leg IK giving the joint setpoints of
every control step. It checks a robot and its simulator settings before any walking controller
runs (biped_sim.other_robots, the COMAN-like robot with its analytic IK).
"""
from dataclasses import dataclass
import math

import numpy as np

from biped_planner.rotations import tilt_of_quaternion

from biped_sim.errors import ConfigError
from biped_sim.sensors import SensorReadings

try:
    import pinocchio as pin
except ImportError as error:  # pragma: no cover - pinocchio is a hard dependency
    raise ImportError('biped_sim.weight_shift_trial needs pinocchio: pip install pin') from error

# Phases of the weight-shift trial, (name, duration (s)): COM over the left foot, right foot up,
# held, down, COM back to the middle, standing still.
WEIGHT_SHIFT_PHASES = (('shift', 3.0), ('lift', 0.5), ('hold', 0.5), ('down', 0.5),
                       ('back', 1.5), ('settle', 0.5))


@dataclass(frozen=True)
class WeightShiftTrial:
    """What a weight-shift trial did (see weight_shift_trial).

    :param start: readings after standing, the reference of the trial.
    :param pelvis_shift: (2,) horizontal pelvis shift that puts the centre of mass over the left
        sole centre (m).
    :param lift_height: height the right foot was lifted to (m).
    :param phases: phase name of each control step.
    :param readings: readings after each control step.
    :param ik_clipped: control steps whose leg IK did not meet its targets.
    """

    start: SensorReadings
    pelvis_shift: np.ndarray
    lift_height: float
    phases: tuple
    readings: tuple
    ik_clipped: int

    def during(self, phase: str) -> list:
        """Return the readings of one phase."""
        return [r for p, r in zip(self.phases, self.readings) if p == phase]

    def max_tilt(self) -> float:
        """Return the largest tilt of the base from upright over the trial (rad)."""
        return max(tilt_of_quaternion(r.base.orientation) for r in self.readings)


def _smooth(u: float) -> float:
    return 0.5 - 0.5 * math.cos(math.pi * min(max(u, 0.0), 1.0))


def _com_over_left_sole(sim, leg_ik, start: SensorReadings) -> np.ndarray:
    """Return the pelvis shift putting the centre of mass over the left sole (Newton, 4 steps).

    The centre of mass is computed with Pinocchio for the leg angles of the IK, the other
    joints at their start angles, an upright pelvis and both soles where they stand.
    """
    model = pin.buildModelFromUrdf(sim.description.urdf_path, pin.JointModelFreeFlyer())
    data = model.createData()
    q_index = [model.joints[model.getJointId(n)].idx_q for n in sim.joint_names]
    q = pin.neutral(model)
    q[q_index] = start.joints.position
    pelvis, left, right = start.base.position, start.left_sole, start.right_sole
    upright = np.eye(3)

    def com(shift):
        solution = leg_ik.solve(pelvis + [shift[0], shift[1], 0.0], upright, left, upright,
                                right, upright)
        q[0:3] = pelvis + [shift[0], shift[1], 0.0]
        q[q_index[:12]] = solution.q
        return pin.centerOfMass(model, data, q)[:2].copy()

    shift, delta = np.zeros(2), 1e-4
    for _ in range(4):
        c = com(shift)
        jacobian = np.column_stack([(com(shift + e) - c) / delta for e in np.eye(2) * delta])
        shift = shift + np.linalg.solve(jacobian, left[:2] - c)
    return shift


def weight_shift_trial(sim, leg_ik, lift_height: float = 0.03, stand_time: float = 0.5,
                       phases=WEIGHT_SHIFT_PHASES) -> WeightShiftTrial:
    """Stand, shift the centre of mass over the left foot, lift the right foot and put it down.

    The proof that a controlled robot can step, in joint space only: the pelvis moves (upright)
    so the centre of mass comes over the left sole centre, the right sole rises straight up by
    lift_height and comes down again, then the pelvis moves back; the leg IK gives the joint
    setpoints of every control step, each phase follows a cosine profile.

    :param sim: a PyBulletBackend (or any backend with reset, step, description, joint_names).
    :param leg_ik: leg IK with solve(pelvis_position, pelvis_rotation, left_position,
        left_rotation, right_position, right_rotation) -> LegIkSolution (biped_mpc.leg_ik or
        biped_mpc.pinocchio_ik), set up for sim.description.
    :param lift_height: how high the right foot rises (m), > 0.
    :param stand_time: standing time before the trial (s), >= 0.
    :param phases: (name, duration (s)) of each phase; names among shift, lift, hold, down,
        back and settle.
    :return: the trial's readings.
    :raises ConfigError: for a bad lift height, stand time or phase.
    """
    if not (math.isfinite(lift_height) and lift_height > 0.0):
        raise ConfigError('lift_height = %r m must be finite and > 0' % (lift_height,))
    if not (math.isfinite(stand_time) and stand_time >= 0.0):
        raise ConfigError('stand_time = %r s must be finite and >= 0' % (stand_time,))
    names = {name for name, _ in WEIGHT_SHIFT_PHASES}
    for name, duration in phases:
        if name not in names or not (math.isfinite(duration) and duration > 0.0):
            raise ConfigError('phase (%r, %r) must name one of %s with a duration > 0 s'
                              % (name, duration, sorted(names)))
    period = sim.time_step * sim.config.control_substeps
    nominal = sim.description.nominal_leg_positions()
    start = sim.reset()
    for _ in range(int(round(stand_time / period))):
        start = sim.step(nominal)
    shift = _com_over_left_sole(sim, leg_ik, start)
    pelvis, left, right = start.base.position, start.left_sole, start.right_sole
    upright = np.eye(3)
    names, readings, clipped = [], [], 0
    for name, duration in phases:
        n = max(1, int(round(duration / period)))
        for k in range(n):
            u = _smooth((k + 1) / n)
            moved = {'shift': u, 'back': 1.0 - u, 'settle': 0.0}.get(name, 1.0)
            lifted = {'lift': u, 'hold': 1.0, 'down': 1.0 - u}.get(name, 0.0) * lift_height
            solution = leg_ik.solve(pelvis + [moved * shift[0], moved * shift[1], 0.0], upright,
                                    left, upright, right + [0.0, 0.0, lifted], upright)
            clipped += 0 if solution.reachable else 1
            names.append(name)
            readings.append(sim.step(solution.q))
    return WeightShiftTrial(start, shift, float(lift_height), tuple(names), tuple(readings),
                            clipped)
