"""The paper's COMAN experiments run through the node graph (issue 7); CLI: scripts/scenarios.py.

Each scenario module has run(trial, setting) -> dict: one trial in a fresh graph, recorded to a
bag, with a JSON result and the paper-style plots in the trial's directory. sweep.py searches a
setting for the largest that completes; summary.py makes the table of tb:summary.
"""
