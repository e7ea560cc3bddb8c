"""ROS 2 nodes of biped_mpc (thin adapters over the library modules)."""
