"""GraphSession.push tells a refused push from an unanswered one, against a real Push service.

A lost answer (seen under heavy load) is not a refusal: the push may have been applied, and a
trial must not read it as one that was not made.
"""
import threading

import pytest
import rclpy
from biped_msgs.srv import Push

from biped_tools.graph_session import GraphSession
from ros_harness import domain_id_for_worker


@pytest.fixture
def push_server():
    """start(answer) serves 'push' answering success=answer; answer None never answers."""
    domain = domain_id_for_worker()
    context = rclpy.Context()
    rclpy.init(context=context, domain_id=domain)
    node = rclpy.create_node('simulator_double', context=context)
    executor = rclpy.executors.SingleThreadedExecutor(context=context)
    executor.add_node(node)
    requests = []

    def start(answer):
        def on_push(request, response):
            requests.append(request)
            response.success = bool(answer)
            return response
        node.create_service(Push, 'push', on_push)
        if answer is not None:  # never spun: the request is never taken, never answered
            threading.Thread(target=executor.spin, daemon=True).start()
        return domain, requests
    yield start
    executor.shutdown()
    node.destroy_node()
    context.try_shutdown()


def session_on(domain):
    """A session with no node of its own: the service double is the only 'push'."""
    session = GraphSession(domain, nodes=[], log=lambda text: None)
    session.start(timeout=10.0)
    return session


@pytest.mark.parametrize('answer', [True, False])
def test_an_answer_is_returned(push_server, answer):
    domain, requests = push_server(answer)
    session = session_on(domain)
    try:
        assert session.push(80.0, 10.0, duration=0.1, at=12.5) is answer
    finally:
        session.stop()
    assert len(requests) == 1
    assert (requests[0].force.x, requests[0].force.y) == (80.0, 10.0)
    assert (requests[0].start.sec, requests[0].start.nanosec) == (12, 500_000_000)


def test_no_answer_is_a_timeout_not_a_refusal(push_server):
    domain, _ = push_server(None)
    session = session_on(domain)
    try:
        with pytest.raises(TimeoutError, match='did not answer in 1 s; the push may have'):
            session.push(80.0, timeout=1.0)
    finally:
        session.stop()
