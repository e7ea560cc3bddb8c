"""A graph session refuses a ROS domain where another graph's simulator runs (a run killed
without its cleanup leaves its nodes walking, and their messages would mix into the new run), and
not one where a node of another test was only seen."""
from builtin_interfaces.msg import Time
import pytest
import rclpy
from rosgraph_msgs.msg import Clock

from biped_tools.graph_session import GraphSession
from ros_harness import domain_id_for_worker


def test_a_domain_with_another_simulators_clock_is_refused_before_anything_starts():
    domain = domain_id_for_worker()
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=domain)
    stray = rclpy.create_node('simulator', context=context)
    clock = stray.create_publisher(Clock, '/clock', 10)
    stray.create_timer(0.01, lambda: clock.publish(Clock(clock=Time(sec=438))))
    executor = rclpy.executors.SingleThreadedExecutor(context=context)
    executor.add_node(stray)
    import threading
    spinning = threading.Thread(target=executor.spin, daemon=True)
    spinning.start()
    try:
        session = GraphSession(domain, log=print)
        with pytest.raises(RuntimeError, match=r'domain \d+ already has a clock running'):
            session.start()
        assert not session.graph.processes  # no node process was started
    finally:
        executor.shutdown()
        stray.destroy_node()
        context.try_shutdown()
