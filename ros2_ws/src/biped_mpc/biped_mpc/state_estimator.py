"""Kalman filter of the discrete three-mass (or LIPM) model: states from noisy outputs."""
from dataclasses import dataclass
from typing import Optional

import numpy as np

from biped_mpc.errors import ConfigError
from biped_mpc.linear_model import (
    DiscreteLinearModel, N_INPUTS, N_MASSES, N_OUTPUTS, N_PLANES, N_STATES, state_index,
    VELOCITY)
from biped_mpc.validation import finite_array, number_tuple
from biped_planner.parameter_fields import parameter, validate_fields


@dataclass(frozen=True)
class EstimatorParams:
    """Noise model of the Kalman filter.

    :param measurement_std: standard deviation of the measured outputs (left leg, right leg,
        ZMP) (m), each in (0, 10]
    :param jerk_std: standard deviation of the applied jerks around the commanded ones
        (m/s^3), [0, 1e4]
    :param acceleration_std: standard deviation of an unmodelled acceleration of (left leg,
        torso, right leg), constant over a period (m/s^2), each in [0, 1e3]; it covers pushes
        (on the torso) and model errors
    :param initial_std: standard deviation of the initial state estimate (SI units), (0, 1e3]
    :param steady_state: use the constant steady-state gain (from the discrete Riccati
        equation, computed once) instead of propagating the covariance every cycle
    """

    measurement_std: tuple = parameter(
        (0.05 / 3.0, 0.05 / 3.0, 0.05 / 3.0),
        'standard deviation of the measured left leg, right leg and ZMP (m)', low=0.0, high=10.0,
        low_open=True)
    jerk_std: float = parameter(0.5, 'standard deviation of the applied jerks (m/s^3)', low=0.0,
                                high=1e4)
    acceleration_std: tuple = parameter(
        (0.05, 1.0, 0.05), 'standard deviation of an unmodelled acceleration of the left leg, '
        'torso and right leg (m/s^2)', low=0.0, high=1e3)
    initial_std: float = parameter(0.01, 'standard deviation of the initial estimate (SI)',
                                   low=0.0, high=1e3, low_open=True)
    steady_state: bool = parameter(True, 'use the constant steady-state Kalman gain')

    def __post_init__(self) -> None:
        object.__setattr__(self, 'measurement_std',
                           number_tuple('measurement_std', self.measurement_std, N_OUTPUTS))
        object.__setattr__(self, 'acceleration_std',
                           number_tuple('acceleration_std', self.acceleration_std, N_MASSES))
        validate_fields(self, ConfigError)


