"""Send bad messages and service requests into a running, walking graph and watch what follows.

A Case is one bad input: a topic (or service), the bad message (or request) built from the
newest real message of that topic, and for each node that reads it a pattern the node's answer
must match: a /rosout line, a walk_command_status, a service response, controller_diagnostics
or diagnostics. The Fuzzer sends the cases one by one while the robot walks in place and
records, per case, whether every target node answered (else: silent), stayed alive (else:
crash), and whether the robot kept walking upright (else: fall, or walk stopped).

Topics with a periodic flow (sensors, references, walking_state, sole_poses, joint_commands)
get a copy of their next real message with one field made bad, published at once: its stamp is
the current period's, so it passes the stamp checks and reaches the field checks (the stamp
cases move the stamp on purpose). Nodes rate-limit their rejection logs, so two cases that a
node logs alike are sent at least `spacing` apart.
"""
from dataclasses import dataclass, field
import inspect
import json
import math
from pathlib import Path
import re
import time
from typing import Callable, Dict, List, Optional, Tuple

from biped_msgs.msg import CommandStatus, ControllerDiagnostics, WalkCommand, WalkingState
from biped_msgs.srv import PlanWalk
from biped_planner.node_support.rejection_log import RejectionLog
from diagnostic_msgs.msg import DiagnosticArray
from nav_msgs.msg import Odometry
from rcl_interfaces.msg import Log
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
from rclpy.serialization import deserialize_message, serialize_message
from std_srvs.srv import Trigger

LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     reliability=ReliabilityPolicy.RELIABLE)
STREAM = QoSProfile(depth=10)
WALKING = (WalkingState.INITIALIZE, WalkingState.SINGLE_SUPPORT, WalkingState.DOUBLE_SUPPORT)
FALL_HEIGHT = 0.45  # m: the pelvis below this is a fall (the state machine's threshold)
EVIDENCE_TIMEOUT = 4.0  # s of wall time a node has to answer a bad input
# s between two cases one node may log alike for one topic: the nodes' RejectionLog period
LOG_SPACING = inspect.signature(RejectionLog).parameters['period'].default + 0.2
REJECTION = r'reject|refus|ignor|not used|invalid|unknown|must|not allowed|cannot|outside'


@dataclass(frozen=True)
class Topic:
    """A topic the fuzzer publishes on: type, QoS, and whether real messages flow on it (then
    a case's message is built from the next real one)."""

    msg_type: type
    latched: bool = False
    flow: bool = True
    usable: Optional[Callable] = None  # msg -> whether cases may copy it (None: any)

    @property
    def qos(self) -> QoSProfile:
        return LATCHED if self.latched else STREAM


@dataclass(frozen=True)
class Case:
    """One bad input.

    :param topic: topic or service name (relative)
    :param variant: what is wrong, for the report
    :param kind: nan, inf, huge, empty, length, enum, frame, bounds, stamp or state
    :param build: (newest real message of the topic or None, Fuzzer) -> the bad message or
        request (the real message is a copy: mutate it freely)
    :param expect: node -> regex (case-insensitive) its answer must match (evidence texts:
        'log: ...', 'status refused command=N error=E: ...', 'response refused error=E: ...',
        'controller_diagnostics status=S: ...', 'diagnostics level=L name: ...')
    :param service: topic is a service; build makes its request
    """

    topic: str
    variant: str
    kind: str
    build: Callable
    expect: Dict[str, str]
    service: bool = False

    @property
    def name(self) -> str:
        return f'{self.topic}: {self.variant}'


def logs(topic: str, kind: str = '', variant: str = '') -> str:
    """A log line naming the topic and a rejection (and, for some kinds, the reason: a NaN
    case's line says nan or finite, a frame case's the frame, a stamp case's ahead or back;
    so that a line refusing the real messages after a bad one was taken does not count)."""
    name = re.escape(topic)
    reason = {'nan': 'nan|finite', 'inf': 'inf|finite', 'frame': 'frame'}.get(kind, '')
    if kind == 'stamp':
        reason = 'ahead|future' if 'ahead' in variant else 'back|before|older'
        if 'nan' in variant.lower():  # a NaN with a bad stamp: either reason
            reason += '|nan|finite'
    return rf'^log: (?=.*\b{name}\b)(?=.*({REJECTION}))' + (rf'(?=.*({reason}))' if reason
                                                             else '')


