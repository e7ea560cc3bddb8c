"""What one MPC cycle returns: the jerks to apply now, and the plan computed on demand."""
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np

from biped_mpc.linear_model import N_INPUTS, N_PLANES, N_STATES
from biped_mpc.qp_backend import QpStatus


@dataclass(frozen=True)
class MpcResult:
    """Outcome of one MPC cycle for both planes (index 0 = x, 1 = y).

    The plan (moves, slacks, predicted inputs, states, outputs) and the cost are computed on
    first access, so that the control loop pays only for the jerks it applies.

    :param jerk: the jerks to apply now, u(k) per plane, shape (2, 3) (m/s^3)
    :param status: QP status per plane; anything but OPTIMAL means the plane used the fallback
        (the previous plan shifted by the cycles since it was computed)
    :param iterations: solver iterations per plane
    :param solve_time: time in the solver calls of both planes (s), a diagnostic only
    """

    jerk: np.ndarray
    status: tuple
    iterations: np.ndarray
    solve_time: float
    _solutions: np.ndarray = field(repr=False)
    _state: np.ndarray = field(repr=False)
    _u_prev: np.ndarray = field(repr=False)
    _error: np.ndarray = field(repr=False)
    _fallback: dict = field(repr=False)
    _mpc: Any = field(repr=False)  # the LinearMpc that solved it

    @property
    def ok(self) -> bool:
        """True when both planes were solved to optimality."""
        return all(s == QpStatus.OPTIMAL for s in self.status)

    @cached_property
    def cost(self) -> np.ndarray:
        """The paper's cost J (eq. costfunction) per plane, nan for a fallback plane, (2,)."""
        return np.array([
            np.nan if plane in self._fallback else self._mpc.paper_cost(
                self._solutions[plane], self._error[plane], self._u_prev[plane])
            for plane in range(N_PLANES)])

    @cached_property
    def moves(self) -> np.ndarray:
        """The input increments du of the plan per plane, shape (2, Nc, 3) (m/s^3)."""
        n_soft = self._mpc.n_soft
        return self._solutions[:, n_soft:].reshape(N_PLANES, -1, N_INPUTS).copy()

    @cached_property
    def slack(self) -> np.ndarray:
        """Soft-constraint slacks epsilon per plane, shape (2, soft groups) (m)."""
        return self._solutions[:, :self._mpc.n_soft].copy()

    @cached_property
    def predicted_inputs(self) -> np.ndarray:
        """Jerks u(k .. k+Np-1) of the plan, shape (2, Np, 3) (m/s^3)."""
        s = self._mpc.prediction.inputs_from_moves
        planned = (self._u_prev[:, None, :]
                   + (self.moves.reshape(N_PLANES, -1) @ s.T).reshape(N_PLANES, -1, N_INPUTS))
        for plane, sequence in self._fallback.items():
            planned[plane] = sequence
        return planned

    @cached_property
    def predicted_states(self) -> np.ndarray:
        """States x(k+1 .. k+Np) of the plan, shape (2, Np, 9)."""
        p = self._mpc.prediction
        flat = (self._state @ p.states_from_state.T
                + self.predicted_inputs.reshape(N_PLANES, -1) @ self._mpc.inputs_to_states.T)
        return flat.reshape(N_PLANES, p.n_predict, N_STATES)

    @cached_property
    def predicted_outputs(self) -> np.ndarray:
        """Outputs y(k+1 .. k+Np): left leg, right leg, ZMP, shape (2, Np, 3) (m)."""
        return self.predicted_states @ self._mpc.output_matrix.T
