"""The model itself as a simulated robot: the paper's MATLAB plant with pushes and noise.

The plant of the model-plant backend (biped_sim.model_plant_backend) and of the paper's
MATLAB loop (biped_sim.model_walk): the controller's own linear model, integrated exactly.
"""
from dataclasses import dataclass
import math
from typing import Optional

import numpy as np

from biped_mpc.linear_model import (
    LinearModel, N_INPUTS, N_OUTPUTS, N_PLANES, N_STATES, OUTPUT_ZMP)
from biped_planner.parameter_fields import parameter, validate_fields

from biped_sim.errors import ConfigError, InputError
from biped_sim.external_push import ExternalPush
from biped_sim.validation import finite_array


@dataclass(frozen=True)
class PlantParams:
    """Measurement noise of the model plant.

    The paper adds "Gaussian noise (-0.05 m <= v_i <= 0.05 m)" to the three outputs. We read it
    as zero-mean Gaussian noise with noise_bound = 3 standard deviations, clipped to
    +-noise_bound so that every sample lies within the stated interval.

    :param seed: seed of the noise generator
    """

    noise_std: float = parameter(0.0, 'standard deviation of the output noise (m); 0 disables '
                                 'noise', low=0.0, high=1.0)
    noise_bound: float = parameter(0.05, 'clipping bound of the noise (m)', low=0.0, high=10.0,
                                   low_open=True)
    seed: int = parameter(0, 'seed of the noise generator', low=0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)

    @classmethod
    def paper_noise(cls, seed: int = 0) -> 'PlantParams':
        """Noise within +-0.05 m: Gaussian with 3 sigma = 0.05 m, clipped at 0.05 m.

        :param seed: seed of the noise generator
        :return: the parameters
        """
        return cls(noise_std=0.05 / 3.0, noise_bound=0.05, seed=seed)


@dataclass(frozen=True)
class PlantMeasurement:
    """What the plant reports after reset or a step, both planes (index 0 = x, 1 = y).

    :param t: time of the sample (s)
    :param outputs: measured outputs (left leg, right leg, ZMP) with noise, (2, 3) (m)
    :param true_outputs: the outputs without noise, (2, 3) (m); the ZMP entry is the
        fictitious ZMP
    :param state: the true state, (2, 9)
    :param zmp_fictitious: the point where the moment of gravity, inertia and the push
        vanishes (Vukobratovic's fictitious ZMP), (2,) (m); it may lie outside the support
        polygon
    :param zmp_real: the centre of pressure: the fictitious ZMP clipped to the support polygon
        set with set_support_polygon (equal to the fictitious one when none is set), (2,) (m)
    """

    t: float
    outputs: np.ndarray
    true_outputs: np.ndarray
    state: np.ndarray
    zmp_fictitious: np.ndarray
    zmp_real: np.ndarray


