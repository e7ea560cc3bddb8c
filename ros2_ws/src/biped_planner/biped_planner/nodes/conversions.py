"""Conversions between biped_msgs / standard messages and biped_planner library values.

All message imports of biped_planner live in its nodes package; the library never sees a message.
"""
from biped_msgs.msg import CommandStatus, WalkCommand as WalkCommandMsg, WalkingState

from biped_planner.walk_command import CommandLimits, WalkCommand
from biped_planner.walking_state_machine import WalkingStatus


def walk_command_from_msg(msg: WalkCommandMsg, limits: CommandLimits) -> WalkCommand:
    """:raises CommandError: when a field is unknown, not finite or out of range."""
    return WalkCommand.from_fields(
        msg.command, (msg.goal_x, msg.goal_y, msg.goal_yaw),
        (msg.step_length, msg.step_width, msg.step_angle), msg.step_time, limits)


def walking_state_msg(status: WalkingStatus, now: float, stamp, plan_id: int,
                      inputs_stale: bool) -> WalkingState:
    msg = WalkingState()
    msg.header.stamp = stamp
    msg.phase = int(status.phase)
    msg.support_foot = int(status.support)
    msg.step_index = int(status.step_index)
    msg.time_in_phase = float(status.time_in_phase(now))
    msg.phase_duration = float(status.phase_duration)
    msg.walk_start_time = float(status.walk_start)
    msg.plan_id = int(plan_id)
    msg.fallen = status.fallen
    msg.stop_requested = status.stop_requested
    msg.inputs_stale = inputs_stale
    msg.reason = status.reason
    return msg


def command_status_msg(node_name: str, command: int, error_code: int, error_msg: str,
                       stamp) -> CommandStatus:
    msg = CommandStatus()
    msg.header.stamp = stamp
    msg.node = node_name
    msg.command = max(0, min(255, int(command)))
    msg.accepted = error_code == CommandStatus.OK
    msg.error_code = error_code
    msg.error_msg = error_msg
    return msg
