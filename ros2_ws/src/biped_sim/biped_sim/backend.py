"""The interface every simulator backend implements (PyBullet humanoid, three-mass model plant).

A controller runs every control period: it reads :meth:`SimulatorBackend.sensors`, computes
joint setpoints and calls :meth:`SimulatorBackend.step`, which advances the physics by
``n_substeps`` fixed physics steps (20 steps of 1 ms for the paper's 50 Hz controller).
Simulated time only advances inside ``step``; nothing reads a wall clock.
"""

import abc
from typing import Optional

import numpy as np

from biped_sim.external_push import ExternalPush
from biped_sim.sensors import SensorReadings


class SimulatorBackend(abc.ABC):
    """A simulated biped that takes joint setpoints and returns sensor readings."""

    @property
    @abc.abstractmethod
    def joint_names(self) -> tuple:
        """Names of the actuated joints, the order of setpoints and joint readings."""

    @property
    @abc.abstractmethod
    def leg_joint_names(self) -> tuple:
        """The 12 leg joints (left then right: hip yaw, roll, pitch, knee, ankle pitch, roll)."""

    @property
    @abc.abstractmethod
    def time(self) -> float:
        """Simulated time since the last reset (s)."""

    @property
    @abc.abstractmethod
    def time_step(self) -> float:
        """Fixed physics step (s)."""

    @abc.abstractmethod
    def reset(self, base_position: Optional[np.ndarray] = None, base_yaw: float = 0.0,
              joint_positions: Optional[dict] = None) -> SensorReadings:
        """Put the robot back in a standing pose at rest and the time to 0.

        :param base_position: (3,) base position (m); None stands the nominal pose on the
            ground at the origin.
        :param base_yaw: heading of the base (rad).
        :param joint_positions: joint name -> angle (rad) overriding the nominal pose.
        :return: the readings in the new state.
        """

    @abc.abstractmethod
    def step(self, joint_setpoints: np.ndarray, n_substeps: Optional[int] = None,
             joint_velocities: Optional[np.ndarray] = None,
             read_sensors: bool = True) -> Optional[SensorReadings]:
        """Track joint setpoints for n_substeps physics steps and return the readings.

        :param joint_setpoints: (len(joint_names),) angles of all actuated joints, or (12,)
            angles of the leg joints only (the other joints keep their last setpoints) (rad).
        :param n_substeps: physics steps to run; None runs one control period.
        :param joint_velocities: optional feed-forward joint speeds, same shape (rad/s).
        :param read_sensors: read the sensors at the end (False: return None, to save the
            readout of an intermediate part of a period).
        :return: the readings at the end of the last physics step.
        """

    @abc.abstractmethod
    def sensors(self) -> SensorReadings:
        """Return the readings of the current state."""

    @abc.abstractmethod
    def push(self, push: ExternalPush) -> None:
        """Schedule an external push, applied over the physics steps it lasts."""

    def close(self) -> None:
        """Release the simulator; the backend is unusable afterwards."""

    def __enter__(self):
        return self

    def __exit__(self, *exc_info) -> None:
        self.close()
