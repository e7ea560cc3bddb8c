"""The MPC's quadratic cost over the input moves: the paper's stage cost and a terminal cost.

Stage cost (eq. costfunction): J = sum_{i=1}^{Np} sum_o a_o (y_o(k+i) - r_o(k+i))^2
+ sum_{moves} sum_j b_j du_j^2 (+ optional jerk weights) with a = alpha_1..3^2 and
b = alpha_4..6^2 in MATLAB's convention (alpha = 20 and 0.1 in the paper), or a = alpha and
b = alpha with weight_convention='literal'. The paper writes d_4..6 as the squared jerks while
its decision is the increments du; the increments are weighted here (as MATLAB's MPC does with
its default rate weight 0.1, the paper's value), and MpcParams.input_weights weights the jerks.

Terminal cost (not in the paper, on by default): the ZMP output hides the torso's unstable mode
(c_t - (z_t/g) c_t'' = 0 has the solution e^{sqrt(g/z_t) t}), so a finite-horizon cost on the
outputs alone lets the plan diverge in its tail, and the closed loop drifts. The cost-to-go of
the same stage cost beyond Np, from the discrete Riccati equation of the increment form,
penalises the terminal state's distance to the rest state of the last reference sample;
unconstrained, this makes the MPC Kajita's preview controller (infinite-horizon LQ with
preview).
"""
import numpy as np

from biped_mpc.condensed_prediction import CondensedPrediction
from biped_mpc.linear_model import (
    DiscreteLinearModel, LEFT_LEG, N_INPUTS, N_OUTPUTS, N_STATES, POSITION, RIGHT_LEG,
    state_index, TORSO)
from biped_mpc.mpc_params import MpcParams


class MpcCost:
    """Hessian and gradient maps of the cost over the Nc input moves of one plane.

    With the condensed prediction Y = free + Theta dU and the jerks U = 1 (x) u(k-1) + S dU:
    H = 2 (Theta' W Theta + W_du + S' W_jerk S) (+ terminal) and
    f = 2 Theta' W (free - ref) + 2 S' W_jerk (1 (x) u(k-1)) (+ terminal).

    :param params: MPC parameters (weights, convention, terminal_cost)
    :param prediction: the condensed prediction of the tracked outputs
    :param model: the discrete model (for the terminal cost)
    :param output_matrix: (3, 9) the tracked outputs (for the terminal cost)
    """

    def __init__(self, params: MpcParams, prediction: CondensedPrediction,
                 model: DiscreteLinearModel, output_matrix: np.ndarray) -> None:
        n_predict = prediction.n_predict
        self._prediction = prediction
        weights = np.tile(params.quadratic_weights('output_weights'), n_predict)
        rate = np.tile(params.quadratic_weights('input_rate_weights'), prediction.n_moves)
        jerk = np.tile(params.quadratic_weights('input_weights'), n_predict)
        theta = prediction.outputs_from_moves
        s = prediction.inputs_from_moves
        move_hessian = 2.0 * (theta.T @ (weights[:, None] * theta) + np.diag(rate)
                              + s.T @ (jerk[:, None] * s))
        self._gradient_from_error = np.ascontiguousarray(2.0 * (weights[:, None] * theta))
        stacked_input = np.tile(np.eye(N_INPUTS), (n_predict, 1))
        self._gradient_from_input = 2.0 * (s.T @ (jerk[:, None] * stacked_input)).T
        self._has_input_weights = bool(np.any(jerk))
        self._jerk_weights = jerk
        self._weights = weights
        self._theta = theta
        self._rate = rate
        self._terminal_gain = None
        if params.terminal_cost:
            terminal_hessian, self._terminal_gain = terminal_terms(
                model, prediction, output_matrix, weights, rate, jerk)
            move_hessian = move_hessian + terminal_hessian
        self.move_hessian = move_hessian

    def gradient(self, out: np.ndarray, error: np.ndarray, u_prev: np.ndarray,
                 state: np.ndarray, y_ref: np.ndarray) -> None:
        """Write the linear term f of both planes over the moves into out.

        :param out: (2, 3 Nc) the moves' part of the QP's linear term, overwritten
        :param error: (2, 3 Np) free response minus reference
        :param u_prev: (2, 3) jerks applied before the plan
        :param state: (2, 9) the state the plan starts from
        :param y_ref: (2, 3 Np) references, step-major
        """
        out[...] = error @ self._gradient_from_error
        if self._has_input_weights:
            out += u_prev @ self._gradient_from_input
        if self._terminal_gain is not None:
            terminal = np.concatenate([state, u_prev, y_ref[:, -N_OUTPUTS:]], axis=1)
            out += terminal @ self._terminal_gain

    def paper_cost(self, moves: np.ndarray, error: np.ndarray, u_prev: np.ndarray) -> float:
        """The paper's cost J (eq. costfunction) of one plane's moves.

        Stage terms only: neither the slack penalty nor the terminal cost is included.

        :param moves: (3 Nc,) input increments of the plan
        :param error: free response minus reference, shape (3 Np,), of the plane
        :param u_prev: jerks applied before the plan, shape (3,)
        :return: J
        """
        output_error = error + self._theta @ moves
        value = float(output_error @ (self._weights * output_error))
        value += float(moves @ (self._rate * moves))
        if self._has_input_weights:
            jerks = np.tile(u_prev, self._prediction.n_predict) + (
                self._prediction.inputs_from_moves @ moves)
            value += float(jerks @ (self._jerk_weights * jerks))
        return value


