#!/usr/bin/env python3
"""How hard a push towards the stance foot the LIPM can recover from at best, and what it takes.

A push towards the stance foot's outer side (270 deg early in a right single support, walking
in place, the push trials' gait: biped_sim.push_trial) cannot be answered by the swing foot,
which may not cross the stance foot: the swing foot lands beside the stance foot, and the
stance foot then steps out. This prints, for the humanoid's step limits, the largest 100 ms
pelvis push after which the LIPM's DCM can still be caught by that outward step, with the ZMP
always at the best edge (the stance sole's outer edge until the stance foot lifts, then the
landed sole's edge towards the push), for choices of the two steps' timing: the bound an ideal
controller reaches, and which timing levers carry it.

Closed forms only: with the ZMP p and a constant force F, xi' = omega (xi - p) + F / (m omega),
so the DCM runs away from p - F / (m omega^2) as exp(omega t).

Usage: .venv/bin/python scripts/experiments/lateral_capture_bound.py [--mass KG]
"""
import argparse
import math

from biped_sim import push_trial
from biped_sim.robot_description import coman_like


def run_away(xi: float, zmp: float, duration: float, omega: float, drift: float = 0.0) -> float:
    """The DCM after `duration` s with the ZMP at zmp and a force drift = F / (m omega^2)."""
    pole = zmp - drift
    return pole + (xi - pole) * math.exp(omega * duration)


def push_onset() -> tuple:
    """(push start, lift-off of its single support, lateral DCM at the push) of the trials' walk
    (s, s, m)."""
    reference = push_trial.walk_in_place_reference()
    start = push_trial.push_start(reference, 'early_single')
    lift_off = max(phase.t_begin for phase in reference.phases if phase.t_begin <= start)
    return start, lift_off, float(reference.lipm.state_at(start)[1][1])


def recovered(force: float, mass: float, onset: tuple, first_landing: float,
              double_support: float, second_step: float) -> bool:
    """The outward step (stance foot, right) catches the DCM after a push to -y.

    :param onset: push_onset()
    :param first_landing: the swing (left) foot lands this long after lift-off (s)
    :param double_support: then both feet stand this long (s)
    :param second_step: then the right foot swings this long (s)
    """
    limits = push_trial.HUMANOID_STEP_LIMITS
    omega = limits.omega
    start, lift_off, xi = onset
    stance_y = -0.5 * push_trial.STEP_WIDTH
    edge = 0.5 * push_trial.REFERENCE.foot_width
    drift = force / (mass * omega ** 2)
    push_end = start + push_trial.PUSH_DURATION
    # the right sole's outer edge until the left foot is down and the double support is over,
    # then the left sole's edge towards the push while the right foot swings out
    free = max(lift_off + first_landing, start) + double_support
    left_y = stance_y + limits.width_min
    zmp_changes = ((start, stance_y - edge), (free, left_y - edge))
    t, end = start, free + second_step
    for change in sorted({push_end, free, end}):
        if change <= t or t >= end:
            continue
        zmp = [z for since, z in zmp_changes if since <= t][-1]
        xi = run_away(xi, zmp, min(change, end) - t, omega, -drift if t < push_end else 0.0)
        t = change
    reach = left_y - limits.width_max - edge   # the right sole's outer edge at its widest
    return xi >= reach


def largest(mass: float, onset: tuple, **timing) -> int:
    best = 0
    for force in range(0, 500, 5):
        if not recovered(force, mass, onset, **timing):
            break
        best = force
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    parser.add_argument('--mass', type=float, default=None,
                        help='robot mass (kg); default: the COMAN-like model\'s')
    args = parser.parse_args()
    if args.mass is None:
        masses = coman_like().controller_model.masses
        args.mass = masses.left_leg_mass + masses.torso_mass + masses.right_leg_mass
    limits = push_trial.HUMANOID_STEP_LIMITS
    single = push_trial.TIMING.single_support
    double = push_trial.TIMING.double_support
    fastest = limits.step_time_min
    onset = push_onset()
    print(f'LIPM z_c {limits.com_height} m, mass {args.mass:.2f} kg, feet '
          f'{push_trial.STEP_WIDTH} m apart, soles {push_trial.REFERENCE.foot_width} m wide, '
          f'ankles {limits.width_min}-{limits.width_max} m apart; push 100 ms towards the '
          f'stance foot, early single support\n')
    print('| swing foot lands after (s) | double support (s) | outward step (s) | largest '
          'push caught (N) |')
    print('|---|---|---|---|')
    for first in (single, fastest):
        for middle in (double, 0.0):
            for second in (single, fastest):
                force = largest(args.mass, onset, first_landing=first,
                                double_support=middle, second_step=second)
                print(f'| {first:.2f} | {middle:.2f} | {second:.2f} | {force} |')


if __name__ == '__main__':
    main()
