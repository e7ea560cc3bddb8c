"""Closed loop on the model plant: references -> (estimator) -> MPC -> model plant.

This is the paper's "Simulation using MATLAB" loop without ROS: the reference is any object
with the WalkingReference sampling method (duck typing), the plant is the model itself.
"""
from dataclasses import dataclass
import math
from typing import Optional

import numpy as np

from biped_mpc.errors import ConfigError
from biped_mpc.linear_mpc import LinearMpc, MpcParams
from biped_mpc.linear_model import (
    LinearModel, N_OUTPUTS, N_PLANES, N_STATES, OUTPUT_LEFT_LEG, OUTPUT_RIGHT_LEG, OUTPUT_ZMP,
    POSITION, state_index)
from biped_mpc.model_plant import ModelPlant, PlantParams
from biped_mpc.qp_backends import QpStatus
from biped_mpc.reference_adapter import outputs_from_window
from biped_mpc.state_estimator import EstimatorParams, StateEstimator


@dataclass(frozen=True)
class Push:
    """A horizontal force on the torso, constant over [t_start, t_start + duration).

    :param force: force per plane (N), (F_x, F_y)
    :param t_start: onset (s)
    :param duration: duration (s), >= 0
    """

    force: tuple = (0.0, 0.0)
    t_start: float = 1.6
    duration: float = 0.1

    def __post_init__(self) -> None:
        if len(self.force) != N_PLANES or not all(math.isfinite(f) for f in self.force):
            raise ConfigError(f'force must be 2 finite numbers (N), got {self.force!r}')
        if not math.isfinite(self.t_start):
            raise ConfigError(f't_start must be finite (s), got {self.t_start!r}')
        if not math.isfinite(self.duration) or self.duration < 0.0:
            raise ConfigError(f'duration must be finite and >= 0 (s), got {self.duration!r}')


@dataclass(frozen=True)
class WalkSetup:
    """One closed-loop run on the model plant.

    :param controller_model: the model the MPC and the estimator use
    :param plant_model: the model simulated as the robot
    :param mpc: MPC parameters
    :param plant: measurement noise of the plant
    :param estimator: Kalman filter parameters; None feeds the true state to the MPC
    :param push: the push, None for none
    :param settle_time: time simulated after the reference's end (s), >= 0
    :param polygon_margin: margin (x, y) from the scaled support box of the reference to the
        real support polygon, (1 - scale) * (foot length, foot width) / 2 (m)
    """

    controller_model: LinearModel
    plant_model: LinearModel
    mpc: MpcParams = MpcParams()
    plant: PlantParams = PlantParams()
    estimator: Optional[EstimatorParams] = None
    push: Optional[Push] = None
    settle_time: float = 1.0
    polygon_margin: tuple = (0.005, 0.004)


