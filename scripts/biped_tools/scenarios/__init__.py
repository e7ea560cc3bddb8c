"""The paper's COMAN experiments, each defined once; CLI: scripts/scenarios.py (command.py).

Each scenario module (disk, omni, push, terrain, start_goal) holds the scenario's geometry,
commands and success test, and run(trial, setting) -> dict: one trial in a fresh node graph
(trial.py), recorded to a bag, with a JSON result and the paper-style plots in the trial's
directory. The same definitions serve the graph tests and the library closed-loop probe
(scripts/experiments/scenario_probe.py). sweep.py searches a setting for the largest that
completes; summary.py makes the table of tb:summary; video.py films one scenario.
"""
