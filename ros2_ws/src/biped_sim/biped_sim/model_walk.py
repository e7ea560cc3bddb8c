"""The paper's "Simulation using MATLAB" loop: references -> (estimator) -> MPC -> model plant.

The MPC's jerks drive the model plant directly (no IK, no joints), the plant being the model
itself or another one (the LIPM baseline on the three-mass robot). The loop is the
ClosedLoopRunner's, with the pieces of this level plugged in:

- :class:`MpcJerkController`, the controller: Kalman correction with the measured outputs (or
  the true state), the MPC on the window's samples 1 .. Np, the Kalman prediction with the
  jerks (the push is unknown to it);
- :class:`JerkDrivenPlant`, the simulated robot and its actuator: per cycle it sets the real
  support polygon of t_{k+1} (the scaled box of the reference grown by the margin), then steps
  the plant by Ts with the jerks and the push (an ExternalPush, its horizontal force on the
  torso, held over the cycles it covers);
- :class:`WalkRecorder`, the WalkLog of the run (the model plant cannot fall).

The reference is any object with the WalkingReference sampling method (duck typing). With a
step adjuster in the setup the reference is a WalkingReference walked through an AdjustedWalk:
each cycle, after its Kalman correction, the controller hands the estimated COM and DCM to the
adjuster, which may replan the step under way before the MPC samples its window.
"""
from dataclasses import dataclass, replace
from typing import Optional

import numpy as np

from biped_planner.step_adjuster import OnlineStepAdjuster, OnlineStepAdjusterParams
from biped_planner.step_adjustment import StepAdjustmentParams
from biped_mpc.linear_model import LinearModel, N_PLANES, N_STATES, POSITION, state_index
from biped_mpc.linear_mpc import LinearMpc, MpcParams
from biped_mpc.reference_adapter import outputs_from_window
from biped_mpc.state_estimator import EstimatorParams, StateEstimator

from biped_sim.closed_loop import ClosedLoopParams, ClosedLoopRunner
from biped_sim.external_push import ExternalPush
from biped_sim.model_plant import ModelPlant, PlantMeasurement, PlantParams, TorsoPushes
from biped_sim.reference_sources import AdjustedWalk
from biped_sim.run_log import trimmed
from biped_sim.walk_log import WalkLog


@dataclass(frozen=True)
class WalkSetup:
    """One closed-loop run on the model plant.

    :param controller_model: the model the MPC and the estimator use
    :param plant_model: the model simulated as the robot
    :param mpc: MPC parameters
    :param plant: measurement noise of the plant
    :param estimator: Kalman filter parameters; None feeds the true state to the MPC
    :param push: the push (its x and y force act on the torso), None for none
    :param settle_time: time simulated after the reference's end (s), >= 0
    :param polygon_margin: margin (x, y) from the scaled support box of the reference to the
        real support polygon, (1 - scale) * (foot length, foot width) / 2 (m)
    :param step_adjuster: online step adjustment, None (or enabled False) for none
    :param step_adjustment: the adjustment QP's weights and limits; its com_height is replaced
        by the controller model's
    """

    controller_model: LinearModel
    plant_model: LinearModel
    mpc: MpcParams = MpcParams()
    plant: PlantParams = PlantParams()
    estimator: Optional[EstimatorParams] = None
    push: Optional[ExternalPush] = None
    settle_time: float = 1.0
    polygon_margin: tuple = (0.005, 0.004)
    step_adjuster: Optional[OnlineStepAdjusterParams] = None
    step_adjustment: StepAdjustmentParams = StepAdjustmentParams()


@dataclass(frozen=True)
class MpcCycle:
    """What the MPC did in one cycle.

    :param result: the MPC's solution (jerk, status, solve_time)
    :param estimate: the state it started from (2, 9)
    :param reference: the plant's output references at t_k, absolute leg masses (2, 3) (m)
    :param window: the reference window of the cycle
    """

    result: object
    estimate: np.ndarray
    reference: np.ndarray
    window: object


