"""Times of ROS messages: a builtin_interfaces/Time as seconds, shared by every node."""


def seconds_of(stamp) -> float:
    """Seconds of a builtin_interfaces/Time (sec, nanosec)."""
    return stamp.sec + stamp.nanosec * 1e-9