def terminal_terms(model: DiscreteLinearModel, prediction: CondensedPrediction,
                   output_matrix: np.ndarray, weights: np.ndarray, rate: np.ndarray,
                   jerk: np.ndarray) -> tuple:
    """Hessian and gradient map of the terminal cost (xi_N - xi_r)' (P - Q) (xi_N - xi_r).

    xi = [x; u_prev] is the state of the increment form (xi+ = [A B; 0 I] xi + [B; I] du),
    P the stabilising solution of its discrete Riccati equation with the stage weights
    Q = diag(C' W C, W_jerk) with C the tracked outputs, R = W_du, and xi_r the rest state
    of the last reference sample r_N: velocities, accelerations and jerks zero, and the
    three positions whose outputs equal r_N. P - Q leaves out the stage cost of the
    last step, already in the sum.

    :return: (hessian over the moves (3 Nc, 3 Nc), gain (9 + 3 + 3, 3 Nc)) with the gradient
        [x, u_prev, r_N] @ gain
    """
    from scipy.linalg import solve_discrete_are

    pred = prediction
    nx, nu = N_STATES, N_INPUTS
    a_aug = np.block([[model.a, model.b], [np.zeros((nu, nx)), np.eye(nu)]])
    b_aug = np.vstack([model.b, np.eye(nu)])
    q_aug = np.zeros((nx + nu, nx + nu))
    q_aug[:nx, :nx] = (output_matrix.T @ np.diag(weights[:N_OUTPUTS]) @ output_matrix)
    q_aug[nx:, nx:] = np.diag(jerk[:nu])
    # A tiny regularisation keeps the Riccati solver well posed when a weight is zero.
    riccati = solve_discrete_are(a_aug, b_aug, q_aug + 1e-9 * np.eye(nx + nu),
                                 np.diag(rate[:nu]))
    terminal = riccati - q_aug
    terminal = 0.5 * (terminal + terminal.T)
    last = slice((pred.n_predict - 1) * nx, pred.n_predict * nx)
    last_input = slice((pred.n_predict - 1) * nu, pred.n_predict * nu)
    from_state = np.vstack([pred.states_from_state[last], np.zeros((nu, nx))])
    from_input = np.vstack([pred.states_from_input[last], np.eye(nu)])
    from_moves = np.vstack([pred.states_from_moves[last], pred.inputs_from_moves[last_input]])
    # Rest state: velocities and accelerations zero, the three positions those whose
    # outputs are the reference (C restricted to the positions is invertible).
    positions = [state_index(mass, POSITION) for mass in (LEFT_LEG, TORSO, RIGHT_LEG)]
    rest = np.zeros((nx + nu, N_OUTPUTS))
    rest[positions] = np.linalg.inv(output_matrix[:, positions])
    hessian = 2.0 * from_moves.T @ terminal @ from_moves
    # gradient = 2 G' P_t (F_x x + F_u u_prev - S r_N) = [x, u_prev, r_N] @ gain
    gain = 2.0 * np.vstack([from_state.T, from_input.T, -rest.T]) @ terminal @ from_moves
    return 0.5 * (hessian + hessian.T), np.ascontiguousarray(gain)