class ModelPlant:
    """The continuous model integrated exactly with piecewise-constant jerks and push forces.

    dX/dt = A X + B U + f F per plane, with F the horizontal force on the torso (N): the push
    adds F / m_torso to the torso's acceleration while the commanded accelerations (the
    states) stay as the jerks made them; the ground reaction is unchanged at the instant of
    the push, so the ZMP (eq. zmp with the push's moment F z_t) equals C X, and the push moves
    it only through the displaced masses and the controller's reaction. The ZMP the plant
    reports is therefore the fictitious ZMP; the real one (centre of pressure) is its
    projection on the support polygon. The discretisation for each distinct dt is computed
    once and cached.

    :param model: the continuous model to simulate (usually three_mass_model)
    :param params: measurement noise
    """

    def __init__(self, model: LinearModel, params: PlantParams = PlantParams()) -> None:
        if not isinstance(model, LinearModel):
            raise ConfigError(f'model must be a LinearModel, got {type(model).__name__}')
        self.model = model
        self.params = params
        self._discrete = {}
        self._rng = np.random.default_rng(params.seed)
        self._support_lower = np.full(N_PLANES, -np.inf)
        self._support_upper = np.full(N_PLANES, np.inf)
        self._c = model.c
        self.reset(np.zeros((N_PLANES, N_STATES)))

    def reset(self, state: np.ndarray, t: float = 0.0) -> PlantMeasurement:
        """Place the robot in a state.

        :param state: the true state per plane, shape (2, 9)
        :param t: time of the state (s)
        :return: the measurement at that state
        :raises InputError: if the state has a wrong shape or is not finite
        """
        self._state = finite_array('state', state, (N_PLANES, N_STATES), InputError).copy()
        if not isinstance(t, (int, float)) or not math.isfinite(t):
            raise InputError(f't must be a finite number (s), got {t!r}')
        self._t = float(t)
        self._rng = np.random.default_rng(self.params.seed)
        return self.measure()

    def set_support_polygon(self, lower: np.ndarray, upper: np.ndarray) -> None:
        """Set the axis-aligned support polygon used to compute the real ZMP.

        :param lower: (x_min, y_min) of the polygon (m)
        :param upper: (x_max, y_max) of the polygon (m)
        :raises InputError: for NaN values, wrong shapes or lower > upper
        """
        lower = np.asarray(lower, dtype=float)
        upper = np.asarray(upper, dtype=float)
        if lower.shape != (N_PLANES,) or upper.shape != (N_PLANES,) or \
                not (lower <= upper).all():
            raise InputError(f'support polygon needs lower <= upper, shapes (2,), got '
                             f'{lower!r}, {upper!r}')
        self._support_lower = lower.copy()
        self._support_upper = upper.copy()

    @property
    def state(self) -> np.ndarray:
        """The true state, shape (2, 9) (a copy)."""
        return self._state.copy()

    @property
    def t(self) -> float:
        """The plant's time (s)."""
        return self._t

    def step(self, jerk: np.ndarray, dt: float,
             external_force: Optional[np.ndarray] = None) -> PlantMeasurement:
        """Advance by dt with the jerks and the push held constant.

        :param jerk: jerks per plane (left leg, torso, right leg), shape (2, 3) (m/s^3)
        :param dt: duration (s), finite and > 0
        :param external_force: horizontal force on the torso per plane (N), shape (2,);
            None for no push
        :return: the measurement at the end of the step
        :raises InputError: for wrong shapes or non-finite values
        """
        u = finite_array('jerk', jerk, (N_PLANES, N_INPUTS), InputError)
        if not isinstance(dt, (int, float)) or not math.isfinite(dt) or dt <= 0.0:
            raise InputError(f'dt must be a finite number > 0 (s), got {dt!r}')
        discrete = self._discrete.get(dt)
        if discrete is None:
            discrete = self.model.discretize(dt)
            self._discrete[dt] = discrete
        state = self._state @ discrete.a.T + u @ discrete.b.T
        if external_force is not None:
            force = finite_array('external_force', external_force, (N_PLANES,), InputError)
            state += force[:, None] * discrete.force_input[None, :]
        self._state = state
        self._t += dt
        return self.measure()

    def measure(self) -> PlantMeasurement:
        """The measurement at the current state (draws new noise).

        :return: the measurement
        """
        true_outputs = self._state @ self._c.T
        outputs = true_outputs
        if self.params.noise_std > 0.0:
            noise = self._rng.normal(0.0, self.params.noise_std, size=(N_PLANES, N_OUTPUTS))
            outputs = true_outputs + np.clip(noise, -self.params.noise_bound,
                                             self.params.noise_bound)
        fictitious = true_outputs[:, OUTPUT_ZMP].copy()
        real = np.clip(fictitious, self._support_lower, self._support_upper)
        return PlantMeasurement(t=self._t, outputs=outputs, true_outputs=true_outputs,
                                state=self._state.copy(), zmp_fictitious=fictitious,
                                zmp_real=real)


class TorsoPushes:
    """The pushes scheduled on a model plant: each ExternalPush's horizontal force, on the torso
    mass, over the steps it covers (the point and the link of a push are ignored).

    :param time_step: duration of a step (s)
    """

    def __init__(self, time_step: float) -> None:
        self._time_step = time_step
        self._pushes = []

    def clear(self) -> None:
        """Forget every push."""
        self._pushes = []

    def add(self, push: ExternalPush, now: int, time_origin: float = 0.0) -> None:
        """Schedule a push.

        :param push: the push (start_time None: at step now)
        :param now: the step about to run
        :param time_origin: time of step 0 (s)
        """
        start, end = push.steps(now, self._time_step, time_origin)
        self._pushes.append((start, end, np.array(push.force[:N_PLANES], dtype=float)))

    def force(self, step: int) -> np.ndarray:
        """(2,) sum of the horizontal forces acting at a step (N)."""
        force = np.zeros(N_PLANES)
        for start, end, value in self._pushes:
            if start <= step < end:
                force += value
        return force
