"""Draw the paper's planning figure (Fig. PathPlanning) for the START-GOAL example map.

Occupied cells (grey), inflated cells (light grey), the A* path (black dashed), footsteps as
rectangles (left red, right blue), the ZMP reference (magenta) and the hip reference (lime,
dashed). Usage: scripts/plot_planning.py [--out output/planning]
"""
import argparse
import os

from biped_planner.astar import AStarPlanner
from biped_planner.example_maps import paper_start_goal_example
from biped_planner.footstep_planner import FootstepPlanner
from biped_planner.sides import LEFT
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams, WalkingReference
import numpy as np

from biped_tools.run_plots import foot_outline, pyplot


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--out', default=os.path.join('output', 'planning'),
                        help='output directory (default: output/planning)')
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    plt = pyplot()
    from matplotlib.patches import Rectangle

    grid, start, goal = paper_start_goal_example()
    astar = AStarPlanner(grid)
    plan = FootstepPlanner().plan_on_map(astar, start, goal)
    params = ReferenceParams()
    reference = WalkingReference(plan.footsteps, StepTiming(0.4, 0.1), params,
                                 hip0=(start.x, start.y))
    window = reference.sample(reference.t_start, int(reference.duration / 0.01) + 1, 0.01)

    figure, axes = plt.subplots(figsize=(7, 7))
    x_min, x_max, y_min, y_max = grid.extent
    res = grid.resolution
    for cells, colour in ((astar.blocked & ~astar.occupied, '0.85'), (astar.occupied, '0.45')):
        for row, col in np.argwhere(cells):
            axes.add_patch(Rectangle((x_min + col * res, y_min + row * res), res, res,
                                     facecolor=colour, edgecolor='none'))
    axes.plot(plan.grid_path.points[:, 0], plan.grid_path.points[:, 1], 'k--', lw=1.5,
              label='A* path')
    for step in plan.footsteps:
        colour = 'red' if step.side == LEFT else 'blue'
        axes.add_patch(foot_outline(step, params.foot_length, params.foot_width,
                                    fill=False, edgecolor=colour, lw=1.0))
    axes.plot(window.zmp[:, 0], window.zmp[:, 1], color='magenta', lw=1.2, label='ZMP')
    axes.plot(window.hip[:, 0], window.hip[:, 1], '--', color='lime', lw=1.8, label='hip')
    axes.plot([], [], color='red', label='left foot')
    axes.plot([], [], color='blue', label='right foot')
    axes.add_patch(Rectangle((0, 0), 0, 0, facecolor='0.45', label='occupied'))
    axes.add_patch(Rectangle((0, 0), 0, 0, facecolor='0.85', label='inflated'))
    axes.annotate('START', (start.x, start.y), xytext=(start.x + 0.1, start.y - 0.25))
    axes.annotate('GOAL', (goal.x, goal.y), xytext=(goal.x - 0.5, goal.y + 0.25))
    axes.set_xlim(x_min, x_max)
    axes.set_ylim(y_min, y_max)
    axes.set_aspect('equal')
    axes.set_xlabel('x (m)')
    axes.set_ylabel('y (m)')
    axes.set_title(f'A* path {plan.grid_path.cost:.2f} m, {len(plan.footsteps) - 2} steps, '
                   f'{reference.duration:.1f} s')
    axes.legend(loc='lower right', fontsize=8)
    path = os.path.join(args.out, 'planning.png')
    figure.savefig(path, dpi=130, bbox_inches='tight')
    print(path)
    return 0
