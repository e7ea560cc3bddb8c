"""A service call that a callback can wait for.

Jazzy's rclpy has no asynchronous service callbacks: a service whose answer depends on another
service's (the state machine's reset waits for the simulator's) must call it and wait inside
its callback. Waiting on the node's own executor would re-enter it; the client therefore lives
on a small helper node with an executor of its own, spun only while a call waits.
"""
import rclpy
from rclpy.executors import SingleThreadedExecutor
from rclpy.node import Node


class SideCall:
    """A blocking client of one service, beside a node.

    :param node: the node the calls are made for (its context and namespace are used)
    :param srv_type: the service type
    :param name: the service name, resolved like the node's own names
    """

    def __init__(self, node: Node, srv_type, name: str) -> None:
        # No global arguments: a command-line '-r __node:=...' must not rename this helper too.
        self._node = rclpy.create_node(
            f'{node.get_name()}_{name.replace("/", "_")}_client', context=node.context,
            namespace=node.get_namespace(), use_global_arguments=False,
            start_parameter_services=False, enable_rosout=False)
        self._client = self._node.create_client(srv_type, node.resolve_service_name(name))
        self._executor = SingleThreadedExecutor(context=node.context)
        self._executor.add_node(self._node)

    def ready(self) -> bool:
        """Whether a server of the service is known."""
        return self._client.service_is_ready()

    def call(self, request, timeout: float):
        """Call and wait (wall time).

        :return: the response, or None when none came within timeout s
        """
        future = self._client.call_async(request)
        self._executor.spin_until_future_complete(future, timeout_sec=timeout)
        if not future.done():
            self._client.remove_pending_request(future)
            return None
        return future.result()

    def destroy(self) -> None:
        self._executor.remove_node(self._node)
        self._node.destroy_node()
        self._executor.shutdown()
