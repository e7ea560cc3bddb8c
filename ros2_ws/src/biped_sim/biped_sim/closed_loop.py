"""Closed-loop walking without ROS: references -> walking controller -> simulator backend.

A :class:`ClosedLoopRunner` owns a simulator backend (PyBullet, the model plant, or any
:class:`biped_sim.backend.SimulatorBackend`), a reference source and a walking controller
(biped_mpc.walking_controller, duck typed: reset(t, feedback) and step(t, window, feedback)),
and runs control cycles of Ts (0.02 s: 20 physics steps of 1 ms on PyBullet):

    window   = reference.sample(t, Np + 1, Ts)          the planner's references
    feedback = ControllerFeedback.from_readings(...)   what the controller may know
    output   = controller.step(t, window, feedback)     estimator + MPC + IK
    readings = backend.step(output.joint_setpoints)     physics over Ts

Reference sources: :class:`PlannedWalk` (a WalkingReference of a footstep plan) and
:class:`CommandedWalk` (footsteps from omnidirectional step commands, OmnidirectionalStepper,
appended with WalkingReference.extend so that the plan stays a fixed number of steps ahead of
the step being walked: the planner's advice is one or two, which keeps the splice correction
of the hip small because the footsteps that change are at least a step after the splice).

What walked on the COMAN-like PyBullet humanoid (tests/test_closed_loop.py, measured with
torque control, PyBulletConfig(leg_kp=2000): with the default 800 the stance ankle and hip
roll yield 1 to 2 degrees, and the robot walks in place but falls after about ten forward
steps; 3000 walks too): setpoints ramped
over 4 parts of each period, the walking controller's defaults (MPC feedback 'prediction',
pelvis velocity servo 0.05 s, posture feedback 0.2, stance-leg projection), references with
0.4 s single and 0.2 s double support, 4 cm swing height, LIPM height 0.497 m, feet
0.20 x 0.10 m, step width 0.14 m. Standing 3 s, 10 steps in place and 20 steps of 0.1, 0.15
and 0.2 m forward stay upright (tilt below 2 degrees) with the measured ZMP in the stance
foot in 95 to 100 % of the single-support cycles and the centre of mass ending within 1 cm
of the last feet's midpoint; the IMU + leg-kinematics pelvis, the LIPM baseline and the
Kalman feedback with gain 0.3 also walk 20 steps of 0.1 m. Without the ramp, 0.1 m steps
walked with a margin of a few percent and longer steps fell.

Each cycle is logged (:class:`RunLog`) so that tests and experiments can assert physical facts:
base pose, centre of mass, measured and reference ZMP, scaled ZMP bounds, feet and contacts,
solver times and statuses, the wall time split between references, controller and physics.
A run ends early when the robot falls: pelvis less than fall_height above its lowest sole or
tilted beyond fall_tilt.
Time is simulated time (the backend's clock); the wall clock only times the split.
"""
from dataclasses import dataclass
import math
import time
from typing import Callable, Optional

import numpy as np

from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.joint_servo import step_toward

PELVIS_GROUND_TRUTH = 'ground_truth'
PELVIS_IMU_KINEMATICS = 'imu_kinematics'


@dataclass(frozen=True)
class ClosedLoopParams:
    """Parameters of the closed-loop runner.

    :param control_period: Ts, time between two controller cycles (s); a multiple of the
        backend's physics step, (0, 1]
    :param pelvis_source: what the controller gets as pelvis pose: 'ground_truth' (the
        simulator's base) or 'imu_kinematics' (IMU orientation, position from the stance feet)
    :param feed_joint_velocities: pass the controller's setpoint speeds to the backend as
        feed-forward of its joint PD
    :param fall_height: the robot has fallen when the pelvis is less than this above its
        lowest sole (m), [0, 5]
    :param fall_tilt: the robot has fallen when the pelvis z axis leans more than this from
        vertical (rad), (0, pi]
    :param stop_on_fall: end the run at the first fallen cycle
    :param setpoint_interpolation: split the period into this many equal parts and send the
        setpoints interpolated linearly from the previous ones, [1, 20]: PyBullet's stiff
        torque servo then sees a ramp, not a step every 20 ms (4, the default, is what made the
        humanoid walk robustly; each part costs one more sensor readout, about 0.2 ms); use 1
        on the model plant, whose servo follows its targets at the control period
    """

    control_period: float = 0.02
    pelvis_source: str = PELVIS_GROUND_TRUTH
    feed_joint_velocities: bool = True
    fall_height: float = 0.35
    fall_tilt: float = math.radians(45.0)
    stop_on_fall: bool = True
    setpoint_interpolation: int = 4

    def __post_init__(self) -> None:
        for name, value, low, high, low_open in (
                ('control_period', self.control_period, 0.0, 1.0, True),
                ('fall_height', self.fall_height, 0.0, 5.0, False),
                ('fall_tilt', self.fall_tilt, 0.0, math.pi, True)):
            ok = (isinstance(value, (int, float)) and not isinstance(value, bool)
                  and math.isfinite(value) and low <= value <= high
                  and not (low_open and value == low))
            if not ok:
                bracket = '(' if low_open else '['
                raise ConfigError(f'ClosedLoopParams.{name} must be a finite number in '
                                  f'{bracket}{low}, {high}], got {value!r}')
        if isinstance(self.setpoint_interpolation, bool) \
                or not isinstance(self.setpoint_interpolation, int) \
                or not 1 <= self.setpoint_interpolation <= 20:
            raise ConfigError(f'ClosedLoopParams.setpoint_interpolation must be an integer in '
                              f'[1, 20], got {self.setpoint_interpolation!r}')
        if self.pelvis_source not in (PELVIS_GROUND_TRUTH, PELVIS_IMU_KINEMATICS):
            raise ConfigError(f'ClosedLoopParams.pelvis_source must be {PELVIS_GROUND_TRUTH!r} '
                              f'or {PELVIS_IMU_KINEMATICS!r}, got {self.pelvis_source!r}')