@dataclass
class WalkLog:
    """Per-cycle record of a closed-loop run, K cycles, planes x then y on the middle axis.

    :param t: cycle times t_k (K,) (s)
    :param state: true states x_k (K, 2, 9)
    :param estimate: states the MPC used (K, 2, 9)
    :param measured: measured outputs y_k (K, 2, 3) (m)
    :param true_outputs: noise-free outputs (K, 2, 3) (m), ZMP = fictitious ZMP
    :param reference: output references at t_k (K, 2, 3) (m)
    :param zmp_min: scaled support box lower corner at t_k (K, 2) (m)
    :param zmp_max: scaled support box upper corner at t_k (K, 2) (m)
    :param polygon_min: real (unscaled) support polygon lower corner (K, 2) (m)
    :param polygon_max: real support polygon upper corner (K, 2) (m)
    :param zmp_real: centre of pressure (K, 2) (m)
    :param jerk: applied jerks (K, 2, 3) (m/s^3)
    :param force: applied push (K, 2) (N)
    :param status: QP status per plane (K, 2) (QpStatus values)
    :param solve_time: MPC solver time per cycle, both planes (K,) (s)
    :param support: support label of the reference at t_k (K,)
    :param com: true centre of mass of the plant (K, 2) (m)
    :param com_velocity: true centre-of-mass velocity (K, 2) (m/s)
    :param torso: true torso mass position (K, 2) (m)
    :param hip: hip reference at t_k (K, 2) (m)
    :param reference_end: time the reference comes to rest (s)
    """

    t: np.ndarray
    state: np.ndarray
    estimate: np.ndarray
    measured: np.ndarray
    true_outputs: np.ndarray
    reference: np.ndarray
    zmp_min: np.ndarray
    zmp_max: np.ndarray
    polygon_min: np.ndarray
    polygon_max: np.ndarray
    zmp_real: np.ndarray
    jerk: np.ndarray
    force: np.ndarray
    status: np.ndarray
    solve_time: np.ndarray
    support: np.ndarray
    com: np.ndarray
    com_velocity: np.ndarray
    torso: np.ndarray
    hip: np.ndarray
    reference_end: float = 0.0

    @property
    def zmp(self) -> np.ndarray:
        """Fictitious (model) ZMP of the plant (K, 2) (m)."""
        return self.true_outputs[:, :, OUTPUT_ZMP]

    def polygon_excursion(self) -> np.ndarray:
        """Distance of the fictitious ZMP outside the real support polygon, per plane (K, 2) (m).

        :return: 0 inside, positive outside
        """
        return np.maximum(np.maximum(self.polygon_min - self.zmp, self.zmp - self.polygon_max),
                          0.0)

    def scaled_box_excursion(self) -> np.ndarray:
        """Distance of the fictitious ZMP outside the scaled (0.9) support box (K, 2) (m).

        :return: 0 inside, positive outside
        """
        return np.maximum(np.maximum(self.zmp_min - self.zmp, self.zmp - self.zmp_max), 0.0)


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


def run_walk(reference, setup: WalkSetup, t0: Optional[float] = None,
             mpc: Optional[LinearMpc] = None) -> WalkLog:
    """Walk the reference in closed loop on the model plant.

    Per cycle k (t_k = t0 + k Ts): measure y_k; estimate x_k (Kalman correction, or the true
    state); sample the reference at t_k, ..., t_k + Np Ts and adapt it (the MPC gets samples
    1 .. Np); solve the MPC; set the real support polygon of t_{k+1} on the plant; step the
    plant by Ts with the jerks and the push; predict the estimator with the jerks (the push is
    unknown to it).

    :param reference: a WalkingReference (duck typing: sample, t_start, t_end)
    :param setup: models, parameters, push
    :param t0: start time (s); default the reference's t_start
    :param mpc: an already built MPC to reuse (reset first); default builds one
    :return: the log
    """
    params = setup.mpc
    dt = params.dt
    n_predict = params.n_predict
    if mpc is None:
        mpc = LinearMpc(setup.controller_model, params)
    else:
        mpc.reset()
    t0 = float(reference.t_start if t0 is None else t0)
    n_cycles = int(round((float(reference.t_end) + setup.settle_time - t0) / dt))
    plant = ModelPlant(setup.plant_model, setup.plant)
    margin = np.asarray(setup.polygon_margin, dtype=float)
    estimator = None
    if setup.estimator is not None:
        estimator = StateEstimator(mpc.discrete_model, setup.estimator)
    state0 = initial_state(reference, t0)
    first = reference.sample(t0, 1, dt)
    plant.set_support_polygon(np.asarray(first.zmp_min)[0] - margin,
                              np.asarray(first.zmp_max)[0] + margin)
    measurement = plant.reset(state0, t0)
    if estimator is not None:
        estimator.reset(state0)
    push_cycles = range(0)
    if setup.push is not None:
        begin = int(round((setup.push.t_start - t0) / dt))
        push_cycles = range(begin, begin + int(round(setup.push.duration / dt)))
    push_force = np.zeros(N_PLANES) if setup.push is None else np.asarray(setup.push.force,
                                                                           dtype=float)
    com_row = setup.plant_model.com_row
    log = _empty_log(n_cycles)
    log.reference_end = float(reference.t_end)
    for k in range(n_cycles):
        t = t0 + k * dt
        window = reference.sample(t, n_predict + 1, dt)
        # The log keeps the references of the plant's outputs (absolute leg masses).
        y_ref = outputs_from_window(window)[0]
        mpc_ref, y_min, y_max = outputs_from_window(window, mpc.params.leg_outputs)
        estimate = measurement.state if estimator is None else estimator.correct(
            measurement.outputs)
        result = mpc.solve(estimate, mpc_ref[:, 1:], y_min[:, 1:], y_max[:, 1:])
        force = push_force if k in push_cycles else np.zeros(N_PLANES)
        zmp_min, zmp_max = np.asarray(window.zmp_min), np.asarray(window.zmp_max)
        _record(log, k, t, measurement, estimate, y_ref[:, 0], zmp_min[0], zmp_max[0], margin,
                result, force, int(np.asarray(window.support)[0]), com_row,
                np.asarray(window.hip)[0])
        plant.set_support_polygon(zmp_min[1] - margin, zmp_max[1] + margin)
        measurement = plant.step(result.jerk, dt, force)
        if estimator is not None:
            estimator.predict(result.jerk)
    return log


