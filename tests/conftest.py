"""Fixtures for node and graph tests: own rclpy context per test, own ROS_DOMAIN_ID per worker,
discovery on localhost only, and real processes that are always torn down."""
import os

import pytest

# pytest puts this directory (no __init__.py: rootdir-relative "prepend" import mode) on sys.path
# before it imports this file, so the harness imports as a top-level module.
from ros_harness import domain_id_for_worker, new_context, ProcessGroup

os.environ['ROS_AUTOMATIC_DISCOVERY_RANGE'] = 'LOCALHOST'
os.environ['ROS_DOMAIN_ID'] = str(domain_id_for_worker())


@pytest.fixture
def ros_context():
    """A fresh rclpy context for one test; nodes made on it must be destroyed by the test."""
    import rclpy
    context = new_context()
    yield context
    rclpy.try_shutdown(context=context)


@pytest.fixture
def executor(ros_context):
    from rclpy.executors import SingleThreadedExecutor
    executor = SingleThreadedExecutor(context=ros_context)
    nodes = []

    def track(node):
        """Spin the node with this executor and destroy it after the test."""
        nodes.append(node)
        executor.add_node(node)
        return node

    executor.track = track
    yield executor
    for node in nodes:
        executor.remove_node(node)
        node.destroy_node()
    executor.shutdown()


@pytest.fixture
def processes():
    """Start real processes with processes.start([...]); all are stopped after the test."""
    group = ProcessGroup()
    yield group
    group.stop_all()


# Whole node graphs on a shared 2-core machine: a graph test that fails runs once more, and
# every rerun is listed in the summary (R). docs/flaky_graph_tests.md keeps what they were.
RERUN_DIRECTORIES = ('graph', 'bad_input')


def pytest_collection_modifyitems(config, items):
    for item in items:
        if item.path.parent.name in RERUN_DIRECTORIES:
            item.add_marker(pytest.mark.flaky(reruns=1))


# Why a rerun test failed the first time: the rerun plugin lists it without its message, and
# the flaky page had "message not kept" for most rows.
FIRST_FAILURES = []
FIRST_FAILURE_CHARS = 4000  # the end of the report: the assertion and the lines before it
# The end of what the test printed: a graph test's node logs (GraphSession(log=print)), the
# nodes' own account of what went wrong before the assertion.
FIRST_FAILURE_OUTPUT_CHARS = 6000


def pytest_runtest_logreport(report):
    if report.outcome == 'rerun':
        output = (report.capstdout + report.capstderr)[-FIRST_FAILURE_OUTPUT_CHARS:]
        FIRST_FAILURES.append((report.nodeid, report.longreprtext[-FIRST_FAILURE_CHARS:],
                               output))


def pytest_terminal_summary(terminalreporter):
    for nodeid, text, output in FIRST_FAILURES:
        terminalreporter.write_sep('-', f'first failure of {nodeid} (it ran again)')
        terminalreporter.write_line(text)
        if output:
            terminalreporter.write_sep('-', 'the end of its output')
            terminalreporter.write_line(output)
