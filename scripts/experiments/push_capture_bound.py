#!/usr/bin/env python3
"""The push table's upper bound: the largest push the LIPM could be stopped from, every cell.

For the cells of `scripts/scenarios.py push-directions` (8 directions x 4 phases, walking in
place or forward at 0.1 m steps, 100 ms pushes), the bound of biped_planner.push_capture_bound:
the LIPM of the robot's mass and the push trials' plan (biped_sim.push_trial), the step
adjuster's limits of the humanoid (ankles 0.1-0.3 m apart sideways, 0.3 m ahead and 0.2 m
behind, swings of 0.15 s or more), up to three steps, the CoP anywhere on the soles and weight
moving at once. No controller of that model withstands more; the table's measured figures can
be read against it.

Usage: .venv/bin/python scripts/experiments/push_capture_bound.py [--gaits in_place forward]
           [--steps 3]
"""
import argparse
import math

from biped_planner.push_capture_bound import (
    AXIS_X, AXIS_Y, PlaneSituation, PushCaptureBound, direction_bound)
from biped_planner.sides import SUPPORT_LEFT, SUPPORT_RIGHT
from biped_sim import push_trial
from biped_sim.robot_description import coman_like

GAITS = {'in_place': 0.0, 'forward': 0.1}
DIRECTIONS = tuple(range(0, 360, 45))
SAMPLE = 1e-3  # s, the sample period of the one-sample window that gives the feet


def robot_mass() -> float:
    """The humanoid's mass (kg), the three-mass model's total."""
    masses = coman_like().controller_model.masses
    return masses.left_leg_mass + masses.torso_mass + masses.right_leg_mass


def situations(step_length: float, phase: str, cop_margin: float = 0.0) -> tuple:
    """(x, y) PlaneSituations of the trials' walk when a push of `phase` begins, the CoP
    kept cop_margin (m) inside the soles' edges."""
    reference = push_trial.walk_reference(step_length)
    start = push_trial.push_start(reference, phase)
    window = reference.sample(start, 1, SAMPLE)
    dcm = reference.lipm.state_at(start)[1]
    now = next(p for p in reference.phases if p.t_begin <= start < p.t_end)
    if now.support in (SUPPORT_LEFT, SUPPORT_RIGHT):
        swinging, next_swing, elapsed = now.swing_side, now.swing_side, start - now.t_begin
    else:
        later = next(p for p in reference.phases if p.t_begin >= now.t_end - 1e-9
                     and p.support in (SUPPORT_LEFT, SUPPORT_RIGHT))
        swinging, next_swing, elapsed = None, later.swing_side, 0.0
    half = (0.5 * push_trial.REFERENCE.foot_length - cop_margin,
            0.5 * push_trial.REFERENCE.foot_width - cop_margin)
    return tuple(PlaneSituation(axis, float(dcm[axis]),
                                (float(window.left_foot[0][axis]),
                                 float(window.right_foot[0][axis])),
                                swinging, next_swing, elapsed, half[axis])
                 for axis in (AXIS_X, AXIS_Y))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--gaits', nargs='+', choices=tuple(GAITS), default=list(GAITS))
    parser.add_argument('--steps', type=int, default=3, help='landings searched')
    parser.add_argument('--cop-margin', type=float, default=0.0,
                        help='m the CoP keeps from the soles\' edges (the stabilizer: 0.01)')
    parser.add_argument('--min-double-support', type=float, default=0.0,
                        help='s both feet stand before a lift-off, at least')
    args = parser.parse_args()
    mass = robot_mass()
    limits = push_trial.HUMANOID_STEP_LIMITS
    print(f'LIPM {mass:.1f} kg, z_c {limits.com_height} m, pushes of '
          f'{push_trial.PUSH_DURATION} s, up to {args.steps} steps, CoP margin '
          f'{args.cop_margin} m, double support {args.min_double_support} s or more: largest '
          f'push stopped (N)\n')
    for gait in args.gaits:
        phases = tuple(push_trial.PHASES)
        bounds = {}
        for phase in phases:
            planes = situations(GAITS[gait], phase, args.cop_margin)
            plane_bounds = []
            for situation in planes:
                bound = PushCaptureBound(situation, push_trial.PUSH_DURATION, mass, limits,
                                         args.steps,
                                         min_double_support=args.min_double_support)
                plane_bounds.append((bound.largest(-1), bound.largest(+1)))
            for direction in DIRECTIONS:
                bounds[direction, phase] = direction_bound(plane_bounds,
                                                           math.radians(direction))
        print(f'| {gait.replace("_", " ")} | ' + ' | '.join(phases) + ' |')
        print('|---|' + '---|' * len(phases))
        for direction in DIRECTIONS:
            print(f'| {direction} deg | '
                  + ' | '.join(f'{bounds[direction, p]:.0f}' for p in phases) + ' |')
        print(f'\nminimum {min(bounds.values()):.0f} N\n', flush=True)


if __name__ == '__main__':
    main()
