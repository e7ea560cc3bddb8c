"""The biped stack's toolbox: what the user commands in scripts/ share.

- node_graph, bringup: start the node processes (one per node, like `ros2 launch`), watch and
  stop them; bringup is the command line;
- graph_session: drive the running graph as a user would and keep what it publishes;
- recording: record topics into a rosbag2 directory (`scripts/record.py`);
- run_plots, planning_figure: the paper-style figures; demo: the main job's command line;
- scenarios: the paper's experiments, each defined once (geometry, commands, success test) and
  run through the graph by `scripts/scenarios.py`, the demo and the tests;
- ros2_cli, teleop: stand-ins for `ros2 topic/service` and teleop_twist_keyboard;
- closed_loop_walk: the walk the library closed-loop experiments and benchmark set up;
- interface_types, stop_signal, paths: interface classes by name, Ctrl-C as a flag, where
  things are.

`scripts/setup.sh` links this package into the venv, so `import biped_tools` works in every
Python of the venv without touching sys.path. Each user command in scripts/ is a thin entry point
that calls the `main()` of its module here.
"""
