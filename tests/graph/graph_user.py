"""What the recovery and node-loss graph tests do as a user of the running graph: walk commands,
the reset service, and the state, diagnostics and odometry they watch."""
from dataclasses import dataclass, field
import math
from typing import List

from biped_msgs.msg import CommandStatus, ControllerDiagnostics, WalkCommand, WalkingState
from diagnostic_msgs.msg import DiagnosticArray
from geometry_msgs.msg import WrenchStamped
from std_srvs.srv import Trigger

WALKING = (WalkingState.INITIALIZE, WalkingState.SINGLE_SUPPORT, WalkingState.DOUBLE_SUPPORT)
FALL_HEIGHT = 0.45  # m: the state machine's fall detection threshold of the pelvis
FALL_TILT = 0.7  # rad


def seconds(stamp) -> float:
    return stamp.sec + stamp.nanosec * 1e-9


@dataclass
class GraphUser:
    """A GraphSession's client with the subscriptions these tests read."""

    session: object
    states: List[WalkingState] = field(default_factory=list)
    statuses: List[CommandStatus] = field(default_factory=list)
    controller: List[ControllerDiagnostics] = field(default_factory=list)
    diagnostics: List[tuple] = field(default_factory=list)  # (sim time, DiagnosticStatus)
    foot_forces: List[float] = field(default_factory=lambda: [0.0, 0.0])  # N, left and right

    def __post_init__(self) -> None:
        node = self.session.node
        node.create_subscription(WalkingState, 'walking_state', self.states.append, 50)
        node.create_subscription(CommandStatus, 'walk_command_status', self.statuses.append, 50)
        node.create_subscription(ControllerDiagnostics, 'controller_diagnostics',
                                 self.controller.append, 50)
        node.create_subscription(DiagnosticArray, 'diagnostics', self._on_diagnostics, 50)
        for side, topic in enumerate(('left_foot_wrench', 'right_foot_wrench')):
            node.create_subscription(WrenchStamped, topic, lambda m, side=side: self._on_wrench(
                side, m), 50)
        self.commands = node.create_publisher(WalkCommand, 'walk_command', 10)
        self.reset_client = node.create_client(Trigger, 'reset')

    def _on_diagnostics(self, msg: DiagnosticArray) -> None:
        self.diagnostics.extend((self.session.sim_time(), status) for status in msg.status)

    def _on_wrench(self, side: int, msg: WrenchStamped) -> None:
        self.foot_forces[side] = msg.wrench.force.z

    def on_both_feet(self, force: float = 50.0) -> bool:
        """Both feet carry at least this normal force (N) now."""
        return min(self.foot_forces) >= force

    def command(self, **fields) -> None:
        """Publish a walk command once the state machine has matched it (a `--once` publish)."""
        assert self.session.spin_until(lambda: self.commands.get_subscription_count() > 0, 15)
        self.commands.publish(WalkCommand(**fields))

    def reset(self) -> Trigger.Response:
        assert self.reset_client.wait_for_service(timeout_sec=15.0), 'no reset service'
        future = self.reset_client.call_async(Trigger.Request())
        assert self.session.spin_until(future.done, 30.0), 'reset did not answer'
        return future.result()

    def state(self) -> WalkingState:
        return self.states[-1]

    def wait_walking(self, steps: int, timeout: float = 120.0) -> bool:
        """Until step_index reaches steps (in the current epoch) or the robot falls."""
        return self.session.spin_until(lambda: self.states and (
            self.state().step_index >= steps or self.state().fallen), timeout)

    def pelvis_since(self, t: float) -> list:
        """(t, x, y, z, tilt, yaw) of the pelvis from sim time t on."""
        return [p for p in self.session.series.pelvis if p[0] >= t]

    def stood_since(self, t: float) -> bool:
        """The pelvis never went below the fall height nor tilted past the fall tilt."""
        samples = self.pelvis_since(t)
        return bool(samples) and all(p[3] > FALL_HEIGHT and p[4] < FALL_TILT for p in samples)

    def first_report(self, t: float, predicate) -> float:
        """Sim time of the first diagnostic status after t that satisfies predicate (nan)."""
        return next((when for when, status in self.diagnostics
                     if when >= t and predicate(status)), math.nan)
