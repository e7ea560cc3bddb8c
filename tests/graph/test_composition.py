"""Composition: the same nodes, parameters and topics with several nodes in one process.

The graph walks to a goal with the control path (simulator, reference generator, controller)
composed in one process, and with every node in one process (bringup --compose).
"""
from biped_msgs.msg import FootstepPlan
import numpy as np
import pytest

from biped_tools.graph_session import GraphSession, IDLE
from biped_tools.node_graph import CONTROL_PATH, KNOWN_NODES
from ros_harness import domain_id_for_worker

COMPOSITIONS = {
    'control_path': [list(CONTROL_PATH)],
    'all': [list(KNOWN_NODES)],
}


@pytest.mark.parametrize('composition', sorted(COMPOSITIONS))
def test_a_composed_graph_walks_to_a_goal(composition):
    compose = COMPOSITIONS[composition]
    with GraphSession(domain_id_for_worker(), compose=compose, log=print) as session:
        assert len(session.graph.processes) == len(KNOWN_NODES) - len(compose[0]) + 1
        session.wait_until_ready()
        start = np.array(session.series.pelvis[-1])
        # a goal before the map reached the planner is refused (NO_MAP): sent again then
        plan = session.plan_answering(
            lambda: session.send_goal(start[1] + 0.8, start[2] + 0.2, 0.0))
        assert plan is not None, 'no plan answered the goal'
        assert plan.status == FootstepPlan.STATUS_OK, f'plan error {plan.error_code}'
        assert session.spin_until(lambda: session.phase() not in (None, IDLE), 60)
        assert session.spin_until(lambda: session.phase() == IDLE or session.fallen(), 240)
        assert not session.fallen()
        end = np.array(session.series.pelvis[-1])
        plan = session.series.plans[-1]
    assert plan.status == 0
    assert np.hypot(end[1] - start[1] - 0.8, end[2] - start[2] - 0.2) < 0.15
    assert end[3] > 0.5  # standing
