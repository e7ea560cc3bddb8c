"""Planar linear model of point masses moving on horizontal planes, driven by jerks.

Shared layout of the three-mass model and the LIPM baseline, so that the same MPC, estimator,
plant and reference adapter run on both. The masses are labelled LEFT leg, TORSO, RIGHT leg
(not stance/swing), so the matrices never change when the support foot changes; only the
references and bounds do.

State per plane (x or y), 9 entries: [c_l, v_l, a_l, c_t, v_t, a_t, c_r, v_r, a_r] (m, m/s,
m/s^2). Inputs, 3 entries: the jerks of the three masses (m/s^3). Outputs, 3 entries:
[left leg mass position, right leg mass position, ZMP] (m).
"""
from dataclasses import dataclass
import math

import numpy as np

from biped_mpc.discretization import discretize_exact
from biped_mpc.errors import ConfigError

LEFT_LEG = 0
TORSO = 1
RIGHT_LEG = 2
N_MASSES = 3
STATES_PER_MASS = 3
N_STATES = N_MASSES * STATES_PER_MASS
N_INPUTS = N_MASSES
OUTPUT_LEFT_LEG = 0
OUTPUT_RIGHT_LEG = 1
OUTPUT_ZMP = 2
N_OUTPUTS = 3
N_PLANES = 2
POSITION = 0
VELOCITY = 1
ACCELERATION = 2


def state_index(mass: int, order: int) -> int:
    """Index in the state vector of a mass's position (order 0), velocity (1) or acceleration (2).

    :param mass: LEFT_LEG, TORSO or RIGHT_LEG
    :param order: POSITION, VELOCITY or ACCELERATION
    :return: the index in [0, 9)
    """
    return STATES_PER_MASS * mass + order


def frozen_array(array: np.ndarray) -> np.ndarray:
    """A read-only float copy of an array (the models' matrices never change once built)."""
    array = np.array(array, dtype=float)
    array.setflags(write=False)
    return array


@dataclass(frozen=True)
class DiscreteLinearModel:
    """x(k+1) = A_d x(k) + B_d u(k) + f_d F(k), y(k) = C x(k) (eq. statespace_lipm_disc).

    u and the horizontal force F on the torso are held constant over dt.

    :param name: model name ('three_mass' or 'lipm')
    :param a: A_d, shape (9, 9)
    :param b: B_d, shape (9, 3)
    :param c: C_d = C, shape (3, 9)
    :param force_input: f_d, response of the state to a unit force (N) held over dt, shape (9,)
    :param dt: sampling period (s)
    """

    name: str
    a: np.ndarray
    b: np.ndarray
    c: np.ndarray
    force_input: np.ndarray
    dt: float