class MpcJerkController:
    """The MPC with its optional Kalman filter, on the measured outputs of the model plant.

    :param mpc: the MPC (reset by its owner)
    :param setup: the run's setup (its mpc parameters size the reference window)
    :param source: an AdjustedWalk to hand the estimate to before the MPC, None for none
    """

    def __init__(self, mpc: LinearMpc, setup: WalkSetup,
                 source: Optional[AdjustedWalk] = None) -> None:
        self.mpc = mpc
        self.params = setup
        self.source = source
        model = setup.controller_model
        self._com_rows = (model.com_row, np.roll(model.com_row, 1))
        self._omega = float(np.sqrt(setup.step_adjustment.gravity / model.com_height))
        self.estimator = None
        if setup.estimator is not None:
            self.estimator = StateEstimator(mpc.discrete_model, setup.estimator)

    def reset(self, t: float, measurement: PlantMeasurement) -> None:
        """Start the estimate at the plant's (known) initial state."""
        if self.estimator is not None:
            self.estimator.reset(measurement.state)

    def step(self, t: float, window, measurement: PlantMeasurement) -> MpcCycle:
        """Estimate, adjust the step, solve the MPC on the window's samples 1 .. Np, predict
        with its jerks."""
        mpc = self.mpc
        estimate = measurement.state if self.estimator is None else self.estimator.correct(
            measurement.outputs)
        if self.source is not None:
            com = estimate @ self._com_rows[0]
            dcm = com + estimate @ self._com_rows[1] / self._omega
            if self.source.adjust(t, com, dcm).applied:
                window = self.source.window(t, len(window.t), float(window.t[1] - window.t[0]))
        # The log keeps the references of the plant's outputs (absolute leg masses).
        y_ref = outputs_from_window(window)[0]
        mpc_ref, y_min, y_max = outputs_from_window(window, mpc.params.leg_outputs)
        result = mpc.solve(estimate, mpc_ref[:, 1:], y_min[:, 1:], y_max[:, 1:])
        if self.estimator is not None:
            self.estimator.predict(result.jerk)
        return MpcCycle(result, estimate, y_ref[:, 0], window)


class JerkDrivenPlant:
    """The model plant stepped by the MPC's jerks, one control period per cycle, with pushes.

    :param model: the model simulated as the robot
    :param params: measurement noise
    :param dt: control period Ts (s)
    :param margin: (2,) margin from the scaled support box to the real support polygon (m)
    """

    def __init__(self, model: LinearModel, params: PlantParams, dt: float,
                 margin: np.ndarray) -> None:
        self.plant = ModelPlant(model, params)
        self._dt = dt
        self.margin = margin
        self._t0 = 0.0
        self._count = 0
        self._pushes = TorsoPushes(dt)
        self.last_force = np.zeros(N_PLANES)

    @property
    def time(self) -> float:
        """Time of the current cycle, t0 + k Ts (s)."""
        return self._t0 + self._count * self._dt

    @property
    def time_step(self) -> float:
        """The control period: the plant is stepped once per cycle (s)."""
        return self._dt

    def reset(self, state: np.ndarray, t0: float, zmp_min: np.ndarray,
              zmp_max: np.ndarray) -> PlantMeasurement:
        """Place the plant in a state at t0 on the support box [zmp_min, zmp_max] (scaled)."""
        self._t0, self._count = float(t0), 0
        self._pushes.clear()
        self.plant.set_support_polygon(zmp_min - self.margin, zmp_max + self.margin)
        return self.plant.reset(state, t0)

    def push(self, push: ExternalPush) -> None:
        """Schedule a push: its horizontal force on the torso over the cycles it covers."""
        self._pushes.add(push, self._count, self._t0)

    def restart(self) -> None:
        """Nothing to forget after a reset: the jerks act at once, without a ramp."""

    def apply(self, cycle: MpcCycle) -> PlantMeasurement:
        """Set the support polygon of the next sample, step the plant by Ts with the jerks."""
        window = cycle.window
        self.plant.set_support_polygon(np.asarray(window.zmp_min)[1] - self.margin,
                                       np.asarray(window.zmp_max)[1] + self.margin)
        force = self._pushes.force(self._count)
        self.last_force = force
        self._count += 1
        return self.plant.step(cycle.result.jerk, self._dt, force)


class WalkRecorder:
    """Fills a WalkLog from the plant's measurements (the runner's recorder).

    :param plant: the jerk-driven plant (the push force it applied)
    :param model: the plant's model (its centre-of-mass row)
    """

    def __init__(self, plant: JerkDrivenPlant, model: LinearModel) -> None:
        self._plant = plant
        self._com_row = model.com_row
        self.log = None

    def start(self, n_cycles: int) -> None:
        """Begin the log of a run of n_cycles cycles."""
        self.log = WalkLog.empty(n_cycles)

    def record(self, k: int, t: float, measurement: PlantMeasurement, window, cycle: MpcCycle,
               timing: tuple) -> None:
        """Record cycle k: the measurement it started from, the MPC's cycle, the push."""
        log, margin = self.log, self._plant.margin
        window = cycle.window  # the one the MPC used, after any step adjustment
        zmp_min, zmp_max = np.asarray(window.zmp_min)[0], np.asarray(window.zmp_max)[0]
        log.t[k] = t
        log.state[k] = measurement.state
        log.estimate[k] = cycle.estimate
        log.measured[k] = measurement.outputs
        log.true_outputs[k] = measurement.true_outputs
        log.reference[k] = cycle.reference
        log.zmp_min[k] = zmp_min
        log.zmp_max[k] = zmp_max
        log.polygon_min[k] = zmp_min - margin
        log.polygon_max[k] = zmp_max + margin
        log.zmp_real[k] = measurement.zmp_real
        log.jerk[k] = cycle.result.jerk
        log.force[k] = self._plant.last_force
        log.status[k] = [int(s) for s in cycle.result.status]
        log.solve_time[k] = cycle.result.solve_time
        log.support[k] = int(np.asarray(window.support)[0])
        log.com[k] = measurement.state @ self._com_row
        log.com_velocity[k] = measurement.state @ np.roll(self._com_row, 1)
        log.torso[k] = measurement.state[:, state_index(1, POSITION)]
        log.hip[k] = np.asarray(window.hip)[0]

    def check_fall(self, measurement: PlantMeasurement, time: float) -> bool:
        """The model plant cannot fall."""
        return False

    def finish(self, count: int) -> WalkLog:
        """The log of the count cycles run."""
        return trimmed(self.log, count)


