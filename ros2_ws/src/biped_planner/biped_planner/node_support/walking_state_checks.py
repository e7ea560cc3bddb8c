"""The check every reader of biped_msgs/WalkingState makes before believing one."""
import math
from typing import Optional

from biped_msgs.msg import WalkingState

WALKING = (WalkingState.INITIALIZE, WalkingState.SINGLE_SUPPORT, WalkingState.DOUBLE_SUPPORT)


def walking_state_problem(msg: WalkingState, now: Optional[float] = None,
                          max_lead: float = 1.0) -> Optional[str]:
    """Why a walking_state cannot be believed, None when it can.

    :param now: the reader's clock (s); None: the walk start is not compared with it
    :param max_lead: how far ahead of now a walk may start (s)
    """
    if msg.phase > WalkingState.FALLEN or msg.support_foot > WalkingState.SUPPORT_DOUBLE:
        return f'phase {msg.phase} or support_foot {msg.support_foot} unknown'
    times = (msg.time_in_phase, msg.phase_duration, msg.walk_start_time, msg.stop_time)
    if not all(math.isfinite(v) and v >= 0.0 for v in times):
        return (f'times must be finite and >= 0: time_in_phase {msg.time_in_phase}, '
                f'phase_duration {msg.phase_duration}, walk_start_time {msg.walk_start_time}, '
                f'stop_time {msg.stop_time}')
    if now is not None and msg.phase in WALKING and msg.walk_start_time > now + max_lead:
        return f'walk_start_time {msg.walk_start_time} is ahead of the clock ({now:.3f} s)'
    return None
