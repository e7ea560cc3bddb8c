"""The biped node graph as processes: one per node, like `ros2 launch` (not available here).

NodeGraph starts each selected node with its parameter file, waits until every node is on the ROS
graph, forwards their logs with a [node] prefix, and stops the whole graph (SIGINT, wait,
SIGKILL), or reports the node that died. The command line is `scripts/bringup.py`
(biped_tools.bringup); GraphSession uses it in process.
"""
from dataclasses import dataclass, field
import json
import os
from pathlib import Path
import signal
import subprocess
import sys
import threading
import time
from typing import Dict, List, Optional

from biped_tools.paths import INSTALL


@dataclass(frozen=True)
class NodeSpec:
    """How to start one node: its package, executable and default parameter file."""

    name: str
    package: str
    executable: str
    node_class: str  # 'module:Class', for composition (biped_tools.node_container)

    @property
    def default_params(self) -> Path:
        return INSTALL / self.package / 'share' / self.package / 'config' / f'{self.name}.yaml'

    @property
    def program(self) -> Path:
        return INSTALL / self.package / 'lib' / self.package / self.executable


# Start order: producers of latched data first.
KNOWN_NODES: Dict[str, NodeSpec] = {spec.name: spec for spec in [
    NodeSpec('simulator', 'biped_sim', 'simulator', 'biped_sim.nodes.simulator:SimulatorNode'),
    NodeSpec('map_server', 'biped_planner', 'map_server',
             'biped_planner.nodes.map_server:MapServerNode'),
    NodeSpec('state_machine', 'biped_planner', 'state_machine',
             'biped_planner.nodes.state_machine:StateMachineNode'),
    NodeSpec('footstep_planner', 'biped_planner', 'footstep_planner',
             'biped_planner.nodes.footstep_planner:FootstepPlannerNode'),
    NodeSpec('reference_generator', 'biped_planner', 'reference_generator',
             'biped_planner.nodes.reference_generator:ReferenceGeneratorNode'),
    NodeSpec('mpc_controller', 'biped_mpc', 'mpc_controller',
             'biped_mpc.nodes.mpc_controller:MpcControllerNode'),
]}

# The control path: what runs every control period in lockstep (bringup --compose control).
# A topic each node publishes from its start: the lockstep clock starts once all of the graph's
# have a publisher (simulator wait_for_publishers), so a command sent when the graph is up meets
# it at the same sim time however slowly the processes started.
STARTUP_TOPICS = {'map_server': 'map', 'state_machine': 'walking_state',
                  'footstep_planner': 'footstep_plan',
                  'reference_generator': 'reference_trajectory'}
CONTROL_PATH = ('simulator', 'reference_generator', 'mpc_controller')
CONTAINER = Path(__file__).resolve().parent.parent / 'node_container.py'


# Nodes not given use_sim_time: the simulator makes the clock, and the controller keeps time by
# the stamps of its inputs (its timers are wall-clock), so /clock would only wake it up.
CLOCK_FREE_NODES = ('simulator', 'mpc_controller')
STACK_DUMP_WAIT = 1.0  # s for a hung node to write its stacks before SIGKILL


def available_nodes() -> List[str]:
    """The known nodes whose executable is installed, in start order."""
    return [name for name, spec in KNOWN_NODES.items() if spec.program.exists()]


@dataclass
class GraphOptions:
    """What to start and how.

    :param nodes: node names, in KNOWN_NODES
    :param params_files: node name -> parameter file replacing its default one
    :param overrides: node name -> ['param:=value', ...] given with -p on the command line
    :param domain_id: ROS_DOMAIN_ID of every process (None: inherit)
    :param backend: simulator backend ('pybullet' or 'model')
    :param gui: open the simulator's GUI window
    :param use_sim_time: every node follows the simulator's /clock
    :param keep_going: when a node dies, report it and keep the others running (to test how
        the graph copes); by default the whole graph stops
    :param map_file: the map the map_server serves (a nav2 map YAML file); None: an empty map
        centred on the simulator's start pose
    :param compose: groups of nodes each run in one process (composition); the nodes in no
        group run one per process
    """

    nodes: List[str]
    params_files: Dict[str, Path] = field(default_factory=dict)
    overrides: Dict[str, List[str]] = field(default_factory=dict)
    domain_id: Optional[int] = None
    backend: str = 'pybullet'
    gui: bool = False
    use_sim_time: bool = False
    keep_going: bool = False
    map_file: Optional[Path] = None
    compose: List[List[str]] = field(default_factory=list)


