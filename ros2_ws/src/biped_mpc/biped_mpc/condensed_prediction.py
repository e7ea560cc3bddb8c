"""Condensed (dense) prediction of a discrete linear model over the MPC horizon."""
import numpy as np

from biped_mpc.errors import ConfigError
from biped_mpc.linear_model import DiscreteLinearModel, frozen_array


def move_starts(move_blocks: tuple) -> np.ndarray:
    """Prediction steps at which each input move (increment) takes effect.

    :param move_blocks: number of steps each move's input is held, one entry per move
    :return: int array of start steps, move j starts at sum(move_blocks[:j])
    """
    return np.concatenate([[0], np.cumsum(move_blocks)[:-1]]).astype(int)


def default_move_blocks(n_predict: int, n_control: int) -> tuple:
    """Spread n_control moves over n_predict steps, fine first and coarse later.

    The first 40 % of the moves last one step, then groups of 20 % of the moves last 2, 4, 8,
    ... steps, and the last move holds to the end of the horizon. For Np = 80, Nc = 20 this is
    8 x 1, 4 x 2, 4 x 4, 3 x 8 and 24 steps. If the horizon is too short, the longest blocks are
    halved until the last move keeps at least one step.

    :param n_predict: prediction horizon Np (steps), >= n_control
    :param n_control: control horizon Nc (moves), >= 1
    :return: tuple of n_control block lengths summing to n_predict
    :raises ConfigError: if n_control > n_predict or either is < 1
    """
    if n_control < 1 or n_predict < n_control:
        raise ConfigError(f'need 1 <= n_control <= n_predict, got n_control={n_control}, '
                          f'n_predict={n_predict}')
    fine = int(round(0.4 * n_control))
    group = max(1, int(round(0.2 * n_control)))
    lengths = [1 if j < fine else 2 ** (1 + (j - fine) // group) for j in range(n_control - 1)]
    while sum(lengths) > n_predict - 1:
        longest = max(lengths)
        index = len(lengths) - 1 - lengths[::-1].index(longest)
        lengths[index] = max(1, longest // 2)
    lengths.sort()
    return tuple(lengths) + (n_predict - sum(lengths),)


class CondensedPrediction:
    """Stacked predictions of the states, outputs and inputs as affine maps of the decisions.

    With u(k+i) = u(k-1) + sum_{j: s_j <= i} du_j (move j starts at step s_j and is then held)
    and x(k+i+1) = A x(k+i) + B u(k+i), i = 0 .. Np-1:

        X = Phi x(k) + Phi_u u(k-1) + Gamma dU,  X = [x(k+1); ...; x(k+Np)]
        Y = Psi x(k) + Psi_u u(k-1) + Theta dU,  Y = [y(k+1); ...; y(k+Np)]
        U = 1 (x) u(k-1) + S dU,                 U = [u(k); ...; u(k+Np-1)]

    Row blocks are ordered by step (step-major), the columns of the moves by move.
    All matrices are read-only.

    :param model: the discrete model (A, B, C)
    :param move_blocks: hold length of each move (steps); their sum is Np
    :raises ConfigError: if a block is < 1
    """

    def __init__(self, model: DiscreteLinearModel, move_blocks: tuple) -> None:
        blocks = tuple(int(b) for b in move_blocks)
        if not blocks or min(blocks) < 1:
            raise ConfigError(f'move blocks must be integers >= 1, got {move_blocks!r}')
        self.model = model
        self.move_blocks = blocks
        self.n_predict = int(sum(blocks))
        self.n_moves = len(blocks)
        a, b, c = model.a, model.b, model.c
        nx, nu = b.shape
        ny = c.shape[0]
        starts = move_starts(blocks)
        n_dec = self.n_moves * nu
        # selection[i] maps the moves to u(k+i) - u(k-1)
        selection = np.zeros((self.n_predict, nu, n_dec))
        for j, start in enumerate(starts):
            selection[start:, :, j * nu:(j + 1) * nu] = np.eye(nu)
        phi = np.zeros((self.n_predict, nx, nx))
        phi_u = np.zeros((self.n_predict, nx, nu))
        gamma = np.zeros((self.n_predict, nx, n_dec))
        x_from_x, x_from_u, x_from_du = np.eye(nx), np.zeros((nx, nu)), np.zeros((nx, n_dec))
        for i in range(self.n_predict):
            x_from_x = a @ x_from_x
            x_from_u = a @ x_from_u + b
            x_from_du = a @ x_from_du + b @ selection[i]
            phi[i], phi_u[i], gamma[i] = x_from_x, x_from_u, x_from_du
        self.states_from_state = frozen_array(phi.reshape(-1, nx))
        self.states_from_input = frozen_array(phi_u.reshape(-1, nu))
        self.states_from_moves = frozen_array(gamma.reshape(-1, n_dec))
        outputs_of = lambda states: np.einsum('oj,ijk->iok', c, states)  # noqa: E731
        self.outputs_from_state = frozen_array(outputs_of(phi).reshape(-1, nx))
        self.outputs_from_input = frozen_array(outputs_of(phi_u).reshape(-1, nu))
        self.outputs_from_moves = frozen_array(outputs_of(gamma).reshape(-1, n_dec))
        self.inputs_from_moves = frozen_array(selection.reshape(-1, n_dec))
        self.n_states, self.n_inputs, self.n_outputs = nx, nu, ny