class PlannedWalk:
    """Reference source of a fixed plan: a WalkingReference (duck typed: sample, t_end).

    :param reference: the walking reference
    """

    def __init__(self, reference) -> None:
        if not hasattr(reference, 'sample'):
            raise ConfigError(f'reference must have sample(t0, n, dt), got '
                              f'{type(reference).__name__}')
        self.reference = reference

    def window(self, t: float, n: int, dt: float):
        """The reference window of n samples from t.

        :param t: first sample time (s)
        :param n: number of samples
        :param dt: sample period (s)
        :return: a ReferenceWindow
        """
        return self.reference.sample(t, n, dt)


class CommandedWalk:
    """Reference source of omnidirectional commands (the paper's tele-operation mode).

    At every window request the plan is extended, if needed, so that at least steps_ahead
    footsteps beyond the one being walked are planned with the command of that time (the
    stepper's lag filter smooths the command changes, one update per step). With a zero command
    the robot walks in place.

    :param stepper: an OmnidirectionalStepper (biped_planner) at the start pose
    :param timing: StepTiming of every step
    :param reference_params: ReferenceParams of the WalkingReference
    :param command: function of the time (s) returning the StepCommand to walk
    :param reference_factory: WalkingReference class (injected, so biped_sim does not import
        the planner)
    :param steps_ahead: planned steps beyond the current one, [1, 10]
    :param t_start: time the walk starts from standing (s)
    """

    def __init__(self, stepper, timing, reference_params, command: Callable, reference_factory,
                 steps_ahead: int = 2, t_start: float = 0.0) -> None:
        if not (isinstance(steps_ahead, int) and 1 <= steps_ahead <= 10):
            raise ConfigError(f'steps_ahead must be an integer in [1, 10], got {steps_ahead!r}')
        if not callable(command):
            raise ConfigError('command must be a function of the time returning a StepCommand')
        self._stepper = stepper
        self._timing = timing
        self._command = command
        self._steps_ahead = steps_ahead
        step_time = timing.single_support + timing.double_support
        self._step_time = step_time
        for _ in range(steps_ahead + 1):
            stepper.next_footstep(command(t_start), step_time)
        self.reference = reference_factory(stepper.footsteps, timing, reference_params,
                                           t_start=t_start)

    def window(self, t: float, n: int, dt: float):
        """The reference window of n samples from t, after extending the plan if needed.

        :param t: first sample time (s)
        :param n: number of samples
        :param dt: sample period (s)
        :return: a ReferenceWindow
        """
        current = int(self.reference.sample(t, 1, dt).step_index[0])
        planned_ahead = self.reference.n_steps - max(current, 1)
        if planned_ahead < self._steps_ahead:
            landings = [self._stepper.next_footstep(self._command(t), self._step_time)
                        for _ in range(self._steps_ahead - planned_ahead)]
            self.reference = self.reference.extend(landings, t, self._timing)
        return self.reference.sample(t, n, dt)


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

    @property
    def tilt(self) -> np.ndarray:
        """(K,) angle between the pelvis z axis and the vertical (rad)."""
        x, y = self.base_orientation[:, 0], self.base_orientation[:, 1]
        return np.arccos(np.clip(1.0 - 2.0 * (x * x + y * y), -1.0, 1.0))

    def zmp_inside_support(self, margin: float = 0.0) -> np.ndarray:
        """Whether the measured ZMP is inside the real support polygon at each cycle.

        The polygon is the convex hull of the sole rectangles in contact (unscaled, grown by
        margin); a cycle without contact or without a measured ZMP counts as outside.

        :param margin: tolerance added around the soles (m)
        :return: (K,) bool
        """
        inside = np.zeros(self.t.size, dtype=bool)
        half = 0.5 * np.array([self.sole_length, self.sole_width]) + margin
        corners = np.array([[1, 1], [1, -1], [-1, -1], [-1, 1]]) * half
        for k in range(self.t.size):
            zmp = self.zmp_measured[k]
            if not np.all(np.isfinite(zmp)) or not self.contacts[k].any():
                continue
            points = []
            for side, sole in enumerate((self.left_sole[k], self.right_sole[k])):
                if self.contacts[k, side]:
                    c, s = math.cos(self.feet_yaw[k, side]), math.sin(self.feet_yaw[k, side])
                    rotation = np.array([[c, -s], [s, c]])
                    points.append(sole[:2] + corners @ rotation.T)
            inside[k] = _inside_convex_hull(zmp, np.vstack(points))
        return inside


