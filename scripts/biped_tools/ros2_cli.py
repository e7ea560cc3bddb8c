"""A small stand-in for ros2cli (not installable here): topic pub, topic echo, service call,
interface show.

The arguments are those of `ros2`, so a line written for a full ROS install works with this tool
by replacing `ros2` with `.venv/bin/python scripts/ros2_cli.py`:

  ros2_cli.py topic pub --once walk_command biped_msgs/msg/WalkCommand "{command: 1}"
  ros2_cli.py topic pub --rate 10 cmd_vel geometry_msgs/msg/Twist "{linear: {x: 0.2}}"
  ros2_cli.py topic pub --once --qos-durability transient_local goal_pose \
      geometry_msgs/msg/PoseStamped "{header: {frame_id: map}, pose: {position: {x: 2.0}}}"
  ros2_cli.py topic echo --once walking_state biped_msgs/msg/WalkingState
  ros2_cli.py service call push biped_msgs/srv/Push "{force: {x: 80.0}, duration: 0.1}"
  ros2_cli.py interface show geometry_msgs/msg/Twist

Values come as YAML; a Header given as `auto` and a Time given as `now` get the current time.
"""
import argparse
from pathlib import Path
import sys
import time

import yaml

from biped_tools.interface_types import import_interface

FLOAT_TYPES = {'float', 'double'}
INTEGER_BITS = {'int8': (True, 8), 'uint8': (False, 8), 'int16': (True, 16),
                'uint16': (False, 16), 'int32': (True, 32), 'uint32': (False, 32),
                'int64': (True, 64), 'uint64': (False, 64), 'byte': (False, 8),
                'octet': (False, 8), 'char': (False, 8)}


