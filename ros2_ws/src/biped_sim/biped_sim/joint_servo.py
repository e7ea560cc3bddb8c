"""How a control period's joint setpoints reach the simulated joint servos.

A real joint servo runs at the physics rate and interpolates the controller's setpoints: a stiff
PD that sees a 50 Hz step kicks the robot at every period. The period is split into parts, each
tracking the setpoint linearly interpolated from the previous one, with the controller's
setpoint speeds as feed-forward of the PD.
"""
from typing import Optional

import numpy as np


def step_toward(backend, previous: Optional[np.ndarray], target: np.ndarray, substeps: int,
                parts: int = 4, velocities: Optional[np.ndarray] = None):
    """Run one control period of the backend towards new setpoints.

    :param backend: a SimulatorBackend
    :param previous: setpoints of the last period (same shape as target), None: no ramp
    :param target: setpoints at the end of the period (rad)
    :param substeps: physics steps of the period
    :param parts: equal parts of the period with interpolated setpoints, >= 1 (no ramp when it
        does not divide substeps)
    :param velocities: feed-forward joint speeds (rad/s), same shape as target, or None
    :return: the backend's readings at the end of the period
    """
    target = np.asarray(target, dtype=float)
    if parts <= 1 or substeps % parts != 0 or previous is None:
        return backend.step(target, substeps, joint_velocities=velocities)
    previous = np.asarray(previous, dtype=float)
    for part in range(1, parts + 1):
        readings = backend.step(previous + (target - previous) * part / parts,
                                substeps // parts, joint_velocities=velocities,
                                read_sensors=part == parts)
    return readings
