"""Closed-loop walking without ROS: references -> controller -> simulated robot, one runner.

A :class:`ClosedLoopRunner` owns a simulated robot, a reference source
(:mod:`biped_sim.reference_sources`) and a controller, and runs control cycles of Ts (0.02 s:
20 physics steps of 1 ms on PyBullet):

    window   = source.window(t, Np + 1, Ts)             the planner's references
    feedback = feedback_factory(readings, pelvis_source) what the controller may know
    output   = controller.step(t, window, feedback)      estimator + MPC (+ IK)
    readings = actuator.apply(output)                    the robot over Ts

It is the one closed loop of the stack, at two levels:

- a humanoid (PyBullet, or the model plant behind the same SimulatorBackend interface) driven
  by the walking controller (biped_mpc.walking_controller, duck typed: reset(t, feedback),
  step(t, window, feedback), params.mpc.n_predict): the default actuator ramps the joint
  setpoints over the period (:class:`biped_sim.joint_servo.SetpointRamp`) and the default
  recorder fills a :class:`biped_sim.run_log.RunLog` and detects falls;
- the paper's MATLAB loop, the MPC's jerks straight into the model plant
  (:func:`biped_sim.model_walk.run_walk` plugs in its controller, actuator and recorder).

A run ends early when the recorder sees a fall (and stop_on_fall). Time is simulated time (the
backend's clock); the wall clock only times the split between references, controller and
physics. docs/simulator_notes.md has what walked and with which settings.
"""
from dataclasses import dataclass
import math
import time
from typing import Callable, Optional

from biped_mpc.walking_controller import (ControllerFeedback, PELVIS_GROUND_TRUTH,
                                          PELVIS_IMU_KINEMATICS)
from biped_planner.parameter_fields import parameter, validate_fields

from biped_sim.errors import ConfigError
from biped_sim.external_push import ExternalPush
from biped_sim.joint_servo import SetpointRamp
from biped_sim.reference_sources import PlannedWalk
from biped_sim.run_log import RunLog, RunRecorder


@dataclass(frozen=True)
class ClosedLoopParams:
    """Parameters of the closed-loop runner.

    setpoint_interpolation: PyBullet's stiff torque servo then sees a ramp, not a step every
    20 ms (4, the default, is what made the humanoid walk robustly; each part costs one more
    sensor readout, about 0.2 ms); use 1 on the model plant, whose servo follows its targets at
    the control period.
    """

    control_period: float = parameter(0.02, "Ts, time between two controller cycles (s), a "
                                      "multiple of the backend's physics step", low=0.0,
                                      high=1.0, low_open=True)
    pelvis_source: str = parameter(PELVIS_GROUND_TRUTH, "the controller's pelvis pose: the "
                                   "simulator's base, or the IMU orientation with the position "
                                   'from the stance feet',
                                   choices=(PELVIS_GROUND_TRUTH, PELVIS_IMU_KINEMATICS))
    feed_joint_velocities: bool = parameter(True, "pass the controller's setpoint speeds to "
                                            'the backend as feed-forward of its joint PD')
    fall_height: float = parameter(0.35, 'fallen when the pelvis is less than this above its '
                                   'lowest sole (m)', low=0.0, high=5.0)
    fall_tilt: float = parameter(math.radians(45.0), 'fallen when the pelvis z axis leans '
                                 'more than this from vertical (rad)', low=0.0, high=math.pi,
                                 low_open=True)
    stop_on_fall: bool = parameter(True, 'end the run at the first fallen cycle')
    setpoint_interpolation: int = parameter(4, 'equal parts of a period with setpoints '
                                            'interpolated from the previous ones', low=1,
                                            high=20)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


class ClosedLoopRunner:
    """Run a controller on a simulated robot (see the module docstring).

    :param backend: the simulator (time, time_step, reset(**kwargs), push(ExternalPush), and
        what the actuator drives: a SimulatorBackend for the default one); its control period
        must be a whole number of physics steps
    :param controller: reset(t, feedback), step(t, window, feedback), params.mpc.n_predict
    :param source: reference source (PlannedWalk, CommandedWalk or an object with
        window(t, n, dt)); a plain WalkingReference is wrapped in a PlannedWalk
    :param feedback_factory: builds the controller feedback from readings:
        feedback_factory(readings, pelvis_source); None uses
        biped_mpc.walking_controller.ControllerFeedback.from_readings
    :param params: runner parameters
    :param clock: wall clock for the time split (diagnostic only)
    :param actuator: apply(output) -> readings over one control period, restart() after a
        reset; None ramps the joint setpoints on the backend (SetpointRamp)
    :param recorder: start(n), record(k, t, readings, window, output, timing),
        check_fall(readings, time), finish(count) -> log; None logs a RunLog (RunRecorder)
    :raises ConfigError: if the control period is not a multiple of the physics step
    """

    def __init__(self, backend, controller, source, feedback_factory: Optional[Callable] = None,
                 params: ClosedLoopParams = ClosedLoopParams(),
                 clock: Callable[[], float] = time.perf_counter, actuator=None,
                 recorder=None) -> None:
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
        self._feedback = feedback_factory or ControllerFeedback.from_readings
        self._clock = clock
        self._n_samples = int(controller.params.mpc.n_predict) + 1
        self.actuator = actuator or SetpointRamp(backend, int(round(substeps)),
                                                 params.setpoint_interpolation,
                                                 params.feed_joint_velocities)
        if recorder is None:
            description = getattr(backend, 'description', None)
            sole_size = ((description.sole_length, description.sole_width)
                         if description is not None else (0.2, 0.1))
            recorder = RunRecorder(sole_size, params.fall_height, params.fall_tilt)
        self.recorder = recorder
        self._readings = None

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
        self.actuator.restart()
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
        :return: the recorder's log of the cycles run (a RunLog by default)
        :raises ConfigError: if duration is negative or not finite
        """
        if isinstance(duration, bool) or not isinstance(duration, (int, float)) \
                or not math.isfinite(duration) or duration < 0.0:
            raise ConfigError(f'duration must be a finite number >= 0 (s), got {duration!r}')
        if self._readings is None:
            self.reset()
        params, clock, recorder = self.params, self._clock, self.recorder
        dt = params.control_period
        n_cycles = int(round(duration / dt))
        recorder.start(n_cycles)
        readings = self._readings
        count = 0
        for k in range(n_cycles):
            t = self.backend.time
            start = clock()
            window = self.source.window(t, self._n_samples, dt)
            references_done = clock()
            feedback = self._feedback(readings, params.pelvis_source)
            # a source with a step adjuster (AdjustedWalk) counts its revisions
            self.controller.walk_adjustments = getattr(self.source, 'revision', 0)
            output = self.controller.step(t, window, feedback)
            if hasattr(self.source, 'observe_output'):  # a plan that answers the landings
                self.source.observe_output(t, output)
            controller_done = clock()
            next_readings = self.actuator.apply(output)
            physics_done = clock()
            recorder.record(k, t, readings, window, output,
                            (references_done - start, controller_done - references_done,
                             physics_done - controller_done))
            count = k + 1
            readings = next_readings
            if on_cycle is not None:
                on_cycle(t, window, output, readings)
            if recorder.check_fall(readings, self.backend.time) and params.stop_on_fall:
                break
        self._readings = readings
        return recorder.finish(count)