def _inside_convex_hull(point: np.ndarray, points: np.ndarray) -> bool:
    """Whether a 2D point is inside (or on) the convex hull of points (monotone chain)."""
    ordered = sorted(map(tuple, points))

    def half(sequence):
        chain = []
        for p in sequence:
            while len(chain) >= 2 and _cross(chain[-2], chain[-1], p) <= 0.0:
                chain.pop()
            chain.append(p)
        return chain[:-1]

    hull = half(ordered) + half(reversed(ordered))
    return all(_cross(hull[i], hull[(i + 1) % len(hull)], point) >= -1e-12
               for i in range(len(hull)))


def _cross(o, a, b) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _yaw(rotation_quaternion) -> float:
    x, y, z, w = rotation_quaternion
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))


class ClosedLoopRunner:
    """Run the walking controller on a simulator backend (see the module docstring).

    :param backend: the simulator (SimulatorBackend); its control period must be a whole
        number of physics steps
    :param controller: the walking controller (reset(t, feedback), step(t, window, feedback),
        params.mpc.n_predict)
    :param source: reference source (PlannedWalk, CommandedWalk or an object with
        window(t, n, dt)); a plain WalkingReference is wrapped in a PlannedWalk
    :param feedback_factory: builds the controller feedback from readings:
        feedback_factory(readings, pelvis_source); None uses
        biped_mpc.walking_controller.ControllerFeedback.from_readings
    :param params: runner parameters
    :param clock: wall clock for the time split (diagnostic only)
    :raises ConfigError: if the control period is not a multiple of the physics step
    """

    def __init__(self, backend, controller, source, feedback_factory: Optional[Callable] = None,
                 params: ClosedLoopParams = ClosedLoopParams(),
                 clock: Callable[[], float] = time.perf_counter) -> None:
        if not isinstance(params, ClosedLoopParams):
            raise ConfigError(f'params must be ClosedLoopParams, got {type(params).__name__}')
        substeps = params.control_period / backend.time_step
        if abs(substeps - round(substeps)) > 1e-6 or round(substeps) < 1:
            raise ConfigError(f'control_period {params.control_period} s is not a multiple of '
                              f'the physics step {backend.time_step} s')
        self.backend = backend
        self.controller = controller
        self.source = source if hasattr(source, 'window') else PlannedWalk(source)
        self.params = params
        if feedback_factory is None:
            from biped_mpc.walking_controller import ControllerFeedback
            feedback_factory = ControllerFeedback.from_readings
        self._feedback = feedback_factory
        self._substeps = int(round(substeps))
        self._clock = clock
        self._n_samples = int(controller.params.mpc.n_predict) + 1
        description = getattr(backend, 'description', None)
        self._sole_size = ((description.sole_length, description.sole_width)
                           if description is not None else (0.2, 0.1))
        self._readings = None
        self._last_setpoints = None

    @property
    def readings(self):
        """The last sensor readings."""
        return self._readings

    def reset(self, **backend_reset) -> None:
        """Reset the backend (standing pose, time 0) and the controller.

        :param backend_reset: keyword arguments of backend.reset (base_position, base_yaw,
            joint_positions)
        """
        self._readings = self.backend.reset(**backend_reset)
        self._last_setpoints = None
        # The start pose is known: the controller's reset anchors the feet with the true base.
        feedback = self._feedback(self._readings, PELVIS_GROUND_TRUTH)
        self.controller.reset(self.backend.time, feedback)

    def push(self, push: ExternalPush) -> None:
        """Schedule an external push on the backend.

        :param push: the push
        """
        self.backend.push(push)

    def add_terrain(self, terrain) -> list:
        """Build uneven terrain in the backend (PyBullet only).

        :param terrain: a biped_sim.terrain.Terrain
        :return: the backend's body ids
        """
        return self.backend.add_terrain(terrain)

    def run(self, duration: float, on_cycle: Optional[Callable] = None) -> RunLog:
        """Run control cycles for a duration of simulated time (or until a fall).

        Call reset first (the first run resets automatically).

        :param duration: simulated time to run (s), >= 0
        :param on_cycle: called after every cycle as on_cycle(t, window, output, readings)
        :return: the log of the cycles run
        :raises ConfigError: if duration is negative or not finite
        """
        if isinstance(duration, bool) or not isinstance(duration, (int, float)) \
                or not math.isfinite(duration) or duration < 0.0:
            raise ConfigError(f'duration must be a finite number >= 0 (s), got {duration!r}')
        if self._readings is None:
            self.reset()
        params, clock = self.params, self._clock
        dt = params.control_period
        n_cycles = int(round(duration / dt))
        log = _empty_log(n_cycles, self._sole_size)
        readings = self._readings
        count = 0
        for k in range(n_cycles):
            t = self.backend.time
            start = clock()
            window = self.source.window(t, self._n_samples, dt)
            references_done = clock()
            feedback = self._feedback(readings, params.pelvis_source)
            output = self.controller.step(t, window, feedback)
            controller_done = clock()
            next_readings = self._apply(output)
            physics_done = clock()
            _record(log, k, t, readings, window, output, references_done - start,
                    controller_done - references_done, physics_done - controller_done)
            count = k + 1
            readings = next_readings
            if on_cycle is not None:
                on_cycle(t, window, output, readings)
            if self._has_fallen(readings):
                log.fallen = True
                log.fall_time = float(self.backend.time)
                if params.stop_on_fall:
                    break
        self._readings = readings
        return _trimmed(log, count)

    def _apply(self, output):
        """Send the setpoints over one control period (interpolated if asked) to the backend."""
        params = self.params
        velocities = output.joint_velocities if params.feed_joint_velocities else None
        target = np.asarray(output.joint_setpoints, dtype=float)
        readings = step_toward(self.backend, self._last_setpoints, target, self._substeps,
                               params.setpoint_interpolation, velocities)
        self._last_setpoints = target.copy()
        return readings

    def _has_fallen(self, readings) -> bool:
        base = readings.base
        lowest_sole = min(float(readings.left_sole[2]), float(readings.right_sole[2]))
        x, y = base.orientation[0], base.orientation[1]
        tilt = math.acos(min(1.0, max(-1.0, 1.0 - 2.0 * (x * x + y * y))))
        return bool(base.position[2] - lowest_sole < self.params.fall_height
                    or tilt > self.params.fall_tilt)


