"""Node-level test of where the footstep planner starts a plan: from the feet the robot stands
on now, also when the goal comes in the very period a walk ends. Real rclpy and DDS, sim time
driven by the test."""
from biped_msgs.msg import FootstepPlan, WalkingState
from biped_msgs.srv import PlanWalk
from geometry_msgs.msg import Pose, PoseArray, PoseStamped
import numpy as np
import rclpy
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile
from nav_msgs.msg import OccupancyGrid as OccupancyGridMsg

from biped_planner.node_support.map_messages import grid_to_msg
from biped_planner.nodes.footstep_planner import FootstepPlannerNode
from biped_planner.occupancy_grid import OccupancyGrid
from ros_harness import Collector, SimClock, spin_until, wait_for_subscribers

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL)


def sole_poses(x: float) -> PoseArray:
    msg = PoseArray()
    msg.header.frame_id = 'map'
    for y in (0.07, -0.07):
        pose = Pose()
        pose.position.x, pose.position.y, pose.orientation.w = x, y, 1.0
        msg.poses.append(pose)
    return msg


def test_a_goal_in_the_period_a_walk_ends_is_planned_from_where_the_feet_landed(
        ros_context, executor):
    executor.track(FootstepPlannerNode(context=ros_context, parameter_overrides=[
        Parameter('use_sim_time', value=True)]))
    client = executor.track(rclpy.create_node('planner_start_client', context=ros_context))
    clock = SimClock(client, executor)
    plans = Collector(client, FootstepPlan, 'footstep_plan', LATCHED)
    grid = client.create_publisher(OccupancyGridMsg, 'map', LATCHED)
    soles = client.create_publisher(PoseArray, 'sole_poses', 10)
    state = client.create_publisher(WalkingState, 'walking_state', 10)
    for publisher in (grid, soles, state, clock.publisher):
        assert wait_for_subscribers(executor, publisher, timeout=15)
    grid.publish(grid_to_msg(OccupancyGrid(np.zeros((200, 200), dtype=np.int8), 0.05,
                                           (-5.0, -5.0)), 'map', client.get_clock().now().to_msg()))
    soles.publish(sole_poses(0.0))
    clock.advance(0.1)
    plan_walk = client.create_client(PlanWalk, 'plan_walk')
    assert spin_until(executor, plan_walk.service_is_ready, 15.0), 'no plan_walk'

    state.publish(WalkingState(phase=WalkingState.INITIALIZE,
                               support_foot=WalkingState.SUPPORT_DOUBLE))
    clock.advance(0.05)
    soles.publish(sole_poses(0.3))  # walked: the feet landed 0.3 m ahead
    clock.advance(0.05)
    state.publish(WalkingState(phase=WalkingState.IDLE, support_foot=WalkingState.SUPPORT_DOUBLE))
    clock.advance(0.02)  # the goal comes before the next sole_poses
    goal = PoseStamped()
    goal.header.frame_id = 'map'
    goal.pose.position.x, goal.pose.orientation.w = 1.0, 1.0
    count = len(plans.messages)
    future = plan_walk.call_async(PlanWalk.Request(request_id=1, kind=PlanWalk.Request.KIND_GOAL,
                                                   goal=goal))
    assert spin_until(executor, future.done, 10.0) and future.result().accepted
    assert plans.wait_for(executor, lambda m: len(m) > count, 10.0), 'no plan'
    start = plans.messages[-1].footsteps[:2]
    assert [round(f.x, 3) for f in start] == [0.3, 0.3], [(f.side, f.x, f.y) for f in start]
