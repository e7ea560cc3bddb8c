"""Node plumbing shared by the nodes of every biped package (nav2_util's role).

Public on purpose: running a node, ROS parameters from dataclasses, and the message forms of the
contracts between packages (the reference window). Library modules never import it.
"""
