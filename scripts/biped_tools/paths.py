"""Where things are in the repository: the colcon install tree and the output directory."""
from pathlib import Path

# resolve(): the package is imported through the venv's link to scripts/biped_tools.
REPO = Path(__file__).resolve().parent.parent.parent
INSTALL = REPO / 'ros2_ws' / 'install'
OUTPUT = REPO / 'output'
# The paper's START -> GOAL map, a nav2 map file installed with biped_planner.
PAPER_MAP = INSTALL / 'biped_planner' / 'share' / 'biped_planner' / 'maps' / \
    'paper_start_goal.yaml'