def initial_state(reference, t0: float) -> np.ndarray:
    """Standing state at t0: legs and torso at their references, at rest.

    :param reference: object with sample(t0, n, dt) returning a ReferenceWindow
    :param t0: start time (s)
    :return: state per plane (2, 9)
    """
    window = reference.sample(t0, 1, 0.01)
    state = np.zeros((N_PLANES, N_STATES))
    state[:, state_index(0, POSITION)] = np.asarray(window.left_mass)[0]
    state[:, state_index(1, POSITION)] = np.asarray(window.hip)[0]
    state[:, state_index(2, POSITION)] = np.asarray(window.right_mass)[0]
    return state


@dataclass(frozen=True)
class WalkRun:
    """A run on the model plant and the plan it ended with.

    :param log: the per-cycle log
    :param reference: the reference at the end of the run (adjusted, if a step adjuster ran)
    :param revisions: plan revisions made by the step adjuster (0 without one)
    :param adjustments: (t, StepAdjustment) of every applied adjustment
    """

    log: WalkLog
    reference: object
    revisions: int = 0
    adjustments: tuple = ()


def run_walk(reference, setup: WalkSetup, t0: Optional[float] = None,
             mpc: Optional[LinearMpc] = None) -> WalkLog:
    """Walk the reference in closed loop on the model plant: walk(...).log.

    :param reference: a WalkingReference (duck typing: sample, t_start, t_end)
    :param setup: models, parameters, push, step adjustment
    :param t0: start time (s); default the reference's t_start
    :param mpc: an already built MPC to reuse (reset first); default builds one
    :return: the log
    """
    return walk(reference, setup, t0, mpc).log


def walk(reference, setup: WalkSetup, t0: Optional[float] = None,
         mpc: Optional[LinearMpc] = None) -> WalkRun:
    """Walk the reference in closed loop on the model plant (see the module docstring).

    Per cycle k (t_k = t0 + k Ts): measure y_k; estimate x_k; sample the reference at t_k, ...,
    t_k + Np Ts and adapt it (the MPC gets samples 1 .. Np); solve the MPC; set the real
    support polygon of t_{k+1} on the plant; step the plant by Ts with the jerks and the push.

    :param reference: a WalkingReference (duck typing: sample, t_start, t_end)
    :param setup: models, parameters, push
    :param t0: start time (s); default the reference's t_start
    :param mpc: an already built MPC to reuse (reset first); default builds one
    :return: the log and the final plan
    """
    dt = setup.mpc.dt
    if mpc is None:
        mpc = LinearMpc(setup.controller_model, setup.mpc)
    else:
        mpc.reset()
    t0 = float(reference.t_start if t0 is None else t0)
    plant = JerkDrivenPlant(setup.plant_model, setup.plant, dt,
                            np.asarray(setup.polygon_margin, dtype=float))
    source = None
    if setup.step_adjuster is not None and setup.step_adjuster.enabled:
        qp = replace(setup.step_adjustment, com_height=setup.controller_model.com_height)
        source = AdjustedWalk(reference, OnlineStepAdjuster(setup.step_adjuster, qp))
    runner = ClosedLoopRunner(
        plant, MpcJerkController(mpc, setup, source), source or reference,
        feedback_factory=lambda measurement, pelvis_source: measurement,
        params=ClosedLoopParams(control_period=dt), actuator=plant,
        recorder=WalkRecorder(plant, setup.plant_model))
    first = reference.sample(t0, 1, dt)
    runner.reset(state=initial_state(reference, t0), t0=t0,
                 zmp_min=np.asarray(first.zmp_min)[0], zmp_max=np.asarray(first.zmp_max)[0])
    if setup.push is not None:
        runner.push(setup.push)
    log = runner.run(float(reference.t_end) + setup.settle_time - t0)
    final = (source or runner.source).reference
    log.reference_end = float(final.t_end)
    if source is None:
        return WalkRun(log, final)
    return WalkRun(log, final, source.revision, tuple(source.history))
