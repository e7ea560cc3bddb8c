"""ROS 2 nodes of biped_sim (thin adapters over the library modules)."""