def basic_value(base: str, value):
    """Check one value of a basic field type and convert it as rosidl expects.

    Jazzy's generated setters check nothing unless ROS_PYTHON_CHECK_FIELDS is set, so a wrong
    type would only fail later, in serialization.
    :raises ValueError: for a value of the wrong type or out of the type's range
    """
    if base in FLOAT_TYPES:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ValueError(f'expected a number, got {value!r}')
        return float(value)
    if base in INTEGER_BITS:
        signed, bits = INTEGER_BITS[base]
        low, high = (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if signed else (0, (1 << bits) - 1)
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            raise ValueError(f'expected an integer in [{low}, {high}], got {value!r}')
        return value
    if base == 'boolean' and not isinstance(value, bool):
        raise ValueError(f'expected true or false, got {value!r}')
    if base.startswith(('string', 'wstring')) and not isinstance(value, str):
        raise ValueError(f'expected a string, got {value!r}')
    return value


def element_type(field_type: str) -> str:
    """'sequence<pkg/Type, 5>' or 'pkg/Type[3]' -> 'pkg/Type'."""
    if field_type.startswith('sequence<'):
        return field_type[len('sequence<'):-1].split(',')[0].strip()
    return field_type.split('[')[0]


def fill(msg, values, now_msg):
    """Set the fields of msg from a dict, recursing into nested messages and sequences.

    :raises ValueError: naming an unknown field or a value of the wrong type
    """
    if values is None:
        return msg
    if not isinstance(values, dict):
        raise ValueError(f'{type(msg).__name__}: expected a mapping of fields, got {values!r}')
    fields = msg.get_fields_and_field_types()
    for key, value in values.items():
        if key not in fields:
            raise ValueError(f'{type(msg).__name__} has no field {key!r}; '
                             f'fields: {", ".join(fields)}')
        field_type = fields[key]
        current = getattr(msg, key)
        if field_type == 'std_msgs/Header' and value == 'auto':
            current.stamp = now_msg
        elif field_type == 'builtin_interfaces/Time' and value == 'now':
            setattr(msg, key, now_msg)
        elif hasattr(current, 'get_fields_and_field_types'):
            fill(current, value, now_msg)
        elif '/' in element_type(field_type) and ('sequence<' in field_type or
                                                   '[' in field_type):
            cls = import_interface(element_type(field_type))
            setattr(msg, key, [fill(cls(), item, now_msg) for item in value])
        else:
            base = element_type(field_type)
            try:
                if 'sequence<' in field_type or '[' in field_type:
                    if not isinstance(value, list):
                        raise ValueError(f'expected a list, got {value!r}')
                    value = [basic_value(base, v) for v in value]
                else:
                    value = basic_value(base, value)
                setattr(msg, key, value)
            except (AssertionError, TypeError, ValueError) as error:
                raise ValueError(f'{type(msg).__name__}.{key} ({field_type}): cannot take '
                                 f'{value!r}: {error}') from None
    return msg


def to_plain(msg):
    """A message as nested dicts and lists, for YAML output."""
    if hasattr(msg, 'get_fields_and_field_types'):
        return {key: to_plain(getattr(msg, key)) for key in msg.get_fields_and_field_types()}
    if isinstance(msg, (list, tuple)) or type(msg).__name__ in ('ndarray', 'array'):
        return [to_plain(v) for v in msg]
    if hasattr(msg, 'item'):
        return msg.item()
    return msg


def qos_profile(args):
    from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy
    return QoSProfile(
        depth=args.qos_depth,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if args.qos_durability == 'transient_local'
        else DurabilityPolicy.VOLATILE,
        reliability=ReliabilityPolicy.BEST_EFFORT if args.qos_reliability == 'best_effort'
        else ReliabilityPolicy.RELIABLE)


def topic_pub(node, args) -> int:
    cls = import_interface(args.type)
    values = yaml.safe_load(args.values) if args.values else None
    publisher = node.create_publisher(cls, args.topic, qos_profile(args))
    import rclpy
    deadline = time.monotonic() + args.timeout
    while (publisher.get_subscription_count() < args.wait_matching_subscriptions and
           time.monotonic() < deadline):
        rclpy.spin_once(node, timeout_sec=0.05)
    if publisher.get_subscription_count() < args.wait_matching_subscriptions:
        print(f'warning: {publisher.get_subscription_count()} subscriber(s) on {args.topic} '
              f'after {args.timeout} s; publishing anyway', file=sys.stderr)
    count = 1 if args.once else args.times
    sent = 0
    while count <= 0 or sent < count:
        msg = fill(cls(), values, node.get_clock().now().to_msg())
        publisher.publish(msg)
        sent += 1
        print(f'publishing #{sent}: {to_plain(msg)}')
        if count <= 0 or sent < count:
            end = time.monotonic() + 1.0 / args.rate
            while time.monotonic() < end:
                rclpy.spin_once(node, timeout_sec=max(0.0, end - time.monotonic()))
    # Let reliable delivery finish before the publisher disappears.
    end = time.monotonic() + 0.5
    while time.monotonic() < end:
        rclpy.spin_once(node, timeout_sec=0.05)
    return 0


def topic_echo(node, args) -> int:
    import rclpy
    cls = import_interface(args.type)
    received = []
    node.create_subscription(cls, args.topic, received.append, qos_profile(args))
    deadline = time.monotonic() + args.timeout if args.timeout > 0 else None
    printed = 0
    while deadline is None or time.monotonic() < deadline:
        rclpy.spin_once(node, timeout_sec=0.1)
        while printed < len(received):
            print(yaml.safe_dump(to_plain(received[printed]), sort_keys=False) + '---')
            printed += 1
            if args.once:
                return 0
    print(f'error: no message on {args.topic} within {args.timeout} s', file=sys.stderr)
    return 1


def service_call(node, args) -> int:
    import rclpy
    cls = import_interface(args.type, kind='srv')
    client = node.create_client(cls, args.service)
    if not client.wait_for_service(timeout_sec=args.timeout):
        print(f'error: service {args.service} not available after {args.timeout} s',
              file=sys.stderr)
        return 1
    request = fill(cls.Request(), yaml.safe_load(args.values) if args.values else None,
                   node.get_clock().now().to_msg())
    future = client.call_async(request)
    rclpy.spin_until_future_complete(node, future, timeout_sec=args.timeout)
    if not future.done():
        print(f'error: no response from {args.service} within {args.timeout} s', file=sys.stderr)
        return 1
    print(yaml.safe_dump(to_plain(future.result()), sort_keys=False))
    return 0


def interface_show(args) -> int:
    """Print an interface's definition, found as `ros2 interface show` finds it: through the
    ament index (AMENT_PREFIX_PATH) to <share>/<package>/<msg|srv|action>/<Type>.<kind>."""
    from ament_index_python.packages import (get_package_share_directory,
                                             PackageNotFoundError)
    parts = args.type.split('/')
    if len(parts) != 3 or parts[1] not in ('msg', 'srv', 'action') or not all(parts):
        raise ValueError(f'type {args.type!r}: expected package/msg|srv|action/Type')
    package, kind, name = parts
    try:
        share = Path(get_package_share_directory(package))
    except (PackageNotFoundError, ValueError) as error:
        print(f'error: {error}', file=sys.stderr)
        return 1
    path = share / kind / f'{name}.{kind}'
    if not path.is_file():
        print(f'error: {args.type}: no {path}', file=sys.stderr)
        return 1
    print(path.read_text().rstrip('\n'))
    return 0


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    groups = parser.add_subparsers(dest='group', required=True)

    def add_qos(sub):
        sub.add_argument('--qos-durability', choices=['volatile', 'transient_local'],
                         default='volatile')
        sub.add_argument('--qos-reliability', choices=['reliable', 'best_effort'],
                         default='reliable')
        sub.add_argument('--qos-depth', type=int, default=10)

    topic = groups.add_parser('topic').add_subparsers(dest='verb', required=True)
    pub = topic.add_parser('pub', help='publish a message given as YAML')
    pub.add_argument('topic')
    pub.add_argument('type', help='e.g. biped_msgs/msg/WalkCommand')
    pub.add_argument('values', nargs='?', default='', help='YAML, e.g. "{command: 1}"')
    pub.add_argument('-1', '--once', action='store_true', help='publish one message and exit')
    pub.add_argument('-r', '--rate', type=float, default=1.0, help='Hz')
    pub.add_argument('-t', '--times', type=int, default=0, help='publish N times (0: forever)')
    pub.add_argument('-w', '--wait-matching-subscriptions', type=int, default=1)
    pub.add_argument('--timeout', type=float, default=5.0,
                     help='seconds to wait for subscribers')
    add_qos(pub)
    pub.set_defaults(run=topic_pub)
    echo = topic.add_parser('echo', help='print messages as YAML')
    echo.add_argument('topic')
    echo.add_argument('type')
    echo.add_argument('--once', action='store_true')
    echo.add_argument('--timeout', type=float, default=0.0, help='seconds; 0 waits forever')
    add_qos(echo)
    echo.set_defaults(run=topic_echo)
    service = groups.add_parser('service').add_subparsers(dest='verb', required=True)
    call = service.add_parser('call', help='call a service with a request given as YAML')
    call.add_argument('service')
    call.add_argument('type', help='e.g. biped_msgs/srv/Push')
    call.add_argument('values', nargs='?', default='')
    call.add_argument('--timeout', type=float, default=10.0)
    call.set_defaults(run=service_call)
    interface = groups.add_parser('interface').add_subparsers(dest='verb', required=True)
    show = interface.add_parser('show', help='print the definition of an interface type')
    show.add_argument('type', help='e.g. geometry_msgs/msg/Twist')
    show.set_defaults(run=interface_show, offline=True)
    return parser


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    if getattr(args, 'offline', False):  # needs no node
        try:
            return args.run(args)
        except ValueError as error:
            print(f'error: {error}', file=sys.stderr)
            return 2
    import rclpy
    from rclpy.signals import SignalHandlerOptions
    # Python's own signal behaviour: Ctrl-C raises KeyboardInterrupt, SIGTERM ends the process
    # (rclpy's handler would invalidate the context under a running call).
    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    node = rclpy.create_node(f'ros2_cli_{int(time.time() * 1000) % 100000}')
    try:
        return args.run(node, args)
    except (ValueError, yaml.YAMLError) as error:
        print(f'error: {error}', file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except BrokenPipeError:  # the reader of our output went away (e.g. `| head`)
        return 0
    finally:
        node.destroy_node()
        rclpy.try_shutdown()