@dataclass(frozen=True)
class LinearModel:
    """Continuous model dX/dt = A X + B U + f F, y = C X (eq. statespace_3lipm), one plane.

    A and B make each mass a triple integrator of its jerk. The ZMP row of C is eq. zmp with
    the masses kept at constant heights (z_k'' = 0):
    p = sum_k (m_k / M) c_k - sum_k (m_k z_k / (M g)) c_k''. A massless mass (m_k = 0) only
    follows its jerks kinematically and does not enter the ZMP. A horizontal force F (N) on the
    torso adds F / m_torso to the torso's acceleration (f has a single entry, in the torso's
    velocity row); its moment about the ground cancels the torso's extra inertial force, so the
    ZMP row needs no force term.

    :param name: model name
    :param masses: (m_left, m_torso, m_right) (kg)
    :param heights: (z_left, z_torso, z_right), constant heights of the masses (m)
    :param gravity: g (m/s^2)
    """

    name: str
    masses: tuple
    heights: tuple
    gravity: float

    def __post_init__(self) -> None:
        if len(self.masses) != N_MASSES or len(self.heights) != N_MASSES:
            raise ConfigError(f'masses and heights need {N_MASSES} entries each, got '
                              f'{len(self.masses)} and {len(self.heights)}')
        for label, value in zip(('left leg', 'torso', 'right leg'), self.masses):
            if not math.isfinite(value) or value < 0.0:
                raise ConfigError(f'{label} mass must be finite and >= 0 (kg), got {value!r}')
        if not self.masses[TORSO] > 0.0:
            raise ConfigError(f'torso mass must be > 0 (kg), got {self.masses[TORSO]!r}')
        for label, value in zip(('left leg', 'torso', 'right leg'), self.heights):
            if not math.isfinite(value) or value <= 0.0:
                raise ConfigError(f'{label} height must be finite and > 0 (m), got {value!r}')
        if not math.isfinite(self.gravity) or self.gravity <= 0.0:
            raise ConfigError(f'gravity must be finite and > 0 (m/s^2), got {self.gravity!r}')

    @property
    def total_mass(self) -> float:
        """M = m_left + m_torso + m_right (kg)."""
        return float(sum(self.masses))

    @property
    def com_height(self) -> float:
        """Height of the centre of mass, sum m_k z_k / M (m)."""
        return float(np.dot(self.masses, self.heights) / self.total_mass)

    @property
    def a(self) -> np.ndarray:
        """Continuous A (9, 9): three triple integrators."""
        block = np.diag([1.0, 1.0], k=1)
        return np.kron(np.eye(N_MASSES), block)

    @property
    def b(self) -> np.ndarray:
        """Continuous B (9, 3): each jerk drives its mass's acceleration."""
        b = np.zeros((N_STATES, N_INPUTS))
        for mass in range(N_MASSES):
            b[state_index(mass, ACCELERATION), mass] = 1.0
        return b

    @property
    def c(self) -> np.ndarray:
        """Output matrix C (3, 9): left leg position, right leg position, ZMP (eq. zmp)."""
        c = np.zeros((N_OUTPUTS, N_STATES))
        c[OUTPUT_LEFT_LEG, state_index(LEFT_LEG, POSITION)] = 1.0
        c[OUTPUT_RIGHT_LEG, state_index(RIGHT_LEG, POSITION)] = 1.0
        c[OUTPUT_ZMP] = self.zmp_row
        return c

    @property
    def zmp_row(self) -> np.ndarray:
        """Row (9,) with p = zmp_row @ X (eq. zmp with constant heights)."""
        row = np.zeros(N_STATES)
        total = self.total_mass
        for mass in range(N_MASSES):
            m, z = self.masses[mass], self.heights[mass]
            row[state_index(mass, POSITION)] = m / total
            row[state_index(mass, ACCELERATION)] = -m * z / (total * self.gravity)
        return row

    @property
    def com_row(self) -> np.ndarray:
        """Row (9,) with the horizontal centre of mass = com_row @ X (velocity: shift by 1)."""
        row = np.zeros(N_STATES)
        for mass in range(N_MASSES):
            row[state_index(mass, POSITION)] = self.masses[mass] / self.total_mass
        return row

    @property
    def force_input(self) -> np.ndarray:
        """f (9,): dX/dt gained per newton of horizontal force on the torso."""
        f = np.zeros(N_STATES)
        f[state_index(TORSO, VELOCITY)] = 1.0 / self.masses[TORSO]
        return f

    def discretize(self, dt: float) -> DiscreteLinearModel:
        """Exact discretisation with the jerks and the force held over dt.

        :param dt: sampling period (s), > 0
        :return: the discrete model
        :raises ConfigError: if dt is not a finite positive number
        """
        inputs = np.column_stack([self.b, self.force_input])
        a_d, b_d = discretize_exact(self.a, inputs, dt)
        return DiscreteLinearModel(name=self.name, a=frozen_array(a_d),
                                   b=frozen_array(b_d[:, :N_INPUTS]), c=frozen_array(self.c),
                                   force_input=frozen_array(b_d[:, N_INPUTS]), dt=float(dt))
