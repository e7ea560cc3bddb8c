"""ROS 2 nodes of biped_planner (thin adapters over the library modules)."""
