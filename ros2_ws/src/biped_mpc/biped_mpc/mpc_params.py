"""Parameters of the linear MPC (paper Table Params and section "Online Walking Controller")."""
from dataclasses import dataclass

import numpy as np

from biped_mpc.condensed_prediction import default_move_blocks
from biped_mpc.errors import ConfigError
from biped_mpc.linear_model import N_INPUTS, N_OUTPUTS
from biped_mpc.qp_backends import BACKENDS
from biped_mpc.validation import check_integer, number_tuple
from biped_planner.parameter_fields import parameter, validate_fields

CONSTRAINT_MODES = ('hard', 'soft', 'off')
WEIGHT_CONVENTIONS = ('matlab', 'literal')
MOVE_BLOCKINGS = ('spread', 'hold')
LEG_OUTPUTS_ABSOLUTE = 'absolute'
LEG_OUTPUTS_TORSO_RELATIVE = 'torso_relative'
LEG_OUTPUTS = (LEG_OUTPUTS_ABSOLUTE, LEG_OUTPUTS_TORSO_RELATIVE)


@dataclass(frozen=True)
class MpcParams:
    """Parameters of the MPC.

    :param dt: control period Ts (s), (0, 1]
    :param n_predict: prediction horizon Np (steps), [1, 1000]
    :param n_control: control horizon Nc (number of input moves), [1, n_predict]
    :param move_blocking: where the Nc moves act. 'hold' is the paper's literal form (moves at
        steps 0 .. Nc-1, the last one held to Np); 'spread' spreads them over the whole
        horizon (for 80/20: 8 x 1, 4 x 2, 4 x 4, 3 x 8, 24 steps), which keeps the QP feasible
        with hard constraints over the whole horizon (see docs/controller_notes.md)
    :param move_blocks: explicit hold length of each move (steps), overriding move_blocking;
        empty to derive it; Nc entries summing to Np
    :param constraint_horizon: number of first predicted steps whose outputs are constrained
        (steps), [1, n_predict]. The default 40 (0.8 s, a whole single support) covers the
        part of the horizon where the spread moves last at most 8 steps; hard constraints on
        the coarse tail (constant jerk over 24 steps cannot follow a 0.8 m swing) make the QP
        infeasible in the paper's walk
    :param output_weights: alpha_1..3 of the errors of (left leg, right leg, ZMP), each >= 0
        (the paper's stance/swing weights, equal in the paper)
    :param input_rate_weights: alpha_4..6 of the input increments du of the jerks of
        (left leg, torso, right leg), each > 0
    :param input_weights: optional extra weights of the jerks themselves, summed over the
        prediction horizon, each >= 0; 0 as in the paper's table
    :param weight_convention: 'matlab': a weight w multiplies the signal before squaring,
        cost (w e)^2, as in MATLAB's MPC Toolbox that the paper's notation follows (its rate
        weight 0.1 is the toolbox default); 'literal': cost w e^2 as eq. costfunction reads.
        With the paper's 20 and 0.1 the literal form tracks too loosely for 0.8 m steps
    :param zmp_constraint: 'hard', 'soft' or 'off': ZMP inside the support polygon
        (eq. ZMPConstraints)
    :param landing_constraint: 'hard', 'soft' or 'off': swing leg inside the reachable
        rectangle (eq. SwingConstraints)
    :param soft_quadratic_weight: quadratic penalty rho on each soft group's slack epsilon
        (1/m^2), > 0
    :param soft_linear_weight: linear penalty on each soft group's slack (1/m), >= 0; large
        enough makes the penalty exact (no violation while the hard problem is feasible)
    :param terminal_cost: add the infinite-horizon cost-to-go beyond Np (LQ, from the discrete
        Riccati equation) of the terminal state's distance to the rest state of the last
        reference sample; it keeps the closed loop stable (see biped_mpc.mpc_cost)
    :param backend: QP solver, one of qp_backends.BACKENDS
    :param leg_outputs: what the MPC tracks of each leg. 'absolute': the leg mass position
        c_l (the paper's C, its reference the midpoint of the planned foot and the planned
        hip); 'torso_relative': c_l - c_t / 2, the leg mass relative to the model's own hip,
        whose reference is half the planned foot (reference_adapter.outputs_from_window with
        the same leg_outputs). With 'torso_relative' a leg that tracks its reference keeps
        its foot, 2 c_l - c_t, on the planned foot wherever the torso moves to place the ZMP,
        and a stance leg stays midway between its sole and the hip as the geometry demands;
        with 'absolute' every centimetre the torso moves away from the planner's hip moves
        the swing foot target by as much and pulls the stance leg mass off the geometry.
        'absolute' is the default here (the paper's model-plant experiments, whose plant has
        free leg masses); the humanoid's WalkingControllerParams default to 'torso_relative'
    """

    dt: float = parameter(0.02, 'control period Ts (s)', low=0.0, high=1.0, low_open=True)
    n_predict: int = parameter(80, 'prediction horizon Np (steps)', low=1, high=1000)
    n_control: int = parameter(20, 'control horizon Nc, the number of input moves', low=1,
                               high=1000)
    move_blocking: str = parameter('spread', 'where the Nc moves act', choices=MOVE_BLOCKINGS)
    move_blocks: tuple = parameter((), 'explicit hold length of each move (steps), Nc entries '
                                   'summing to Np; empty to derive it', low=1)
    constraint_horizon: int = parameter(40, 'first predicted steps whose outputs are '
                                        'constrained (steps)', low=1, high=1000)
    output_weights: tuple = parameter((20.0, 20.0, 20.0), 'weights of the left leg, right leg '
                                      'and ZMP errors', low=0.0)
    input_rate_weights: tuple = parameter((0.1, 0.1, 0.1), 'weights of the jerk increments of '
                                          'the left leg, torso and right leg', low=0.0,
                                          low_open=True)
    input_weights: tuple = parameter((0.0, 0.0, 0.0), 'weights of the jerks themselves',
                                     low=0.0)
    weight_convention: str = parameter('matlab', 'matlab: cost (w e)^2; literal: cost w e^2',
                                       choices=WEIGHT_CONVENTIONS)
    zmp_constraint: str = parameter('hard', 'ZMP inside the support polygon',
                                    choices=CONSTRAINT_MODES)
    landing_constraint: str = parameter('hard', 'swing leg inside its landing box',
                                        choices=CONSTRAINT_MODES)
    soft_quadratic_weight: float = parameter(1e4, 'quadratic penalty of a soft slack (1/m^2)',
                                             low=0.0, high=1e12, low_open=True)
    soft_linear_weight: float = parameter(1e3, 'linear penalty of a soft slack (1/m)', low=0.0,
                                          high=1e12)
    terminal_cost: bool = parameter(True, 'add the infinite-horizon cost-to-go beyond Np')
    backend: str = parameter('daqp', 'QP solver of the MPC', choices=BACKENDS)
    leg_outputs: str = parameter(LEG_OUTPUTS_ABSOLUTE, 'what the MPC tracks of each leg: '
                                 'the leg mass (absolute) or the leg mass minus half the torso '
                                 '(torso_relative)', choices=LEG_OUTPUTS)

    def __post_init__(self) -> None:
        for name, size in (('output_weights', N_OUTPUTS), ('input_rate_weights', N_INPUTS),
                           ('input_weights', N_INPUTS)):
            object.__setattr__(self, name, number_tuple(name, getattr(self, name), size))
        try:
            blocks = tuple(self.move_blocks)
        except TypeError:
            raise ConfigError(f'move_blocks must be a sequence of integers, got '
                              f'{self.move_blocks!r}') from None
        object.__setattr__(self, 'move_blocks', blocks)
        validate_fields(self, ConfigError)
        check_integer('n_predict', self.n_predict, 1, 1000)
        check_integer('n_control', self.n_control, 1, self.n_predict)
        if blocks and (len(blocks) != self.n_control or sum(blocks) != self.n_predict
                       or not all(isinstance(b, int) and b >= 1 for b in blocks)):
            raise ConfigError(f'move_blocks must be {self.n_control} integers >= 1 summing '
                              f'to n_predict={self.n_predict}, got {self.move_blocks!r}')
        check_integer('constraint_horizon', self.constraint_horizon, 1, self.n_predict)

    def quadratic_weights(self, name: str) -> np.ndarray:
        """The coefficients multiplying the squared signals in the QP cost.

        :param name: 'output_weights', 'input_rate_weights' or 'input_weights'
        :return: the weights squared ('matlab' convention) or as given ('literal'), (3,)
        """
        weights = np.asarray(getattr(self, name), dtype=float)
        return weights ** 2 if self.weight_convention == 'matlab' else weights

    @property
    def blocks(self) -> tuple:
        """Hold length of each of the Nc moves (steps), summing to Np."""
        if self.move_blocks:
            return tuple(self.move_blocks)
        if self.move_blocking == 'hold':
            return (1,) * (self.n_control - 1) + (self.n_predict - self.n_control + 1,)
        return default_move_blocks(self.n_predict, self.n_control)
