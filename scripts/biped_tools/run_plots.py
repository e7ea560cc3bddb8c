"""Figures of a graph run: top view (map, path, footsteps, COM) and ZMP against the support
polygon, in the style of the paper's figures. Input: a graph_session.RunSeries."""
import math
from pathlib import Path
from typing import Optional

from biped_planner.sides import LEFT
import numpy as np


def pyplot():
    """matplotlib.pyplot on the file-only Agg backend (no display needed)."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    return plt


def foot_outline(step, length: float, width: float, **style):
    """The rectangle of a foot (length x width in m) centred on a footstep, turned by its yaw.

    :param step: anything with x, y (m) and yaw (rad)
    :param style: matplotlib patch keywords (edgecolor, fill, lw, ...)
    :return: a matplotlib Polygon to add to an axes
    """
    from matplotlib.patches import Polygon
    half = np.array([[1, 1], [1, -1], [-1, -1], [-1, 1]]) * [0.5 * length, 0.5 * width]
    cos_yaw, sin_yaw = math.cos(step.yaw), math.sin(step.yaw)
    corners = half @ np.array([[cos_yaw, sin_yaw], [-sin_yaw, cos_yaw]]) + [step.x, step.y]
    return Polygon(corners, closed=True, **style)


def zmp_inside_fraction(series, margin: float = 0.0) -> float:
    """Fraction of measured ZMP samples inside the reference support bounds of the same time
    (the 0.9-scaled polygon's box widened back to the foot: margin in m)."""
    if not series.zmp or not series.bounds:
        return float('nan')
    bounds = np.array(series.bounds)
    zmp = np.array([z for z in series.zmp if np.isfinite(z[1])])
    if zmp.size == 0:
        return float('nan')
    index = np.clip(np.searchsorted(bounds[:, 0], zmp[:, 0]), 0, len(bounds) - 1)
    b = bounds[index]
    inside = ((zmp[:, 1] >= b[:, 1] - margin) & (zmp[:, 1] <= b[:, 3] + margin) &
              (zmp[:, 2] >= b[:, 2] - margin) & (zmp[:, 2] <= b[:, 4] + margin))
    return float(np.mean(inside))


def top_view(series, out: Path, title: str, grid=None, goal=None, foot=(0.2, 0.1),
             extra=None) -> Path:
    """Map, A* path, footsteps of the last plan, pelvis and COM paths."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 7))
    if grid is not None:
        x0, x1, y0, y1 = grid.extent
        ax.imshow(grid.values >= 50, origin='lower', extent=(x0, x1, y0, y1), cmap='Greys',
                  vmin=0, vmax=1.5, alpha=0.8)
    if series.path:
        path = np.array(series.path)
        ax.plot(path[:, 0], path[:, 1], 'k--', lw=1.5, label='A* path')
    plans = [p for p in series.plans if p.status == 0]
    if plans:
        for step in plans[-1].footsteps:
            ax.add_patch(foot_outline(step, foot[0], foot[1], fill=False,
                                      ec='r' if step.side == LEFT else 'b', lw=1.0))
    if series.com:
        com = np.array(series.com)
        ax.plot(com[:, 1], com[:, 2], color='limegreen', lw=2, label='COM (measured)')
    if series.zmp:
        zmp = np.array([z for z in series.zmp if np.isfinite(z[1])])
        if zmp.size:
            ax.plot(zmp[:, 1], zmp[:, 2], color='m', lw=0.6, alpha=0.7, label='ZMP (F/T)')
    if goal is not None:
        ax.plot(goal[0], goal[1], 'k*', ms=14, label='goal')
    if extra is not None:
        extra(ax)
    ax.set_aspect('equal')
    ax.set_xlabel('x (m)')
    ax.set_ylabel('y (m)')
    ax.set_title(title)
    ax.plot([], [], 'r-', label='left foot')
    ax.plot([], [], 'b-', label='right foot')
    ax.legend(loc='best', fontsize=8)
    return save_figure(fig, out)


def zmp_figure(series, out: Path, title: str, window: Optional[tuple] = None) -> Path:
    """Measured and reference ZMP in x and y against the support polygon bounds over time."""
    plt = pyplot()
    fig, axes = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
    bounds = np.array(series.bounds) if series.bounds else np.zeros((0, 5))
    reference = np.array(series.zmp_reference) if series.zmp_reference else np.zeros((0, 3))
    zmp = np.array(series.zmp) if series.zmp else np.zeros((0, 3))
    for axis, (ax, label) in enumerate(zip(axes[:2], ('x', 'y'))):
        if len(bounds):
            ax.fill_between(bounds[:, 0], bounds[:, 1 + axis], bounds[:, 3 + axis], step='post',
                            color='0.8', label='support polygon (x0.9)')
        if len(reference):
            ax.plot(reference[:, 0], reference[:, 1 + axis], 'k--', lw=1, label='reference ZMP')
        if len(zmp):
            ax.plot(zmp[:, 0], zmp[:, 1 + axis], 'r-', lw=0.8, label='measured ZMP (F/T)')
        ax.set_ylabel(f'ZMP {label} (m)')
        ax.legend(loc='upper left', fontsize=8)
    if series.com:
        com = np.array(series.com)
        axes[2].plot(com[:, 0], com[:, 3], 'g-', label='COM height')
        axes[2].set_ylabel('COM z (m)')
        axes[2].legend(loc='upper left', fontsize=8)
    axes[-1].set_xlabel('simulated time (s)')
    if window is not None:
        axes[-1].set_xlim(*window)
    axes[0].set_title(title)
    return save_figure(fig, out)


def save_figure(fig, path: Path) -> Path:
    """Lay out a figure, save it (110 dpi) and close it."""
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    pyplot().close(fig)
    return Path(path)


def save_time_figure(fig, ax, path: Path, ylabel: str, title: str) -> Path:
    """Label a figure over simulated time, save it (110 dpi) and close it."""
    ax.set_xlabel('simulated time (s)')
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(loc='lower left', fontsize=8)
    return save_figure(fig, path)
