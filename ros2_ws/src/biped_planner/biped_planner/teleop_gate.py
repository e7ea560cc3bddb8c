"""What the state machine does with each cmd_vel, the ROS teleop convention.

A teleop repeats its velocity at 10-50 Hz. Only a new velocity is worth a new plan (a plan per
message would supersede the previous request before its plan arrives); a repeated one only
proves the operator is still there. A walk driven by cmd_vel stops, finishing its step, when
cmd_vel falls silent for the timeout, measured on the node's clock AND in wall time (either
alone misfires: a lockstep simulation can run the clock faster than the wall, and a stalled
one slower). A cmd_vel that arrives while the walk is stopping for that silence is not
refused: the walk starts again once it has stopped, if the operator is still sending (a walk
stopping for another reason, an explicit STOP, is not restarted by cmd_vel).
"""
import enum
from typing import Optional, Tuple

Velocity = Tuple[float, float, float]  # vx (m/s), vy (m/s), wz (rad/s)

SAME_VELOCITY = 1e-6  # m/s or rad/s: a teleop repeating its velocity sends it bit for bit


class TeleopAction(enum.Enum):
    FORWARD = 'forward'  # start or steer the walk: ask the planner
    REFRESH = 'refresh'  # the velocity the walk already follows: only the timeout restarts
    DEFER = 'defer'      # the walk is stopping: start again once it is idle


class TeleopGate:
    """The velocity a teleop walk follows and when the operator was last heard.

    Times are (clock, wall) pairs in seconds.
    """

    def __init__(self) -> None:
        self.velocity: Optional[Velocity] = None  # the last velocity forwarded
        self.last_heard: Optional[Tuple[float, float]] = None
        self.driving = False  # the current walk follows cmd_vel
        self.deferred: Optional[Velocity] = None
        self.stopping_for_silence = False  # the walk is ending by the timeout

    def received(self, velocity: Velocity, now: float, wall: float, walking: bool,
                 stopping: bool, start_pending: bool) -> TeleopAction:
        """Record a valid cmd_vel and say what to do with it.

        :param walking: a walk is under way (or starting)
        :param stopping: that walk is ending
        :param start_pending: a walk waits for its plan
        """
        self.last_heard = (now, wall)
        if walking and stopping and self.stopping_for_silence:
            self.deferred = velocity
            return TeleopAction.DEFER
        self.deferred = None
        steering = (walking and self.driving) or start_pending
        if steering and self.velocity is not None and max(
                abs(a - b) for a, b in zip(velocity, self.velocity)) <= SAME_VELOCITY:
            return TeleopAction.REFRESH
        self.velocity = velocity
        return TeleopAction.FORWARD

    def silent(self, now: float, wall: float, timeout: float) -> bool:
        """Whether the operator has been silent longer than timeout on both clocks."""
        return self.last_heard is not None and min(
            now - self.last_heard[0], wall - self.last_heard[1]) > timeout

    def timed_out(self, now: float, wall: float, timeout: float, walking: bool) -> bool:
        """Whether the teleop walk must stop now (then it no longer follows cmd_vel)."""
        if self.driving and walking and self.silent(now, wall, timeout):
            self.driving = False
            self.stopping_for_silence = True
            return True
        return False

    def restart(self, now: float, wall: float, timeout: float) -> Optional[Velocity]:
        """Once idle: the deferred velocity, if the operator is still sending (else None)."""
        velocity, self.deferred = self.deferred, None
        if velocity is None or self.silent(now, wall, timeout):
            return None
        self.velocity = velocity  # the new walk's: its repeats must not supersede its start
        return velocity

    def ended(self, drop_deferred: bool = False) -> None:
        """The walk ended (idle, fallen, reset): the next cmd_vel starts a new one; after a
        fall or a reset, not one deferred before it (drop_deferred)."""
        self.driving = False
        self.velocity = None
        self.stopping_for_silence = False
        if drop_deferred:
            self.deferred = None