def _empty_log(n: int, sole_size: tuple) -> RunLog:
    return RunLog(
        t=np.zeros(n), base_position=np.zeros((n, 3)), base_orientation=np.zeros((n, 4)),
        com=np.zeros((n, 3)), zmp_measured=np.zeros((n, 2)), zmp_reference=np.zeros((n, 2)),
        zmp_min=np.zeros((n, 2)), zmp_max=np.zeros((n, 2)), hip_reference=np.zeros((n, 2)),
        left_sole=np.zeros((n, 3)), right_sole=np.zeros((n, 3)), feet_yaw=np.zeros((n, 2)),
        contacts=np.zeros((n, 2), dtype=bool), support=np.zeros(n, dtype=np.uint8),
        solve_time=np.zeros(n), mpc_status=np.zeros((n, 2), dtype=int),
        controller_status=np.zeros(n, dtype=int), time_references=np.zeros(n),
        time_controller=np.zeros(n), time_physics=np.zeros(n), sole_length=sole_size[0],
        sole_width=sole_size[1])


def _record(log: RunLog, k: int, t: float, readings, window, output, t_ref: float,
            t_ctrl: float, t_phys: float) -> None:
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
    log.time_references[k] = t_ref
    log.time_controller[k] = t_ctrl
    log.time_physics[k] = t_phys


def _trimmed(log: RunLog, count: int) -> RunLog:
    for name, value in vars(log).items():
        if isinstance(value, np.ndarray):
            setattr(log, name, value[:count])
    return log
