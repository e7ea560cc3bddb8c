"""Bad input on the user's and the planner's side while the robot walks in place.

NaN, inf, huge, empty, mismatched-length, unknown-enum, wrong-frame, out-of-bounds and
wrong-state variants of walk_command, goal_pose, cmd_vel, map, footstep_plan, walking_state,
sole_poses, balance_estimate, step_adjustment and of the services plan_walk and reset
(bad_input_commands_cases). For every case:
each node that reads the input is alive and answered it (a /rosout line naming the topic and
the rejection, a refused walk_command_status or service response), and the robot neither fell
nor stopped walking. The counts are in output/bad_input/commands.json and
docs/bad_input_suite.md.
"""
import pytest

from bad_input_commands_cases import cases, GRAPH_OVERRIDES, SERVICES, TOPICS
from bad_input_graph import fuzz_walking_graph
from bad_input_harness import failures, LOG_SPACING


@pytest.mark.timeout(900)
def test_every_bad_input_on_the_command_side_is_refused_out_loud_while_walking():
    results = fuzz_walking_graph('commands', TOPICS, SERVICES, cases(),
                                 lambda node, topic: LOG_SPACING, GRAPH_OVERRIDES)
    assert not failures(results), '\n'.join(failures(results))
