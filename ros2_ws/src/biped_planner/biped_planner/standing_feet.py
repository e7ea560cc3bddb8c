"""Where standing feet are, for the nodes that plan from the measured soles.

The controller sends the measured soles every period, and they creep by micrometres while a
robot settles on its feet. A node that took the newest message would start its references or
its plan from whichever period's soles it happened to read last, which depends on the machine's
load; it holds the feet it has until one of them really moved.
"""
from typing import Sequence, Tuple

from biped_planner.footsteps import Footstep
from biped_planner.rotations import wrap_angle

MOVED_DISTANCE = 0.005  # m: a foot that slid this far was moved (a push, a reset), not settling
MOVED_YAW = 0.02  # rad


def foot_moved(held: Footstep, measured: Footstep, distance: float = MOVED_DISTANCE,
               yaw: float = MOVED_YAW) -> bool:
    """Whether measured is farther than distance (m) or yaw (rad) from held."""
    return (held.x - measured.x) ** 2 + (held.y - measured.y) ** 2 > distance ** 2 or \
        abs(wrap_angle(held.yaw - measured.yaw)) > yaw


def settled_feet(held: Sequence[Footstep], measured: Sequence[Footstep],
                 distance: float = MOVED_DISTANCE, yaw: float = MOVED_YAW) -> Tuple:
    """The held [left, right] feet, or the measured ones once either foot moved (both are
    taken then: a plan starts from one measurement, not from two)."""
    if held is None or any(foot_moved(h, m, distance, yaw) for h, m in zip(held, measured)):
        return tuple(measured)
    return tuple(held)
