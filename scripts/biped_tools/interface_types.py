"""ROS interface types by name: 'pkg/msg/Type' (or 'pkg/Type') to its Python class.

Shared by the recorder (types announced on the graph) and the ros2 CLI stand-in (types typed by
the user), so that both accept the same names and fail with the same words.
"""
import importlib


class InterfaceError(ValueError):
    """A type name that is malformed, or whose interface is not installed for this Python."""


def split_type_name(type_name: str, kind: str = 'msg') -> tuple:
    """'pkg/msg/Type' -> ('pkg', 'msg', 'Type'); 'pkg/Type' takes `kind` as its middle part.

    :raises InterfaceError: for any other form
    """
    parts = type_name.split('/')
    if len(parts) == 2:
        parts = [parts[0], kind, parts[1]]
    if len(parts) != 3 or not all(parts):
        raise InterfaceError(f'type {type_name!r}: expected package/{kind}/Type')
    return tuple(parts)


def import_interface(type_name: str, kind: str = 'msg'):
    """Import the Python class of a message or service type (rclpy needs it for the type
    support).

    :param type_name: 'pkg/msg/Type', 'pkg/srv/Type' or 'pkg/Type'
    :param kind: 'msg' or 'srv', for a name without its middle part
    :raises InterfaceError: if the name is malformed or the type is not installed here
    """
    package, middle, name = split_type_name(type_name, kind)
    try:
        return getattr(importlib.import_module(f'{package}.{middle}'), name)
    except (ImportError, AttributeError):
        raise InterfaceError(f'unknown type {type_name!r}: not installed for this Python (no '
                             f'{package}.{middle}.{name}); run scripts/setup.sh or install the '
                             f'interface package') from None
