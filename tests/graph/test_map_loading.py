"""Graph test: a user's map file. `bringup.py --map` with the paper's PGM map, the goal sent with
the README's `ros2 topic pub --once goal_pose` line, and the humanoid walks START -> GOAL around
the obstacles of that file (the demo's walk: 40-60 s of wall time)."""
import math
import subprocess

from biped_msgs.msg import FootstepPlan, WalkingState
from nav_msgs.msg import Odometry
import rclpy
from rclpy.parameter import Parameter
from rclpy.qos import DurabilityPolicy, QoSProfile

from biped_planner.example_maps import paper_start_goal_example
from biped_planner.map_file import load_map
from ros_harness import Collector, OutputLines, PYTHON, REPO, ros_environment, spin_until

BRINGUP = str(REPO / 'scripts' / 'bringup.py')
CLI = str(REPO / 'scripts' / 'ros2_cli.py')
PGM_MAP = REPO / 'ros2_ws' / 'src' / 'biped_planner' / 'maps' / 'paper_start_goal.yaml'
# The README's goal line, word for word after `ros2`.
GOAL_LINE = ['topic', 'pub', '--once', 'goal_pose', 'geometry_msgs/msg/PoseStamped',
             '{header: {frame_id: map}, pose: {position: {x: 3.4, y: 3.4}, '
             'orientation: {z: 0.707, w: 0.707}}}']
LATCHED = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL)


def test_bringup_with_a_pgm_map_file_walks_start_to_goal(processes, ros_context, executor):
    _, start, goal = paper_start_goal_example()
    grid = load_map(PGM_MAP)
    bringup = processes.start(
        [PYTHON, BRINGUP, '--map', str(PGM_MAP),  # sim time without --sim-time
         '-p', f'simulator:start_x:={start.x}', '-p', f'simulator:start_y:={start.y}',
         '-p', f'simulator:start_yaw:={start.yaw}'],
        stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, bufsize=1)
    output = OutputLines(bringup)
    output.wait_for_line(r'all nodes up', timeout=60)
    output.wait_for_line(r'\[map_server *\] .*serving map from .*paper_start_goal\.yaml: 40 x 40 '
                    r'cells of 0\.1 m', timeout=10)
    obstacles = output.wait_for_line(r'\[simulator *\] .*?(\d+) obstacle boxes from the map', 30)
    assert int(obstacles.group(1)) > 0

    client = executor.track(rclpy.create_node('map_loading_client', context=ros_context,
                                              parameter_overrides=[
                                                  Parameter('use_sim_time', value=True)]))
    states = Collector(client, WalkingState, 'walking_state', 50)
    odometry = Collector(client, Odometry, 'odom', 50)
    plans = Collector(client, FootstepPlan, 'footstep_plan', LATCHED)
    # The robot stands and the controller runs before the user sends the goal.
    assert odometry.wait_for(executor, lambda m: len(m) > 100, timeout=120)
    assert states.wait_for(executor, timeout=30)
    sent = subprocess.run([PYTHON, CLI, *GOAL_LINE], env=ros_environment(),
                          capture_output=True, text=True, timeout=60)
    assert sent.returncode == 0, sent.stderr
    assert plans.wait_for(executor, lambda m: any(p.status == FootstepPlan.STATUS_OK
                                                  for p in m), timeout=60), \
        [(p.status, p.error_msg) for p in plans.messages]
    plan = [p for p in plans.messages if p.status == FootstepPlan.STATUS_OK][-1]
    walking = (WalkingState.INITIALIZE, WalkingState.SINGLE_SUPPORT,
               WalkingState.DOUBLE_SUPPORT)
    assert states.wait_for(executor, lambda m: m[-1].phase in walking, timeout=60)
    assert spin_until(executor, lambda: states.messages[-1].phase == WalkingState.IDLE or
                      any(s.fallen for s in states.messages), timeout=400)
    spin_until(executor, lambda: False, timeout=2.0)   # the hip settles
    assert not any(s.fallen for s in states.messages)
    assert bringup.poll() is None, 'the graph stopped'

    # Around the obstacles of the file: every footstep on a free cell of the loaded map.
    for step in plan.footsteps:
        row, col = grid.world_to_cell(step.x, step.y)
        assert grid.values[row, col] == 0, (step.x, step.y)
    final = odometry.messages[-1].pose.pose.position
    assert math.hypot(final.x - goal.x, final.y - goal.y) <= 0.15, (final.x, final.y)


def test_a_bad_map_file_stops_the_bringup_naming_the_file_and_the_field(tmp_path):
    bad = tmp_path / 'bad.yaml'
    bad.write_text('image: paper.pgm\nresolution: -0.1\norigin: [0.0, 0.0, 0.0]\n')
    result = subprocess.run([PYTHON, BRINGUP, '--nodes', 'map_server', '--map', str(bad)],
                            env=ros_environment(), capture_output=True, text=True, timeout=120)
    output = result.stdout + result.stderr
    assert result.returncode == 1, output
    assert f'{bad}: resolution must be > 0 m, got -0.1' in output
    assert 'node map_server died (exit code 1)' in output


def test_a_missing_map_file_is_refused_before_anything_starts(tmp_path):
    result = subprocess.run([PYTHON, BRINGUP, '--map', str(tmp_path / 'none.yaml')],
                            env=ros_environment(), capture_output=True, text=True, timeout=60)
    assert result.returncode == 2
    assert f'--map {tmp_path / "none.yaml"}: no such file' in result.stderr
    assert 'started' not in result.stdout
