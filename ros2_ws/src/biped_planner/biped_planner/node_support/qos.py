"""Quality of service of the latched topics (plans, maps, markers), shared by every node."""
from rclpy.qos import DurabilityPolicy, QoSProfile, ReliabilityPolicy

# Publishers keep the latest message for late subscribers.
LATCHED = QoSProfile(depth=1, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                     reliability=ReliabilityPolicy.RELIABLE)
# Subscribers keep more than the latest: two plans in a burst must both be seen.
LATCHED_IN = QoSProfile(depth=10, durability=DurabilityPolicy.TRANSIENT_LOCAL,
                        reliability=ReliabilityPolicy.RELIABLE)
