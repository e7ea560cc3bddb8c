"""Whether a producer's process is alive, apart from whether its data are on time.

A node that is slow (a loaded machine, a long solve) and a node that is dead look the same to a
wall-time timeout on its data. DDS tells them apart: a publisher with AUTOMATIC liveliness is
asserted by the middleware's own threads, which keep running while the node's Python code is
busy or starved, and a reader learns within the lease that the writer's process is gone. A
consumer that waits in lockstep can then wait for a slow producer and give up on a dead one at
once.

The producer creates a LivelinessToken on `<stream>/alive` (std_msgs/Empty, never published);
the consumer a LivelinessWatch on the same topic. A producer without a token (a user's own
node) is unknown to the watch: the consumer falls back to its wall-time timeout.

Nodes composed in one process share one DDS participant (one rclpy context), and DDS raises no
liveliness event between a participant's own readers and writers. A producer in the consumer's
own context is alive for as long as the consumer runs, so the watch counts the tokens of its
context too, while their nodes exist.
"""
import weakref

from rclpy.duration import Duration
from rclpy.event_handler import SubscriptionEventCallbacks
from rclpy.qos import LivelinessPolicy, QoSProfile
from std_msgs.msg import Empty

LEASE = 0.5  # s: a killed process is known dead within this
LIVELINESS = QoSProfile(depth=1, liveliness=LivelinessPolicy.AUTOMATIC,
                        liveliness_lease_duration=Duration(seconds=LEASE))


def token_topic(stream: str) -> str:
    return f'{stream}/alive'


_TOKENS = weakref.WeakSet()  # the tokens of this process


class LivelinessToken:
    """Announces, for as long as this process lives, that it produces `stream`."""

    def __init__(self, node, stream: str) -> None:
        self.stream = stream
        self.context = node.context
        self.publisher = node.create_publisher(Empty, token_topic(stream), LIVELINESS)
        _TOKENS.add(self)

    def exists(self) -> bool:
        """Its publisher (and so its node) has not been destroyed."""
        try:
            with self.publisher.handle:
                return True
        except Exception:  # noqa: B902 - rclpy's InvalidHandle once destroyed
            return False


class LivelinessWatch:
    """How many producers of `stream` with a token are alive (DDS liveliness events)."""

    def __init__(self, node, stream: str) -> None:
        self._stream = stream
        self._context = node.context
        self.alive_count = 0
        self._ever_remote = False
        self._subscription = node.create_subscription(
            Empty, token_topic(stream), lambda _msg: None, LIVELINESS,
            event_callbacks=SubscriptionEventCallbacks(liveliness=self._on_change))

    def _on_change(self, info) -> None:
        self.alive_count = int(info.alive_count)
        self._ever_remote = self._ever_remote or self.alive_count > 0

    @property
    def local(self) -> bool:
        """A producer of the stream runs in this context (composed with the consumer)."""
        return any(token.stream == self._stream and token.context is self._context and
                   token.exists() for token in list(_TOKENS))

    @property
    def ever_alive(self) -> bool:
        return self._ever_remote or self.local

    @property
    def alive(self) -> bool:
        return self.alive_count > 0 or self.local
