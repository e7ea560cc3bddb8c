"""Read the newest message of a topic when asked, without an executor callback per message."""
from rclpy.impl.implementation_singleton import rclpy_implementation as _rclpy
from rclpy.node import Node
from rclpy.qos import QoSProfile


class LatestMessageReader:
    """A subscription that no executor runs: DDS keeps the newest message, take() converts it.

    A callback costs a Python subscriber about 0.25 ms of CPU per message on this machine
    (wake-up, conversion to Python, call), most of it for messages it only stores. The
    subscription is made as Node.create_subscription makes its own, under the node's name in the
    ROS graph, but it is not registered with the node, so that no executor runs it.

    :param node: the node it belongs to (destroy() it before the node)
    :param msg_type: message class
    :param topic: topic name, resolved like any of the node's topics
    :param qos: QoS of the subscription; depth 1 keeps only the newest message
    """

    def __init__(self, node: Node, msg_type, topic: str,
                 qos: QoSProfile = QoSProfile(depth=1)) -> None:
        msg_type.__class__.__import_type_support__()
        with node.handle:
            self._handle = _rclpy.Subscription(node.handle, msg_type, topic,
                                               qos.get_c_qos_profile())
        self._msg_type = msg_type

    def take(self):
        """The newest message received since the last take, or None if none came."""
        messages = self.take_all()
        return messages[-1] if messages else None

    def take_all(self) -> list:
        """Every message received since the last take (at most the QoS depth), oldest first."""
        messages = []
        while True:
            with self._handle:
                taken = self._handle.take_message(self._msg_type, False)
            if taken is None:
                return messages
            messages.append(taken[0])

    def destroy(self) -> None:
        self._handle.destroy_when_not_in_use()