def refused_status(*codes: int) -> str:
    """A walk_command_status refusing the command with one of these error codes."""
    return rf'^status refused command=\d+ error=({"|".join(str(c) for c in codes)})\b'


def refused_response(*codes: int) -> str:
    """A service response refusing the request (with one of these error codes, if given)."""
    return r'^response refused' + (
        rf' error=({"|".join(str(c) for c in codes)})\b' if codes else '')


@dataclass
class Evidence:
    wall: float
    node: str
    text: str


@dataclass
class CaseResult:
    name: str
    topic: str
    kind: str
    outcome: str  # rejected | silent | crash | fall | stopped | not sent
    answers: Dict[str, str] = field(default_factory=dict)  # node -> matching evidence
    silent_nodes: List[str] = field(default_factory=list)
    dead_nodes: List[str] = field(default_factory=list)
    note: str = ''


def response_text(response) -> str:
    if hasattr(response, 'accepted'):
        return (f'response {"accepted" if response.accepted else "refused"} '
                f'error={response.error_code}: {response.error_msg}')
    return f'response {"accepted" if response.success else "refused"}: {response.message}'


class Fuzzer:
    """Publishers, service clients and watchers on a GraphSession's client node.

    :param session: a started biped_tools.graph_session.GraphSession (keep_going=True)
    :param topics: topic -> Topic, every topic cases publish on
    :param services: service -> service type, every service cases call
    :param spacing: (node, topic) -> s of wall time between two rejection logs the node could
        rate-limit as one
    """

    def __init__(self, session, topics: Dict[str, Topic], services: Dict[str, type],
                 spacing: Callable[[str, str], float], log=print) -> None:
        self.session = session
        self.log = log
        self.topics = topics
        self.spacing = spacing
        self.evidence: List[Evidence] = []
        self.states: List[Tuple[float, WalkingState]] = []  # (wall, state)
        self.heights: List[Tuple[float, float]] = []  # (wall, pelvis z)
        self._raw: Dict[str, bytes] = {}
        self._own: Dict[str, set] = {}  # topic -> serialized messages the fuzzer sent
        self._armed: Optional[Tuple[Case, list]] = None
        self._last_log: Dict[Tuple[str, str], float] = {}
        self._previous = ''  # the case sent before
        node = session.node
        self.publishers = {name: node.create_publisher(spec.msg_type, name, spec.qos)
                           for name, spec in topics.items()}
        for name, spec in topics.items():
            qos = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL) \
                if spec.latched else STREAM
            node.create_subscription(spec.msg_type, name, self._receiver(name), qos, raw=True)
        self.clients = {name: node.create_client(srv, name) for name, srv in services.items()}
        self._commands = node.create_publisher(WalkCommand, 'walk_command', 10)
        self._reset = node.create_client(Trigger, 'reset')
        self._planner = node.create_client(PlanWalk, 'plan_walk')
        node.create_subscription(Log, '/rosout', self._on_log, QoSProfile(depth=1000))
        node.create_subscription(CommandStatus, 'walk_command_status', self._on_status, 100)
        node.create_subscription(ControllerDiagnostics, 'controller_diagnostics',
                                 self._on_controller, 100)
        node.create_subscription(DiagnosticArray, 'diagnostics', self._on_diagnostics, 100)
        node.create_subscription(WalkingState, 'walking_state', self._on_state, 100)
        node.create_subscription(Odometry, 'odom', lambda m: self.heights.append(
            (time.monotonic(), m.pose.pose.position.z)), 100)

    # --- watching ---------------------------------------------------------------------------
    def _on_state(self, msg: WalkingState) -> None:
        """The state machine's walking_state; the fuzzer's own bad ones (a 'phase 9' case) are
        not the robot's state."""
        if serialize_message(msg) not in self._own.get('walking_state', ()):
            self.states.append((time.monotonic(), msg))

    def _add(self, node: str, text: str) -> None:
        self.evidence.append(Evidence(time.monotonic(), node, text))

    def _on_log(self, msg: Log) -> None:
        self._add(msg.name, f'log: {msg.msg}')

    def _on_status(self, msg: CommandStatus) -> None:
        self._add(msg.node, f'status {"accepted" if msg.accepted else "refused"} '
                            f'command={msg.command} error={msg.error_code}: {msg.error_msg}')

    def _on_controller(self, msg: ControllerDiagnostics) -> None:
        if msg.message:
            self._add('mpc_controller', f'controller_diagnostics status={msg.status}: '
                                        f'{msg.message}')

    def _on_diagnostics(self, msg: DiagnosticArray) -> None:
        for status in msg.status:
            node = status.name.split(':')[0].strip()
            self._add(node, f'diagnostics level={int.from_bytes(status.level, "little")} '
                            f'{status.name}: {status.message}')

    def _receiver(self, topic: str):
        def receive(raw: bytes) -> None:
            if raw in self._own.get(topic, ()):
                return  # one of the fuzzer's own messages (DDS may deliver it again)
            usable = self.topics[topic].usable
            if usable is not None and not usable(deserialize_message(
                    raw, self.topics[topic].msg_type)):
                return
            self._raw[topic] = raw
            if self._armed is not None and self._armed[0].topic == topic:
                case, sent = self._armed
                self._armed = None
                sent.append(self._publish(case, self.latest(topic)))
        return receive

    def latest(self, topic: str):
        """A copy of the newest real message of topic (None: none yet)."""
        raw = self._raw.get(topic)
        return None if raw is None else deserialize_message(raw, self.topics[topic].msg_type)

    def state(self) -> Optional[WalkingState]:
        return self.states[-1][1] if self.states else None

    def spin(self, predicate, timeout: float) -> bool:
        return self.session.spin_until(predicate, timeout)

    # --- the walk ---------------------------------------------------------------------------
    def start_walking(self, steps: int = 2, timeout: float = 120.0) -> None:
        """START (walk in place) until step_index reaches steps; after a fall, reset first."""
        state = self.state()
        if state is not None and state.fallen:
            self.reset_robot()
        assert self.spin(lambda: self._commands.get_subscription_count() > 0, 30), \
            'nobody subscribes walk_command'
        # the walk follows the planner's plan: the state machine must see plan_walk first
        assert self._planner.wait_for_service(timeout_sec=30.0), 'no plan_walk service'
        self.spin(lambda: False, 2.0)
        begun = time.monotonic()
        self._commands.publish(WalkCommand(command=WalkCommand.START))
        assert self.spin(lambda: any(w >= begun and s.phase in WALKING and s.step_index >= steps
                                     for w, s in self.states[-5:]), timeout), \
            f'the robot did not walk {steps} steps in place after START'
        assert self.state().plan_id != 0, 'the walk follows no footstep plan'

    def reset_robot(self) -> None:
        assert self._reset.wait_for_service(timeout_sec=15.0), 'no reset service'
        for _ in range(10):
            future = self._reset.call_async(Trigger.Request())
            assert self.spin(future.done, 30.0), 'reset did not answer'
            if future.result().success:
                self.spin(lambda: False, 3.0)  # the controller restarts standing
                return
            self.spin(lambda: False, 1.0)
        raise AssertionError(f'reset refused: {future.result().message}')

    def walking(self) -> bool:
        state = self.state()
        return state is not None and state.phase in WALKING

    # --- cases ------------------------------------------------------------------------------
    def _publish(self, case: Case, real):
        msg = case.build(real, self)
        self._own.setdefault(case.topic, set()).add(serialize_message(msg))
        self.publishers[case.topic].publish(msg)
        return msg

    def _wait_spacing(self, case: Case) -> None:
        def ready() -> bool:
            now = time.monotonic()
            return all(now - self._last_log.get((node, case.topic), -math.inf) >=
                       self.spacing(node, case.topic) for node in case.expect)
        self.spin(ready, 30.0)

    def _send(self, case: Case) -> Optional[str]:
        """Send the case; :return: the response text of a service, else None."""
        if case.service:
            client = self.clients[case.topic]
            if not client.wait_for_service(timeout_sec=10.0):
                return 'no service'
            future = client.call_async(case.build(None, self))
            if not self.spin(future.done, 15.0):
                return 'no response'
            return response_text(future.result())
        if self.topics[case.topic].flow:
            sent = []
            self._armed = (case, sent)
            if not self.spin(lambda: bool(sent), 10.0):
                self._armed = None
                return 'no real message to copy'
            return None
        self._publish(case, self.latest(case.topic))
        return None

    def _answer(self, node: str, pattern: str, since: float) -> Optional[Evidence]:
        regex = re.compile(pattern, re.IGNORECASE)
        return next((e for e in self.evidence
                     if e.wall >= since and e.node == node and regex.search(e.text)), None)

    def run(self, case: Case) -> CaseResult:
        """Send one case and judge it."""
        if not self.walking():
            self.start_walking()
        self._wait_spacing(case)
        before = self.state()
        since = time.monotonic()
        problem = self._send(case)
        result = CaseResult(case.name, case.topic, case.kind, 'rejected')
        if case.service and problem is not None and problem.startswith('response'):
            for node in case.expect:
                self._add(node, problem)
        elif problem is not None:
            result.outcome, result.note = 'not sent', problem
            return result
        answers: Dict[str, Evidence] = {}

        def answered() -> bool:
            for node, pattern in case.expect.items():
                if node not in answers:
                    evidence = self._answer(node, pattern, since)
                    if evidence is not None:
                        answers[node] = evidence
            return len(answers) == len(case.expect) or bool(self.dead())

        self.spin(answered, EVIDENCE_TIMEOUT)
        self.spin(lambda: False, 0.1)  # a crash or a fall right after the answer
        for node, evidence in answers.items():
            result.answers[node] = evidence.text
            if evidence.text.startswith('log: '):
                self._last_log[(node, case.topic)] = evidence.wall
        result.silent_nodes = [node for node in case.expect if node not in answers]
        result.dead_nodes = self.dead()
        fell = any(s.fallen for w, s in self.states if w >= since) or any(
            z < FALL_HEIGHT for w, z in self.heights if w >= since)
        stopped = before is not None and before.phase in WALKING and not self.walking()
        if result.dead_nodes:
            result.outcome = 'crash'
        elif fell:
            result.outcome = 'fall'
            result.note = f'(or a late effect of the case before: {self._previous})'
        elif result.silent_nodes:
            result.outcome = 'silent'
        elif stopped:
            result.outcome = 'stopped'
            result.note = self.state().reason
        self.log(f'[bad_input] {result.outcome:8s} {case.name}: ' + '; '.join(
            f'{node}: {text[:160]}' for node, text in result.answers.items()) +
            (f' SILENT: {result.silent_nodes}' if result.silent_nodes else '') +
            (f' {result.note}' if result.note else ''))
        self._previous = case.name
        return result

    def run_again(self, case: Case, first: CaseResult) -> CaseResult:
        """Send a case that met silence once more, a full rejection-log period later.

        A node logs a refusal once per period per topic; on a loaded machine the answer to the
        case before can reach the fuzzer after its EVIDENCE_TIMEOUT, and the node's next refusal
        then falls inside the period the fuzzer did not see start. Silent twice is silent.
        """
        now = time.monotonic()
        for node in first.silent_nodes:
            self._last_log[(node, case.topic)] = now
        second = self.run(case)
        if second.outcome != 'silent':
            second.note = (second.note + ' ' if second.note else '') + \
                f'(silent on the first send: {first.silent_nodes})'
        return second

    def dead(self) -> List[str]:
        return [name for name, process in self.session.graph.processes.items()
                if process.poll() is not None]


