"""The graph a bad-input module fuzzes: every node (map_server too when installed), the robot
walking in place, and the checks every module makes at its end."""
from pathlib import Path

from biped_tools.graph_session import ALL_NODES, GraphSession
from biped_tools.node_graph import available_nodes

from bad_input_harness import (failures, Fuzzer, run_cases, summary, WALKING, write_report)
from ros_harness import domain_id_for_worker

REPORT_DIR = Path(__file__).resolve().parents[2] / 'output' / 'bad_input'
STANDING_HEIGHT = 0.5  # m: the pelvis of the standing or walking robot is above this


def graph_nodes() -> list:
    nodes = list(ALL_NODES)
    if 'map_server' in available_nodes() and 'map_server' not in nodes:
        nodes.append('map_server')
    return nodes


def fuzz_walking_graph(name: str, topics, services, cases, spacing, overrides=None) -> list:
    """Start the graph, walk in place, send every case; :return: the CaseResults.

    :param overrides: node parameters, {node: ['name:=value', ...]}

    Asserts what holds for the whole run: every node alive at the end, the robot standing and
    still walking in place (its step index went on).
    """
    with GraphSession(domain_id_for_worker(), nodes=graph_nodes(), keep_going=True,
                      overrides=overrides, log=print) as session:
        session.wait_until_ready(120.0)
        fuzzer = Fuzzer(session, topics, services, spacing)
        fuzzer.start_walking()
        first_step = fuzzer.state().step_index
        results = run_cases(fuzzer, cases)
        path = write_report(name, results, REPORT_DIR)
        print(f'[bad_input] {name}: {summary(results)} ({path})')
        for line in failures(results):
            print(f'[bad_input] FAILED {line}')
        assert session.spin_until(lambda: fuzzer.heights, 10.0)
        dead = fuzzer.dead()
        height = fuzzer.heights[-1][1]
        state = fuzzer.state()
        assert not dead, f'nodes died: {dead}'
        assert height > STANDING_HEIGHT, f'the robot is not standing (pelvis at {height:.2f} m)'
        assert state.phase in WALKING and not state.fallen, \
            f'not walking at the end: phase {state.phase}, {state.reason!r}'
        assert state.epoch != 0 or state.step_index > first_step, 'the walk did not go on'
    return results