def _empty_log(n: int) -> WalkLog:
    return WalkLog(
        t=np.zeros(n), state=np.zeros((n, N_PLANES, N_STATES)),
        estimate=np.zeros((n, N_PLANES, N_STATES)), measured=np.zeros((n, N_PLANES, N_OUTPUTS)),
        true_outputs=np.zeros((n, N_PLANES, N_OUTPUTS)),
        reference=np.zeros((n, N_PLANES, N_OUTPUTS)), zmp_min=np.zeros((n, N_PLANES)),
        zmp_max=np.zeros((n, N_PLANES)), polygon_min=np.zeros((n, N_PLANES)),
        polygon_max=np.zeros((n, N_PLANES)), zmp_real=np.zeros((n, N_PLANES)),
        jerk=np.zeros((n, N_PLANES, 3)), force=np.zeros((n, N_PLANES)),
        status=np.zeros((n, N_PLANES), dtype=int), solve_time=np.zeros(n),
        support=np.zeros(n, dtype=int), com=np.zeros((n, N_PLANES)),
        com_velocity=np.zeros((n, N_PLANES)), torso=np.zeros((n, N_PLANES)),
        hip=np.zeros((n, N_PLANES)))


def _record(log, k, t, measurement, estimate, reference, zmp_min, zmp_max, margin, result,
            force, support, com_row, hip) -> None:
    log.t[k] = t
    log.state[k] = measurement.state
    log.estimate[k] = estimate
    log.measured[k] = measurement.outputs
    log.true_outputs[k] = measurement.true_outputs
    log.reference[k] = reference
    log.zmp_min[k] = zmp_min
    log.zmp_max[k] = zmp_max
    log.polygon_min[k] = zmp_min - margin
    log.polygon_max[k] = zmp_max + margin
    log.zmp_real[k] = measurement.zmp_real
    log.jerk[k] = result.jerk
    log.force[k] = force
    log.status[k] = [int(s) for s in result.status]
    log.solve_time[k] = result.solve_time
    log.support[k] = support
    log.com[k] = measurement.state @ com_row
    log.com_velocity[k] = measurement.state @ np.roll(com_row, 1)
    log.torso[k] = measurement.state[:, state_index(1, POSITION)]
    log.hip[k] = hip


def tracking_rms(log: WalkLog) -> dict:
    """Root mean square tracking errors of the true outputs over the run (m).

    :param log: a run
    :return: {'left_leg': (x, y), 'right_leg': (x, y), 'zmp': (x, y)}
    """
    error = log.true_outputs - log.reference
    rms = np.sqrt(np.mean(error ** 2, axis=0))
    return {'left_leg': rms[:, OUTPUT_LEFT_LEG].tolist(),
            'right_leg': rms[:, OUTPUT_RIGHT_LEG].tolist(),
            'zmp': rms[:, OUTPUT_ZMP].tolist()}


def optimal_fraction(log: WalkLog) -> float:
    """Fraction of plane-cycles solved to optimality.

    :param log: a run
    :return: in [0, 1]
    """
    return float(np.mean(log.status == int(QpStatus.OPTIMAL)))