def run_cases(fuzzer: Fuzzer, cases: List[Case]) -> List[CaseResult]:
    """Every case, in order; a node that died ends the cases that need it ('not sent')."""
    results = []
    for case in cases:
        dead = [node for node in case.expect if node in fuzzer.dead()]
        if dead:
            results.append(CaseResult(case.name, case.topic, case.kind, 'not sent',
                                      dead_nodes=dead, note='a target node is dead'))
            continue
        result = fuzzer.run(case)
        if result.outcome == 'silent':
            result = fuzzer.run_again(case, result)
        results.append(result)
    return results


def summary(results: List[CaseResult]) -> dict:
    counts = {}
    for result in results:
        counts[result.outcome] = counts.get(result.outcome, 0) + 1
    return {'cases': len(results), 'messages': len(results), **counts}


def write_report(name: str, results: List[CaseResult], directory: Path) -> Path:
    """results as JSON (output/bad_input/<name>.json): the doc's table is made from these."""
    directory.mkdir(parents=True, exist_ok=True)
    path = directory / f'{name}.json'
    path.write_text(json.dumps({'summary': summary(results), 'cases': [
        result.__dict__ for result in results]}, indent=1))
    return path


def failures(results: List[CaseResult]) -> List[str]:
    return [f'{r.outcome}: {r.name}' + (f' (silent: {r.silent_nodes})' if r.silent_nodes
                                        else '') + (f' {r.note}' if r.note else '')
            for r in results if r.outcome != 'rejected']
