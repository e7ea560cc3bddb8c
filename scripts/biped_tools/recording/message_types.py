"""Message definitions and type hashes for the bag: every interface installed here, ours too.

A rosbag2 connection carries its type's full message definition and RIHS01 hash, so that other
tools can decode the bag. They are computed by rosbags from the installed .msg files (the ones
rclpy's type support was generated from) and checked against the hash a publisher announces.
"""
import os
from pathlib import Path
import sys
from typing import Iterator, List, Optional, Sequence

from biped_tools.interface_types import import_interface, InterfaceError, split_type_name
from biped_tools.paths import INSTALL
from biped_tools.recording.errors import RecordError


def interface_prefixes() -> List[Path]:
    """Install prefixes whose share/<pkg>/msg/*.msg define the interfaces rclpy uses.

    :return: AMENT_PREFIX_PATH entries, the workspace's biped_msgs install and the venv (where
        the ROS wheels install their share/ files), without duplicates, in that order
    """
    candidates = [Path(p) for p in os.environ.get('AMENT_PREFIX_PATH', '').split(os.pathsep) if p]
    candidates += [INSTALL / 'biped_msgs', Path(sys.prefix)]
    prefixes: List[Path] = []
    for prefix in candidates:
        if prefix not in prefixes:
            prefixes.append(prefix)
    return prefixes


def import_message_class(type_name: str):
    """Import the Python class of 'pkg/msg/Type' (rclpy needs it for the type support).

    :raises RecordError: if the name is malformed or the type is not installed here
    """
    try:
        return import_interface(type_name)
    except InterfaceError as error:
        raise RecordError(str(error)) from None


def _nested_types(desc) -> Iterator[str]:
    """Names of the message types a rosbags field descriptor refers to."""
    from rosbags.interfaces import Nodetype
    kind, rest = desc
    if kind == Nodetype.NAME:
        yield rest
    elif kind in (Nodetype.ARRAY, Nodetype.SEQUENCE):
        yield from _nested_types(rest[0])


class TypeRegistry:
    """A rosbags typestore that knows every interface type installed here, ours included.

    Definitions come from the installed .msg files (the ones rclpy's type support was generated
    from); rosbags' own Jazzy store only fills in types that have no .msg file (e.g. service
    event types). rosbags then computes the message definition and RIHS01 hash written into
    the bag; `check_hash` compares that hash with the one a publisher announces on the graph.

    :param prefixes: install prefixes to search (default: `interface_prefixes()`)
    """

    def __init__(self, prefixes: Optional[Sequence[Path]] = None) -> None:
        from rosbags.typesys import get_typestore, Stores
        self.prefixes = list(interface_prefixes() if prefixes is None else prefixes)
        self.typestore = get_typestore(Stores.EMPTY)
        self._fallback = get_typestore(Stores.ROS2_JAZZY)

    def find_msg_file(self, type_name: str) -> Optional[Path]:
        """:return: the installed .msg file of 'pkg/msg/Type', or None
        :raises RecordError: for a malformed type name
        """
        try:
            package, kind, name = split_type_name(type_name)
        except InterfaceError as error:
            raise RecordError(str(error)) from None
        for prefix in self.prefixes:
            path = prefix / 'share' / package / kind / f'{name}.msg'
            if path.is_file():
                return path
        return None

    def ensure(self, type_name: str) -> None:
        """Register type_name and every type it uses.

        :raises RecordError: if a definition is found neither installed nor in rosbags' store
        """
        from rosbags.typesys import get_types_from_msg, TypesysError
        if type_name in self.typestore.fielddefs:
            return
        path = self.find_msg_file(type_name)
        if path is not None:
            try:
                types = get_types_from_msg(path.read_text(), type_name)
            except TypesysError as error:
                raise RecordError(f'cannot parse {path}: {error}') from None
        elif type_name in self._fallback.fielddefs:
            types = {type_name: self._fallback.fielddefs[type_name]}
        else:
            searched = ', '.join(str(p / 'share') for p in self.prefixes)
            raise RecordError(f'no message definition for {type_name}: no .msg file under '
                              f'{searched} and not a standard Jazzy type')
        for _, fields in types.values():
            for _, desc in fields:
                for nested in _nested_types(desc):
                    if nested != type_name:
                        self.ensure(nested)
        self.typestore.register(types)

    def rihs01(self, type_name: str) -> str:
        """:return: the RIHS01 type hash rosbags writes for type_name (registering it first)"""
        self.ensure(type_name)
        return self.typestore.hash_rihs01(type_name)

    def check_hash(self, type_name: str, announced: str) -> None:
        """Compare rosbags' hash of type_name with the one a publisher announced.

        A mismatch means the bag would carry a definition other than the publisher's, so its
        messages could not be decoded correctly.
        :param announced: 'RIHS01_<hex>' from the graph; anything else is not checked
        :raises RecordError: naming both hashes on a mismatch
        """
        if not announced.startswith('RIHS01_') or set(announced[7:]) <= {'0'}:
            return
        ours = self.rihs01(type_name)
        if ours != announced:
            raise RecordError(f'{type_name}: the publisher\'s type hash {announced} differs '
                              f'from the installed definition\'s {ours}; rebuild the workspace')
