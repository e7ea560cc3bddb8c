"""Conversions between the walking controller's data and the MPC controller node's messages."""
import math

from biped_msgs.msg import ControllerDiagnostics
from geometry_msgs.msg import Pose, PoseArray
import numpy as np

from biped_mpc.balance.balance_loop import landing_report
from biped_planner.landing_hold import LANDING_NONE
from biped_planner.rotations import quaternion_from_yaw, quaternion_to_matrix


def sole_poses_msg(feet, stamp, frame_id: str = 'map') -> PoseArray:
    """The soles the controller stands on or moves to: [left, right], x y z and yaw.

    :param feet: (left, right) sole x, y, z (m), yaw (rad)
    """
    msg = PoseArray()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    for target in feet:
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = (float(v) for v in target[:3])
        _, _, pose.orientation.z, pose.orientation.w = (
            float(v) for v in quaternion_from_yaw(target[3]))
        msg.poses.append(pose)
    return msg


def world_velocity(odom) -> np.ndarray:
    """nav_msgs/Odometry gives the twist in the pelvis frame; the controller wants it in the
    world frame (3,) (m/s)."""
    q = odom.pose.pose.orientation
    twist = odom.twist.twist
    return quaternion_to_matrix(np.array([q.x, q.y, q.z, q.w])) @ np.array(
        [twist.linear.x, twist.linear.y, twist.linear.z])


def diagnostics_msg(stamp, status: int, message: str, params, output=None,
                    latency: float = 0.0) -> ControllerDiagnostics:
    """biped_msgs/ControllerDiagnostics of a cycle (output None: no cycle ran)."""
    diag = ControllerDiagnostics()
    diag.header.stamp = stamp
    diag.status = status
    diag.message = message
    diag.model = params.model
    diag.solver = params.mpc.backend
    diag.dt = params.mpc.dt
    if output is not None:
        diag.solve_time = float(output.solve_time)
        diag.cycle_latency = float(latency)
        cost = np.asarray(output.cost, dtype=float)
        diag.cost = float(np.nansum(cost)) if np.any(np.isfinite(cost)) else math.nan
        diag.state_x = np.asarray(output.state[0], dtype=float).tolist()
        diag.state_y = np.asarray(output.state[1], dtype=float).tolist()
        diag.zmp_measured_x, diag.zmp_measured_y = (float(v) for v in output.zmp_measured)
        diag.zmp_estimated_x, diag.zmp_estimated_y = (
            float(v) for v in output.zmp_estimated)
        diag.predicted_zmp_x = [float(output.zmp_predicted[0])]
        diag.predicted_zmp_y = [float(output.zmp_predicted[1])]
        stabilizer_terms(diag, output)
    return diag


def stabilizer_terms(diag: ControllerDiagnostics, output) -> None:
    """The stabilizer's terms of a ControllerOutput, so that a bag shows it work."""
    def floats(values) -> list:
        return [float(v) for v in np.asarray(values, dtype=float).reshape(-1)]
    diag.zmp_desired = floats(output.zmp_desired)
    diag.zmp_error = floats(output.zmp_error)
    diag.dcm_error = floats(output.dcm_error)
    diag.foot_torque_errors = floats(output.foot_torque_errors)
    diag.foot_contacts = [bool(c) for c in output.foot_contacts]
    diag.ankle_offsets = floats(output.ankle_offsets)
    diag.ankle_conformance = floats(output.ankle_conformance)
    diag.vertical_offsets = floats(output.vertical_offsets)
    diag.landing_modes = [str(m) for m in output.landing_modes]
    diag.trunk_tilt = floats(output.trunk_tilt)
    diag.command_leash_shift = floats(output.command_leash_shift)
    diag.dcm_leash_shift = floats(output.dcm_leash_shift)
    diag.lift_held = [bool(h) for h in output.lift_held]


def landing_of(output) -> tuple:
    """BalanceEstimate's landing_modes and landing_depths from a cycle's output (None: no
    cycle yet): 'support' (a foot the plan has on the ground) is 'none' there."""
    if output is None:
        return [LANDING_NONE, LANDING_NONE], [0.0, 0.0]
    return landing_report(output.landing_modes, output.landing_depths)


def deadline_terms(diag: ControllerDiagnostics, monitor) -> None:
    """The deadline accounting of a biped_mpc.deadline_monitor.DeadlineMonitor."""
    report = monitor.report()
    diag.command_deadline = monitor.deadline
    diag.periods, diag.late_periods = report.periods, report.late
    diag.latency_p50, diag.latency_p99, diag.latency_max = report.p50, report.p99, report.max
