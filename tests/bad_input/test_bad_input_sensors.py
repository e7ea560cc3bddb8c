"""Bad input on the controller's and the simulator's side while the robot walks in place.

NaN, inf, huge, empty, mismatched-length, unknown-enum, wrong-frame, out-of-bounds and
backward / future-stamp variants of reference_trajectory, joint_states, odom, the foot wrenches,
zmp, joint_commands and of the services push and set_terrain (bad_input_sensors_cases), each a
second publisher's message beside the real one. For every case: each node that reads the input
is alive and answered it (a /rosout line naming the topic and the rejection, or a refused
service response), and the robot neither fell nor stopped walking: the node kept its previous
valid data. The counts are in output/bad_input/sensors.json and docs/bad_input_suite.md.
"""
import pytest

from bad_input_graph import fuzz_walking_graph
from bad_input_sensors_cases import cases, SERVICES, TOPICS
from bad_input_harness import failures, LOG_SPACING


@pytest.mark.timeout(900)
def test_every_bad_sensor_command_or_service_input_is_refused_out_loud_while_walking():
    results = fuzz_walking_graph('sensors', TOPICS, SERVICES, cases(),
                                 lambda node, topic: LOG_SPACING)
    assert not failures(results), '\n'.join(failures(results))
