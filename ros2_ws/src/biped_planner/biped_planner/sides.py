"""Foot sides and support labels: one name per meaning, the values of biped_msgs.

Footstep.side, WalkingState.support and ReferenceTrajectory.support use these numbers; the
libraries of every package import them from here.
"""
LEFT = 0
RIGHT = 1
SIDES = (LEFT, RIGHT)

SUPPORT_LEFT = 0
SUPPORT_RIGHT = 1
SUPPORT_DOUBLE = 2


def other_side(side: int) -> int:
    """The other foot."""
    return RIGHT if side == LEFT else LEFT
