"""Lift-off gate: a foot the plan lifts stays down while the robot stands on it.

A push towards the stance foot drives the DCM over that foot's outer half; the swing foot lands
on the far side, where it takes no load, and the robot rolls onto the stance foot's edge with
the landed foot in the air. The plan then lifts the stance foot, the one carrying the robot:
its leg shortens under the whole weight and the robot falls onto that side. Held on the ground
instead, the foot keeps the centre of pressure at its outer edge, beyond the DCM, which brings
the DCM back until the other foot is loaded; then it lifts, late, and its swing catches up with
the plan. The DCM must be over the foot: a foot that carries the load because the DCM is
leaving it sideways (a push towards the swing foot) is stepping to catch it, and holding that
step fells the robot. Only the lift-off waits: once the foot is released in a swing it is not
held again before it lands (a foot that lands early is the landing logic's). The plan's timing
is kept; only the foot's height waits, at most `max_hold` s per swing.
"""
from dataclasses import dataclass

import numpy as np

from biped_mpc.balance.dcm_feedback import project_into_polygon, rectangle_vertices
from biped_mpc.errors import ConfigError
from biped_mpc.validation import check_period
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.sides import SIDES


@dataclass(frozen=True)
class LiftOffGateParams:
    """Load and DCM conditions and the longest hold of the lift-off gate (see LiftOffGate)."""

    load_share: float = parameter(
        0.75, 'share of the measured normal load of both feet on the foot the plan lifts above '
        'which that foot stays on the ground', low=0.5, high=1.0)
    min_load: float = parameter(
        50.0, 'both feet together carry at least this normal force for a hold (N): a robot '
        'in the air holds nothing', low=0.0, high=1e4)
    dcm_margin: float = parameter(
        0.0, 'the DCM may be this far outside the sole rectangle for a hold (m)',
        low=-0.05, high=0.2)
    max_hold: float = parameter(0.3, 'longest hold in one swing (s): then the plan lifts it',
                                low=0.0, high=1.0)
    sole_length: float = parameter(0.2, 'sole length along the foot (m)', low=0.01, high=1.0)
    sole_width: float = parameter(0.1, 'sole width across the foot (m)', low=0.01, high=1.0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


class LiftOffGate:
    """Which foot the plan lifts stays on the ground this cycle (one per swing, both sides).

    :param params: conditions and longest hold
    """

    def __init__(self, params: LiftOffGateParams = LiftOffGateParams()) -> None:
        self.params = params
        self.reset()

    def reset(self) -> None:
        """No foot held, no hold time spent, no lift-off seen."""
        self.held = [False, False]
        self._spent = np.zeros(2)
        self._released = [False, False]  # this swing's lift-off has happened

    def update(self, dt: float, lifting, normal_forces, dcm, sole_positions,
               sole_yaws) -> list:
        """One control period.

        :param dt: period (s), > 0
        :param lifting: (left, right) True for the foot the plan has in the air while the other
            is its support (a single support's swing foot)
        :param normal_forces: (left, right) measured normal forces on the soles (N)
        :param dcm: (2,) measured DCM (m)
        :param sole_positions: (left, right) measured sole centres, world (m)
        :param sole_yaws: (left, right) measured sole headings (rad)
        :return: (left, right) True for a foot to keep on the ground this cycle
        """
        check_period(dt)
        p = self.params
        forces = [max(float(f), 0.0) for f in normal_forces]
        total = forces[0] + forces[1]
        for side in SIDES:
            if not (lifting[side] and not lifting[1 - side]):
                self._spent[side] = 0.0
                self._released[side] = False
                self.held[side] = False
                continue
            standing_on = total >= p.min_load and forces[side] > p.load_share * total and \
                self._over_sole(dcm, sole_positions[side], sole_yaws[side])
            self.held[side] = bool(not self._released[side] and standing_on and
                                   self._spent[side] + dt <= p.max_hold + 1e-9)
            if self.held[side]:
                self._spent[side] += dt
            else:
                self._released[side] = True
        return list(self.held)

    def _over_sole(self, dcm, sole_position, sole_yaw: float) -> bool:
        """The DCM over the sole rectangle widened by dcm_margin on every side, edges included
        (as run_log's ZMP-inside check)."""
        p = self.params
        corners = rectangle_vertices(sole_position, sole_yaw,
                                     max(p.sole_length + 2.0 * p.dcm_margin, 0.0),
                                     max(p.sole_width + 2.0 * p.dcm_margin, 0.0))
        return project_into_polygon(dcm, corners)[1]
