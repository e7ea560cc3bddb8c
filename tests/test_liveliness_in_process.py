"""LivelinessWatch in a composed process: a producer in the same process counts as alive.

DDS raises no liveliness event between the readers and writers of one participant, and nodes
composed in one process share it; without this the simulator would never see a composed
controller alive and would fall back to its wall-time timeout.
"""
import rclpy

from biped_planner.node_support.liveliness import LivelinessToken, LivelinessWatch
from ros_harness import new_context


def test_a_token_of_this_process_makes_its_stream_alive_and_no_other():
    context = new_context()
    try:
        consumer = rclpy.create_node('consumer', context=context)
        watch = LivelinessWatch(consumer, 'composed_test_stream')
        other = LivelinessWatch(consumer, 'composed_test_other_stream')
        assert not watch.alive and not watch.ever_alive
        producer = rclpy.create_node('producer', context=context)
        LivelinessToken(producer, 'composed_test_stream')
        assert watch.alive and watch.ever_alive
        assert not other.alive and not other.ever_alive
    finally:
        rclpy.try_shutdown(context=context)
