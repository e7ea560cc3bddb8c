"""The per-cycle record of a humanoid's closed-loop run, and when the humanoid has fallen.

Each cycle of :class:`biped_sim.closed_loop.ClosedLoopRunner` on a simulated humanoid (PyBullet
or the model-plant backend) is logged so that tests and experiments can assert physical facts:
base pose, centre of mass, measured and reference ZMP, scaled ZMP bounds, feet and contacts,
solver times and statuses, the wall time split between references, controller and physics.
The robot has fallen when its pelvis is less than fall_height above its lowest sole or tilted
beyond fall_tilt.
"""
from dataclasses import dataclass
import math

import numpy as np

from biped_mpc.balance.dcm_feedback import project_into_polygon, rectangle_vertices
from biped_planner.rotations import tilt_of_quaternion


@dataclass
class RunLog:
    """One record per control cycle (K cycles), world frame, SI units.

    :param t: cycle times (K,) (s)
    :param base_position: (K, 3) pelvis position (m)
    :param base_orientation: (K, 4) pelvis quaternion (x, y, z, w)
    :param com: (K, 3) whole-body centre of mass (m)
    :param zmp_measured: (K, 2) F/T ZMP, NaN without contact (m)
    :param zmp_reference: (K, 2) reference ZMP (m)
    :param zmp_min: (K, 2) lower corner of the scaled support box of the reference (m)
    :param zmp_max: (K, 2) upper corner (m)
    :param hip_reference: (K, 2) reference hip (m)
    :param left_sole: (K, 3) left sole centre (m)
    :param right_sole: (K, 3) right sole centre (m)
    :param feet_yaw: (K, 2) left and right sole headings the controller holds or targets (rad)
    :param contacts: (K, 2) foot contact flags
    :param support: (K,) reference support label (0 left, 1 right, 2 double)
    :param solve_time: (K,) QP solve time, both planes (s)
    :param mpc_status: (K, 2) QP statuses
    :param controller_status: (K,) controller status bits
    :param time_references: (K,) wall time sampling the references (s)
    :param time_controller: (K,) wall time in the controller (s)
    :param time_physics: (K,) wall time in the backend step (s)
    :param fallen: True if the run ended with a fall
    :param fall_time: time of the fall (s), NaN if none
    :param sole_length: foot length (m)
    :param sole_width: foot width (m)
    """

    t: np.ndarray
    base_position: np.ndarray
    base_orientation: np.ndarray
    com: np.ndarray
    zmp_measured: np.ndarray
    zmp_reference: np.ndarray
    zmp_min: np.ndarray
    zmp_max: np.ndarray
    hip_reference: np.ndarray
    left_sole: np.ndarray
    right_sole: np.ndarray
    feet_yaw: np.ndarray
    contacts: np.ndarray
    support: np.ndarray
    solve_time: np.ndarray
    mpc_status: np.ndarray
    controller_status: np.ndarray
    time_references: np.ndarray
    time_controller: np.ndarray
    time_physics: np.ndarray
    fallen: bool = False
    fall_time: float = math.nan
    sole_length: float = 0.2
    sole_width: float = 0.1

    @classmethod
    def empty(cls, n: int, sole_size: tuple = (0.2, 0.1)) -> 'RunLog':
        """A log of n cycles of zeros, for the given (foot length, foot width) (m)."""
        return cls(
            t=np.zeros(n), base_position=np.zeros((n, 3)), base_orientation=np.zeros((n, 4)),
            com=np.zeros((n, 3)), zmp_measured=np.zeros((n, 2)), zmp_reference=np.zeros((n, 2)),
            zmp_min=np.zeros((n, 2)), zmp_max=np.zeros((n, 2)), hip_reference=np.zeros((n, 2)),
            left_sole=np.zeros((n, 3)), right_sole=np.zeros((n, 3)), feet_yaw=np.zeros((n, 2)),
            contacts=np.zeros((n, 2), dtype=bool), support=np.zeros(n, dtype=np.uint8),
            solve_time=np.zeros(n), mpc_status=np.zeros((n, 2), dtype=int),
            controller_status=np.zeros(n, dtype=int), time_references=np.zeros(n),
            time_controller=np.zeros(n), time_physics=np.zeros(n), sole_length=sole_size[0],
            sole_width=sole_size[1])

    @property
    def tilt(self) -> np.ndarray:
        """(K,) angle between the pelvis z axis and the vertical (rad)."""
        x, y = self.base_orientation[:, 0], self.base_orientation[:, 1]
        return np.arccos(np.clip(1.0 - 2.0 * (x * x + y * y), -1.0, 1.0))

    def longest_flight(self, t_from: float = -math.inf, t_to: float = math.inf) -> float:
        """The longest time with neither foot in contact (the contact flags: its ground force
        above the threshold), from t_from to t_to (s): cycles in a row without a contact, times
        the cycle period (a walk always has a foot loaded; a hop or a landing's rebound not).

        :return: 0 when a foot touches at every cycle of the interval
        """
        inside = (self.t >= t_from - 1e-9) & (self.t < t_to - 1e-9)
        period = float(np.median(np.diff(self.t))) if self.t.size > 1 else 0.0
        return longest_run(inside & ~self.contacts.any(axis=1)) * period

    def zmp_inside_support(self, margin: float = 0.0) -> np.ndarray:
        """Whether the measured ZMP is inside the real support polygon at each cycle.

        The polygon is the convex hull of the sole rectangles in contact (unscaled, grown by
        margin); a cycle without contact or without a measured ZMP counts as outside.

        :param margin: tolerance added around the soles (m)
        :return: (K,) bool
        """
        inside = np.zeros(self.t.size, dtype=bool)
        length, width = self.sole_length + 2.0 * margin, self.sole_width + 2.0 * margin
        for k in range(self.t.size):
            zmp = self.zmp_measured[k]
            if not np.all(np.isfinite(zmp)) or not self.contacts[k].any():
                continue
            corners = [rectangle_vertices(sole[:2], self.feet_yaw[k, side], length, width)
                       for side, sole in enumerate((self.left_sole[k], self.right_sole[k]))
                       if self.contacts[k, side]]
            inside[k] = project_into_polygon(zmp, np.vstack(corners))[1]
        return inside


