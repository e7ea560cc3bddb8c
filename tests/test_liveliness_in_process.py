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
        token = LivelinessToken(producer, 'composed_test_stream')  # noqa: F841 - kept alive
        assert watch.alive and watch.ever_alive
        assert not other.alive and not other.ever_alive
        producer.destroy_node()  # gone with its node
        assert not watch.alive
    finally:
        rclpy.try_shutdown(context=context)


def test_a_token_of_another_context_is_not_counted_as_composed():
    producer_context, consumer_context = new_context(), new_context()
    try:
        producer = rclpy.create_node('producer', context=producer_context)
        token = LivelinessToken(producer, 'composed_test_stream_2')  # noqa: F841 - kept alive
        consumer = rclpy.create_node('consumer', context=consumer_context)
        assert not LivelinessWatch(consumer, 'composed_test_stream_2').local
    finally:
        rclpy.try_shutdown(context=producer_context)
        rclpy.try_shutdown(context=consumer_context)
