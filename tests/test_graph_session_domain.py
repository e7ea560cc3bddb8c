"""A graph session refuses a ROS domain where another graph's nodes already run (a run killed
without its cleanup leaves them walking, and their messages would mix into the new run)."""
import pytest
import rclpy

from biped_tools.graph_session import GraphSession
from ros_harness import domain_id_for_worker


def test_a_domain_with_another_graphs_node_is_refused_before_anything_starts():
    domain = domain_id_for_worker()
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=domain)
    stray = rclpy.create_node('state_machine', context=context)
    try:
        session = GraphSession(domain, log=print)
        with pytest.raises(RuntimeError, match=r"domain \d+ already runs \['state_machine'\]"):
            session.start()
        assert not session.graph.processes  # no node process was started
    finally:
        stray.destroy_node()
        context.try_shutdown()