def process_groups(nodes: List[str], compose: List[List[str]]) -> List[List[str]]:
    """The processes to start, in start order: each compose group (its nodes in start order)
    at the place of its first node, every other node alone.

    :raises ValueError: a composed node that is not started, or in two groups
    """
    seen = set()
    for group in compose:
        for name in group:
            if name not in nodes:
                raise ValueError(f'--compose names {name!r}, which is not started '
                                 f'(nodes: {nodes})')
            if name in seen:
                raise ValueError(f'--compose names {name!r} in two groups')
            seen.add(name)
    groups, placed = [], set()
    for name in nodes:
        if name in placed:
            continue
        group = next((g for g in compose if name in g), [name])
        group = [n for n in nodes if n in group]
        groups.append(group)
        placed.update(group)
    return groups


class NodeGraph:
    """The node processes of one bring-up."""

    def __init__(self, options: GraphOptions, log=print) -> None:
        unknown = [n for n in options.nodes if n not in KNOWN_NODES]
        if unknown:
            raise ValueError(f'unknown nodes {unknown}; known: {list(KNOWN_NODES)}')
        missing = [n for n in options.nodes if not KNOWN_NODES[n].program.exists()]
        if missing:
            raise FileNotFoundError(
                f'nodes {missing} are not installed under {INSTALL}; run scripts/setup.sh')
        self.groups = process_groups(list(options.nodes), [list(g) for g in options.compose])
        self.options = options
        self.log = log
        self.processes: Dict[str, subprocess.Popen] = {}
        self._threads: List[threading.Thread] = []
        self._stopping = False
        self._reported_dead = set()

    def environment(self) -> dict:
        env = dict(os.environ)
        env.setdefault('ROS_AUTOMATIC_DISCOVERY_RANGE', 'LOCALHOST')
        if self.options.domain_id is not None:
            env['ROS_DOMAIN_ID'] = str(self.options.domain_id)
        env['PYTHONUNBUFFERED'] = '1'
        env['RCUTILS_COLORIZED_OUTPUT'] = '0'
        env['RCUTILS_CONSOLE_OUTPUT_FORMAT'] = '[{severity}] {message}'
        return env

    def command(self, name: str) -> List[str]:
        """The command line of a node run alone."""
        return [sys.executable, str(KNOWN_NODES[name].program)] + self.ros_arguments(name)

    def group_command(self, group: List[str]) -> List[str]:
        """The command line of a process: the node alone, or a container of the group."""
        if len(group) == 1:
            return self.command(group[0])
        spec = {name: self.ros_arguments(name) for name in group}
        return [sys.executable, str(CONTAINER), json.dumps(spec)]

    def ros_arguments(self, name: str) -> List[str]:
        """The node's ROS arguments: name, parameter file, parameters."""
        spec = KNOWN_NODES[name]
        params = self.options.params_files.get(name, spec.default_params)
        args = ['--ros-args', '-r', f'__node:={name}']
        if Path(params).exists():
            args += ['--params-file', str(params)]
        if self.options.use_sim_time and name not in CLOCK_FREE_NODES:
            args += ['-p', 'use_sim_time:=true']
        if name == 'simulator':
            args += ['-p', f'backend:={self.options.backend}',
                     '-p', f'gui:={str(self.options.gui).lower()}']
            awaited = [STARTUP_TOPICS[node] for node in self.options.nodes
                       if node in STARTUP_TOPICS]
            if awaited:
                args += ['-p', f'wait_for_publishers:={",".join(awaited)}']
        if name == 'map_server':
            args += self.map_server_arguments()
        if name == 'state_machine' and 'footstep_planner' not in self.options.nodes:
            args += ['-p', 'use_planner:=false']  # walks in place, without waiting for one
        for override in self.options.overrides.get(name, []):
            args += ['-p', override]
        return args

    def map_server_arguments(self) -> List[str]:
        """The map file, and the empty map's centre: the simulator's start (as a launch file
        passes one argument to two nodes)."""
        args = []
        if self.options.map_file is not None:
            args += ['-p', f'yaml_filename:={Path(self.options.map_file).resolve()}']
        for override in self.options.overrides.get('simulator', []):
            name, _, value = override.partition(':=')
            if name in ('start_x', 'start_y'):
                args += ['-p', f'empty_map.center_{name[-1]}:={value}']
        return args

    def start(self) -> None:
        env = self.environment()
        width = max((len('+'.join(g)) for g in self.groups), default=0)
        for group in self.groups:
            name = '+'.join(group)
            process_env = env if len(group) == 1 else dict(  # composed: lines name their node
                env, RCUTILS_CONSOLE_OUTPUT_FORMAT='[{severity}] [{name}] {message}')
            process = subprocess.Popen(self.group_command(group), env=process_env,
                                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                       text=True, bufsize=1, start_new_session=True)
            self.processes[name] = process
            thread = threading.Thread(target=self._forward, args=(name.ljust(width), process),
                                      daemon=True)
            thread.start()
            self._threads.append(thread)
            self.log(f'[bringup] started {name} (pid {process.pid})')

    def _forward(self, prefix: str, process: subprocess.Popen) -> None:
        for line in process.stdout:
            self.log(f'[{prefix}] {line.rstrip()}')

    def wait_until_up(self, timeout: float = 30.0, abort: Optional[threading.Event] = None
                      ) -> None:
        """Wait until every node is on the ROS graph (or abort is set).

        :raises TimeoutError: naming the nodes not seen in time
        :raises RuntimeError: naming a node that died while starting
        """
        import rclpy
        from rclpy.context import Context
        context = Context()
        domain = self.options.domain_id
        rclpy.init(args=[], context=context, **({} if domain is None else {'domain_id': domain}))
        watcher = rclpy.create_node('bringup_watcher', context=context)
        try:
            deadline = time.monotonic() + timeout
            expected = set(self.options.nodes)
            while abort is None or not abort.is_set():
                self.check_alive()
                seen = {name for name, _ in watcher.get_node_names_and_namespaces()}
                if expected <= seen:
                    self.log(f'[bringup] all nodes up: {", ".join(self.options.nodes)}')
                    return
                if time.monotonic() > deadline:
                    raise TimeoutError(f'nodes not up after {timeout} s: '
                                       f'{sorted(expected - seen)}')
                time.sleep(0.1)
        finally:
            watcher.destroy_node()
            rclpy.try_shutdown(context=context)

    def check_alive(self) -> None:
        """:raises RuntimeError: naming the node that died and its exit status (unless
            keep_going, which only reports it)."""
        for name, process in self.processes.items():
            if process.poll() is None or self._stopping or name in self._reported_dead:
                continue
            code = process.returncode
            how = f'signal {-code}' if code < 0 else f'exit code {code}'
            if not self.options.keep_going:
                raise RuntimeError(f'node {name} died ({how}); stopping the graph')
            self._reported_dead.add(name)
            self.log(f'[bringup] node {name} died ({how}); the others keep running')

    def stop(self, grace: float = 5.0) -> None:
        """SIGINT to every node, then SIGKILL to those still running after grace seconds."""
        self._stopping = True
        for process in self.processes.values():
            if process.poll() is None:
                process.send_signal(signal.SIGINT)
        deadline = time.monotonic() + grace
        for name, process in self.processes.items():
            try:
                process.wait(timeout=max(0.05, deadline - time.monotonic()))
            except subprocess.TimeoutExpired:
                # imported here: node_runner brings rclpy, which this module loads only to use it
                from biped_planner.node_support.node_runner import DUMP_STACKS_SIGNAL
                self.log(f'[bringup] {name} ignored SIGINT for {grace} s: its stacks, then '
                         'SIGKILL')
                process.send_signal(DUMP_STACKS_SIGNAL)
                time.sleep(STACK_DUMP_WAIT)
                os.killpg(process.pid, signal.SIGKILL)
                process.wait()
        for thread in self._threads:
            thread.join(timeout=1.0)
        self.log('[bringup] all nodes stopped')
