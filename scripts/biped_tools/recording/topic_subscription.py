"""How the recorder subscribes: resolved topic names and the QoS that matches the publishers."""
from typing import Sequence

from biped_tools.recording.errors import RecordError

# Subscription history: deep enough for a publisher's transient_local history and for bursts of
# a 1 kHz topic while Python writes (DDS allocates samples as they come, not up front).
RECORD_DEPTH = 1000


def resolve_topic(node, topic: str) -> str:
    """Expand a (relative) topic name against the node's namespace and remappings.

    :raises RecordError: with rcl's reason for an invalid name
    """
    try:
        return node.resolve_topic_name(topic)
    except RuntimeError as error:
        reason = str(error).replace('failed to resolve name: ', '').split(', at /')[0]
        raise RecordError(f'invalid topic name {topic!r}: {reason}') from None


def adapted_qos(offered: Sequence):
    """The subscription QoS that matches every offered publisher QoS, as rosbag2 chooses it.

    Reliable only if every publisher is reliable (a reliable reader does not match a
    best-effort writer); transient_local only if every publisher is, so that their stored
    history (maps, plans) is delivered to us too.
    :param offered: the publishers' rclpy QoSProfiles
    """
    from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
    reliable = all(p.reliability == ReliabilityPolicy.RELIABLE for p in offered)
    latched = bool(offered) and all(p.durability == DurabilityPolicy.TRANSIENT_LOCAL
                                    for p in offered)
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST, depth=RECORD_DEPTH,
        reliability=ReliabilityPolicy.RELIABLE if reliable else ReliabilityPolicy.BEST_EFFORT,
        durability=DurabilityPolicy.TRANSIENT_LOCAL if latched else DurabilityPolicy.VOLATILE)


def rosbags_qos(profile):
    """An rclpy QoSProfile as rosbags' Qos (for offered_qos_profiles in the bag)."""
    from rosbags.interfaces import (Qos, QosDurability, QosHistory, QosLiveliness,
                                    QosReliability, QosTime)

    def as_time(duration) -> QosTime:
        # rclpy's infinite duration is int64 max ns, which rosbag2 also writes as sec/nsec.
        return QosTime(*divmod(duration.nanoseconds, 10**9))

    return Qos(history=QosHistory(int(profile.history)), depth=int(profile.depth),
               reliability=QosReliability(int(profile.reliability)),
               durability=QosDurability(int(profile.durability)),
               deadline=as_time(profile.deadline), lifespan=as_time(profile.lifespan),
               liveliness=QosLiveliness(int(profile.liveliness)),
               liveliness_lease_duration=as_time(profile.liveliness_lease_duration),
               avoid_ros_namespace_conventions=bool(profile.avoid_ros_namespace_conventions))