class StateEstimator:
    """Linear Kalman filter on x(k+1) = A_d x(k) + B_d u(k) + w, y(k) = C x(k) + v, per plane.

    Process noise Q = sigma_j^2 B_d B_d' + G diag(sigma_a^2) G' with G the response of the
    states to a unit acceleration held over one period on each mass ([dt^2/2, dt, 0] per mass);
    measurement noise R = diag(measurement_std^2). Both planes share the model and the gains.
    Each cycle: correct(y(k)) gives x(k|k); predict(u(k)) gives x(k+1|k).
    Observability: the legs are measured directly; the torso only through the ZMP row
    p = ... + (m_t/M) c_t - (m_t z_t/(M g)) c_t'', which with the triple integrator makes
    (position, velocity, acceleration) of the torso observable.

    :param model: the discrete model the controller uses
    :param params: noise model
    :raises ConfigError: if the model is not of the nine-state layout
    """

    def __init__(self, model: DiscreteLinearModel,
                 params: EstimatorParams = EstimatorParams()) -> None:
        if model.a.shape != (N_STATES, N_STATES) or model.c.shape != (N_OUTPUTS, N_STATES):
            raise ConfigError('the estimator needs the nine-state, three-output layout')
        self.model = model
        self.params = params
        dt = model.dt
        disturbance = np.zeros((N_STATES, N_MASSES))
        for mass in range(N_MASSES):
            disturbance[state_index(mass, VELOCITY) - 1:state_index(mass, VELOCITY) + 1, mass] = (
                dt ** 2 / 2.0, dt)
        self.process_covariance = (params.jerk_std ** 2 * model.b @ model.b.T
                                   + disturbance @ np.diag(np.asarray(params.acceleration_std,
                                                                      dtype=float) ** 2)
                                   @ disturbance.T
                                   + 1e-12 * np.eye(N_STATES))
        self.measurement_covariance = np.diag(np.asarray(params.measurement_std, float) ** 2)
        self.steady_gain = self._steady_state_gain()
        self.reset(np.zeros((N_PLANES, N_STATES)))

    def _steady_state_gain(self) -> np.ndarray:
        from scipy.linalg import solve_discrete_are

        a, c = self.model.a, self.model.c
        prior = solve_discrete_are(a.T, c.T, self.process_covariance,
                                   self.measurement_covariance)
        self.steady_prior_covariance = prior
        return prior @ c.T @ np.linalg.inv(c @ prior @ c.T + self.measurement_covariance)

    def reset(self, state: np.ndarray) -> None:
        """Restart from a known state with the initial covariance.

        :param state: initial estimate x(0|-1) per plane, shape (2, 9)
        :raises InputError: if state has a wrong shape or is not finite
        """
        self._state = finite_array('state', state, (N_PLANES, N_STATES)).copy()
        self._covariance = self.params.initial_std ** 2 * np.eye(N_STATES)

    @property
    def state(self) -> np.ndarray:
        """The current estimate per plane, shape (2, 9) (a copy)."""
        return self._state.copy()

    @property
    def covariance(self) -> np.ndarray:
        """The current error covariance, shared by the planes, shape (9, 9) (a copy)."""
        if self.params.steady_state:
            return self.steady_prior_covariance.copy()
        return self._covariance.copy()

    def correct(self, measurement: np.ndarray) -> np.ndarray:
        """Measurement update with y(k): x(k|k) = x(k|k-1) + K (y(k) - C x(k|k-1)).

        :param measurement: measured outputs per plane (left leg, right leg, ZMP), (2, 3) (m)
        :return: the corrected estimate x(k|k), shape (2, 9)
        :raises InputError: if the measurement has a wrong shape or is not finite
        """
        y = finite_array('measurement', measurement, (N_PLANES, N_OUTPUTS))
        c = self.model.c
        if self.params.steady_state:
            gain = self.steady_gain
        else:
            p = self._covariance
            gain = p @ c.T @ np.linalg.inv(c @ p @ c.T + self.measurement_covariance)
            identity_minus = np.eye(N_STATES) - gain @ c
            # Joseph form keeps the covariance symmetric positive definite.
            self._covariance = (identity_minus @ p @ identity_minus.T
                                + gain @ self.measurement_covariance @ gain.T)
        self._state = self._state + (y - self._state @ c.T) @ gain.T
        return self._state.copy()

    def predict(self, jerk: np.ndarray, force: Optional[np.ndarray] = None) -> np.ndarray:
        """Time update with the applied jerks: x(k+1|k) = A_d x(k|k) + B_d u(k) (+ f_d F).

        :param jerk: applied jerks per plane, shape (2, 3) (m/s^3)
        :param force: known horizontal force on the torso per plane (N), shape (2,); None if
            unknown (an unknown push is left to the process noise)
        :return: the predicted estimate x(k+1|k), shape (2, 9)
        :raises InputError: if an input has a wrong shape or is not finite
        """
        u = finite_array('jerk', jerk, (N_PLANES, N_INPUTS))
        model = self.model
        self._state = self._state @ model.a.T + u @ model.b.T
        if force is not None:
            f = finite_array('force', force, (N_PLANES,))
            self._state += f[:, None] * model.force_input[None, :]
        if not self.params.steady_state:
            self._covariance = (model.a @ self._covariance @ model.a.T
                                + self.process_covariance)
        return self._state.copy()
