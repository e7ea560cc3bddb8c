#!/usr/bin/env python3
"""Show other humanoids (optional example-robot-data extra) standing and stepping in PyBullet.

For each robot: torque-controlled standing for --stand seconds, then, from a new reset, the
weight-shift trial of biped_sim.other_robots (centre of mass over the left foot, right foot
lifted --lift metres and put down, centre of mass back), with the Pinocchio leg IK. Prints a
markdown table: mass, standing height (top of the robot in its nominal pose), result, largest
tilt of the pelvis, lowest lifted-foot height while held, real-time factor of the whole run.

A robot passes when it never tilts 3 degrees or more, its pelvis never sinks 1 cm, the lifted
foot is off the ground for the whole hold and both feet are back on the ground at the end.

Needs: pip install -r requirements-robots.txt
Usage: .venv/bin/python scripts/experiments/other_robot_demo.py [--robot g1 talos] [--gui]
           [--lift 0.03]
"""

import argparse
import math
import sys
import time

from biped_mpc.pinocchio_ik import PinocchioLegIk
from biped_planner.rotations import tilt_of_quaternion as tilt
from biped_sim.other_robots import MissingRobotDataError, ROBOTS, sim_config
from biped_sim.weight_shift_trial import weight_shift_trial
from biped_sim.pybullet_backend import PyBulletBackend
import pybullet

MAX_TILT_DEG = 3.0
MAX_SINK = 0.01  # m


def standing_height(sim) -> float:
    """Return the top of the robot's collision shapes above the ground (m), current pose."""
    top = pybullet.getAABB(sim.robot_id, -1, physicsClientId=sim.client_id)[1][2]
    for link in range(pybullet.getNumJoints(sim.robot_id, physicsClientId=sim.client_id)):
        top = max(top, pybullet.getAABB(sim.robot_id, link, physicsClientId=sim.client_id)[1][2])
    return top


def run(name: str, gui: bool, stand: float, lift: float) -> dict:
    """Stand and step one robot; return a row of the table."""
    description = ROBOTS[name]()
    sim = PyBulletBackend(description, sim_config(name, gui=gui))
    try:
        leg_ik = PinocchioLegIk(description.urdf_path, description.leg_joint_names,
                                description.sole_frames, seed=description.nominal_leg_positions())
        start_wall = time.perf_counter()
        first = sim.reset()
        height = standing_height(sim)
        q = description.nominal_leg_positions()
        standing = [sim.step(q) for _ in range(int(round(stand / 0.02)))]
        trial = weight_shift_trial(sim, leg_ik, lift_height=lift)
        elapsed = time.perf_counter() - start_wall
        simulated = standing[-1].time + trial.readings[-1].time if standing else \
            trial.readings[-1].time
        everything = standing + list(trial.readings)
        max_tilt = max(math.degrees(tilt(r.base.orientation)) for r in everything)
        sink = max(first.base.position[2] - r.base.position[2] for r in everything)
        held = trial.during('hold')
        lowest_lifted = min(r.right_sole[2] for r in held)
        final = trial.readings[-1]
        passed = (max_tilt < MAX_TILT_DEG and sink < MAX_SINK
                  and all(not r.right_foot.in_contact for r in held)
                  and final.left_foot.in_contact and final.right_foot.in_contact)
        return {'robot': name, 'mass': sim.total_mass, 'height': height,
                'result': 'stands and steps' if passed else 'FAILED', 'tilt': max_tilt,
                'lifted': lowest_lifted, 'rtf': simulated / elapsed}
    finally:
        sim.close()


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--robot', nargs='+', choices=sorted(ROBOTS), default=sorted(ROBOTS))
    parser.add_argument('--gui', action='store_true', help='open the PyBullet GUI')
    parser.add_argument('--stand', type=float, default=3.0, help='standing time (s)')
    parser.add_argument('--lift', type=float, default=0.03, help='foot lift height (m)')
    args = parser.parse_args()
    rows = []
    try:
        for name in args.robot:
            rows.append(run(name, args.gui, args.stand, args.lift))
    except MissingRobotDataError as error:
        print(error, file=sys.stderr)
        return 2
    print('| robot | mass (kg) | height (m) | result | max tilt (deg) '
          '| lifted foot (mm) | RTF |')
    print('|---|---|---|---|---|---|---|')
    for row in rows:
        print('| %s | %.1f | %.2f | %s | %.2f | %.1f | %.2f |'
              % (row['robot'], row['mass'], row['height'], row['result'], row['tilt'],
                 1000.0 * row['lifted'], row['rtf']))
    return 0 if all(row['result'] != 'FAILED' for row in rows) else 1


if __name__ == '__main__':
    sys.exit(main())
