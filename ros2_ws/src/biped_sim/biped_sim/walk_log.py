"""The per-cycle record of the paper's MATLAB loop (MPC jerks into the model plant), scored.

Planes x then y on the middle axis; the ZMP of the log is the plant's fictitious ZMP, which may
leave the real support polygon (the centre of pressure is its projection on it).
"""
from dataclasses import dataclass

import numpy as np

from biped_mpc.linear_model import (N_OUTPUTS, N_PLANES, N_STATES, OUTPUT_LEFT_LEG,
                                    OUTPUT_RIGHT_LEG, OUTPUT_ZMP)
from biped_mpc.qp_backends import QpStatus


@dataclass
class WalkLog:
    """Per-cycle record of a closed-loop run on the model plant, K cycles.

    :param t: cycle times t_k (K,) (s)
    :param state: true states x_k (K, 2, 9)
    :param estimate: states the MPC used (K, 2, 9)
    :param measured: measured outputs y_k (K, 2, 3) (m)
    :param true_outputs: noise-free outputs (K, 2, 3) (m), ZMP = fictitious ZMP
    :param reference: output references at t_k (K, 2, 3) (m)
    :param zmp_min: scaled support box lower corner at t_k (K, 2) (m)
    :param zmp_max: scaled support box upper corner at t_k (K, 2) (m)
    :param polygon_min: real (unscaled) support polygon lower corner (K, 2) (m)
    :param polygon_max: real support polygon upper corner (K, 2) (m)
    :param zmp_real: centre of pressure (K, 2) (m)
    :param jerk: applied jerks (K, 2, 3) (m/s^3)
    :param force: applied push (K, 2) (N)
    :param status: QP status per plane (K, 2) (QpStatus values)
    :param solve_time: MPC solver time per cycle, both planes (K,) (s)
    :param support: support label of the reference at t_k (K,)
    :param com: true centre of mass of the plant (K, 2) (m)
    :param com_velocity: true centre-of-mass velocity (K, 2) (m/s)
    :param torso: true torso mass position (K, 2) (m)
    :param hip: hip reference at t_k (K, 2) (m)
    :param reference_end: time the reference comes to rest (s)
    """

    t: np.ndarray
    state: np.ndarray
    estimate: np.ndarray
    measured: np.ndarray
    true_outputs: np.ndarray
    reference: np.ndarray
    zmp_min: np.ndarray
    zmp_max: np.ndarray
    polygon_min: np.ndarray
    polygon_max: np.ndarray
    zmp_real: np.ndarray
    jerk: np.ndarray
    force: np.ndarray
    status: np.ndarray
    solve_time: np.ndarray
    support: np.ndarray
    com: np.ndarray
    com_velocity: np.ndarray
    torso: np.ndarray
    hip: np.ndarray
    reference_end: float = 0.0

    @classmethod
    def empty(cls, n: int) -> 'WalkLog':
        """A log of n cycles of zeros."""
        return cls(
            t=np.zeros(n), state=np.zeros((n, N_PLANES, N_STATES)),
            estimate=np.zeros((n, N_PLANES, N_STATES)),
            measured=np.zeros((n, N_PLANES, N_OUTPUTS)),
            true_outputs=np.zeros((n, N_PLANES, N_OUTPUTS)),
            reference=np.zeros((n, N_PLANES, N_OUTPUTS)), zmp_min=np.zeros((n, N_PLANES)),
            zmp_max=np.zeros((n, N_PLANES)), polygon_min=np.zeros((n, N_PLANES)),
            polygon_max=np.zeros((n, N_PLANES)), zmp_real=np.zeros((n, N_PLANES)),
            jerk=np.zeros((n, N_PLANES, 3)), force=np.zeros((n, N_PLANES)),
            status=np.zeros((n, N_PLANES), dtype=int), solve_time=np.zeros(n),
            support=np.zeros(n, dtype=int), com=np.zeros((n, N_PLANES)),
            com_velocity=np.zeros((n, N_PLANES)), torso=np.zeros((n, N_PLANES)),
            hip=np.zeros((n, N_PLANES)))

    @property
    def zmp(self) -> np.ndarray:
        """Fictitious (model) ZMP of the plant (K, 2) (m)."""
        return self.true_outputs[:, :, OUTPUT_ZMP]

    def polygon_excursion(self) -> np.ndarray:
        """Distance of the fictitious ZMP outside the real support polygon, per plane (K, 2) (m).

        :return: 0 inside, positive outside
        """
        return np.maximum(np.maximum(self.polygon_min - self.zmp, self.zmp - self.polygon_max),
                          0.0)

    def scaled_box_excursion(self) -> np.ndarray:
        """Distance of the fictitious ZMP outside the scaled (0.9) support box (K, 2) (m).

        :return: 0 inside, positive outside
        """
        return np.maximum(np.maximum(self.zmp_min - self.zmp, self.zmp - self.zmp_max), 0.0)


def tracking_rms(log: WalkLog) -> dict:
    """Root mean square tracking errors of the true outputs over the run (m).

    :param log: a run
    :return: {'left_leg': (x, y), 'right_leg': (x, y), 'zmp': (x, y)}
    """
    error = log.true_outputs - log.reference
    rms = np.sqrt(np.mean(error ** 2, axis=0))
    return {'left_leg': rms[:, OUTPUT_LEFT_LEG].tolist(),
            'right_leg': rms[:, OUTPUT_RIGHT_LEG].tolist(),
            'zmp': rms[:, OUTPUT_ZMP].tolist()}


def optimal_fraction(log: WalkLog) -> float:
    """Fraction of plane-cycles solved to optimality.

    :param log: a run
    :return: in [0, 1]
    """
    return float(np.mean(log.status == int(QpStatus.OPTIMAL)))
