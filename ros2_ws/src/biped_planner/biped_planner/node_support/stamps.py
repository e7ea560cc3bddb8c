"""Times of ROS messages: a builtin_interfaces/Time as seconds, shared by every node."""


def seconds_of(stamp) -> float:
    """Seconds of a builtin_interfaces/Time (sec, nanosec)."""
    return stamp.sec + stamp.nanosec * 1e-9


def nanoseconds_of(stamp) -> int:
    """Nanoseconds of a builtin_interfaces/Time (sec, nanosec), exact."""
    return stamp.sec * 1_000_000_000 + stamp.nanosec


def time_msg_of(seconds: float):
    """A builtin_interfaces/Time of seconds (rounded to the nanosecond)."""
    from rclpy.time import Time
    return Time(nanoseconds=round(seconds * 1e9)).to_msg()