def longest_run(flags) -> int:
    """The most consecutive True values in a sequence of flags (0 for none)."""
    longest = run = 0
    for flag in flags:
        run = run + 1 if flag else 0
        longest = max(longest, run)
    return longest


def trimmed(log, count: int):
    """The log with its per-cycle arrays cut to the first count cycles (in place)."""
    for name, value in vars(log).items():
        if isinstance(value, np.ndarray):
            setattr(log, name, value[:count])
    return log


class RunRecorder:
    """Fills a RunLog from the humanoid's readings, and tells a fall (the runner's recorder).

    :param sole_size: (foot length, foot width) of the robot (m)
    :param fall_height: fallen below this pelvis height above the lowest sole (m)
    :param fall_tilt: fallen beyond this pelvis tilt from vertical (rad)
    """

    def __init__(self, sole_size: tuple, fall_height: float, fall_tilt: float) -> None:
        self._sole_size = sole_size
        self._fall_height = fall_height
        self._fall_tilt = fall_tilt
        self.log = None

    def start(self, n_cycles: int) -> None:
        """Begin the log of a run of n_cycles cycles."""
        self.log = RunLog.empty(n_cycles, self._sole_size)

    def record(self, k: int, t: float, readings, window, output, timing: tuple) -> None:
        """Record cycle k: the readings it started from, its references and controller output.

        :param timing: wall times (s) of the references, the controller and the physics
        """
        log = self.log
        log.t[k] = t
        log.base_position[k] = readings.base.position
        log.base_orientation[k] = readings.base.orientation
        log.com[k] = readings.com_position
        log.zmp_measured[k] = readings.zmp
        log.zmp_reference[k] = window.zmp[0]
        log.zmp_min[k] = window.zmp_min[0]
        log.zmp_max[k] = window.zmp_max[0]
        log.hip_reference[k] = window.hip[0]
        log.left_sole[k] = readings.left_sole
        log.right_sole[k] = readings.right_sole
        log.feet_yaw[k] = (output.left_foot_target[3], output.right_foot_target[3])
        log.contacts[k] = (readings.left_foot.in_contact, readings.right_foot.in_contact)
        log.support[k] = window.support[0]
        log.solve_time[k] = output.solve_time
        log.mpc_status[k] = output.mpc_status
        log.controller_status[k] = output.status
        log.time_references[k], log.time_controller[k], log.time_physics[k] = timing

    def check_fall(self, readings, time: float) -> bool:
        """Whether the readings show a fall, which the log then records with its time (s)."""
        base = readings.base
        lowest_sole = min(float(readings.left_sole[2]), float(readings.right_sole[2]))
        fallen = bool(base.position[2] - lowest_sole < self._fall_height
                      or tilt_of_quaternion(base.orientation) > self._fall_tilt)
        if fallen:
            self.log.fallen = True
            self.log.fall_time = float(time)
        return fallen

    def finish(self, count: int) -> RunLog:
        """The log of the count cycles run."""
        return trimmed(self.log, count)
