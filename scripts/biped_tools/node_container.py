"""Run several nodes of the graph in one process, on one executor (composition).

rclpy has no component container; this is its idea for the stack's own nodes: the node
classes, parameters and topics are the ones of the separate processes, each node built with
its own command-line arguments (parameter file, -p overrides, remaps) and none of the
process's global ones. `scripts/bringup.py --compose` starts it.

    python scripts/node_container.py '{"simulator": ["--ros-args", ...], ...}'
"""
import importlib
import json
import sys
from typing import Callable, Dict, List

from biped_planner.node_support.node_runner import run_nodes
from biped_tools.node_graph import KNOWN_NODES


def node_factory(class_path: str, name: str, ros_args: List[str]) -> Callable:
    """A callable that builds the node class_path ('module:Class') with its own arguments."""
    module, _, class_name = class_path.partition(':')
    node_class = getattr(importlib.import_module(module), class_name)

    def make():
        return node_class(cli_args=list(ros_args), use_global_arguments=False)
    make.__name__ = f'make_{name}'
    return make


def parse_spec(text: str) -> Dict[str, List[str]]:
    """The container's argument: a JSON object node name -> that node's ROS arguments."""
    spec = json.loads(text)
    if not isinstance(spec, dict) or not spec or not all(
            isinstance(args, list) and all(isinstance(a, str) for a in args)
            for args in spec.values()):
        raise ValueError('expected a JSON object: node name -> list of ROS arguments')
    return spec


def main(argv=None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 1:
        print(__doc__, file=sys.stderr)
        return 2
    try:
        spec = parse_spec(argv[0])
    except ValueError as error:
        print(f'[node_container] error: {error}', file=sys.stderr)
        return 2
    unknown = [name for name in spec if name not in KNOWN_NODES]
    if unknown:
        print(f'[node_container] error: unknown nodes {unknown}; known: {list(KNOWN_NODES)}',
              file=sys.stderr)
        return 2
    try:
        run_nodes([node_factory(KNOWN_NODES[name].node_class, name, args)
                   for name, args in spec.items()])
    except Exception as error:  # noqa: B902 - one clear line, as a node process would give
        print(f'[node_container] error: {type(error).__name__}: {error}', file=sys.stderr)
        return 1
    return 0
