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


class SetpointRamp:
    """The closed-loop runner's actuator for a SimulatorBackend: one ramped period per output.

    :param backend: the simulator
    :param substeps: physics steps of a control period
    :param parts: equal parts of the period with interpolated setpoints (see step_toward)
    :param feed_velocities: pass the controller's setpoint speeds as feed-forward of the PD
    """

    def __init__(self, backend, substeps: int, parts: int, feed_velocities: bool) -> None:
        self._backend = backend
        self._substeps = substeps
        self._parts = parts
        self._feed_velocities = feed_velocities
        self._last_setpoints = None

    def restart(self) -> None:
        """Forget the last setpoints (after a reset): the next period starts without a ramp."""
        self._last_setpoints = None

    def apply(self, output):
        """Send the output's joint setpoints over one control period; return the readings.

        :param output: the controller's output (joint_setpoints, joint_velocities)
        """
        velocities = output.joint_velocities if self._feed_velocities else None
        target = np.asarray(output.joint_setpoints, dtype=float)
        readings = step_toward(self._backend, self._last_setpoints, target, self._substeps,
                               self._parts, velocities)
        self._last_setpoints = target.copy()
        return readings
