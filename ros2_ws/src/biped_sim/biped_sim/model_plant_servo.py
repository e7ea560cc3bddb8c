"""How the model plant's masses follow their targets: a jerk servo per mass, like a stiff joint.

Each mass follows its target trajectory with a jerk: the cubic through its last four targets
(of calls of equal duration) gives the target's jerk (feed-forward) and its state now (position,
velocity, acceleration), and a state feedback K with every eigenvalue of A - B K at servo_pole
(Ackermann) adds K (x_target - x). A cubic reproduces a constant jerk exactly, so a target that
keeps its jerk is followed without error; the MPC changes its jerk every period, which the servo
follows with a lag of a few periods (the plant is no copy of the controller's model). The jerk
that only reaches the next target position (position deadbeat) is not used: it makes the
velocity oscillate with a growing factor -2 per period.
"""
import numpy as np

from biped_mpc.linear_model import LinearModel, N_PLANES, POSITION, state_index

MASSES = (0, 1, 2)  # left leg, torso, right leg in the plant's state layout
TORSO = 1


def placement_gain(a: np.ndarray, b: np.ndarray, pole: float) -> np.ndarray:
    """State feedback K with every eigenvalue of A - B K at pole (Ackermann's formula).

    :param a: (n, n) discrete state matrix of one mass (a triple integrator)
    :param b: (n,) discrete input vector
    :param pole: the (repeated) closed-loop eigenvalue, in [0, 1)
    :return: (n,) gain
    """
    n = a.shape[0]
    controllability = np.column_stack([np.linalg.matrix_power(a, k) @ b for k in range(n)])
    last = np.zeros(n)
    last[-1] = 1.0
    shifted = a - pole * np.eye(n)
    return last @ np.linalg.solve(controllability, np.linalg.matrix_power(shifted, n))


class MassServo:
    """The jerks that make the three masses follow their targets (see the module docstring).

    :param model: the plant's continuous model (its discretisation gives the gains)
    :param period: control period (s); the pole is servo_pole per period
    :param time_step: physics step (s), the unit of the call durations
    :param servo_pole: eigenvalue of each mass's tracking error per control period, [0, 1)
    :param feed_forward: add the jerk of the cubic through the last four targets
    """

    def __init__(self, model: LinearModel, period: float, time_step: float, servo_pole: float,
                 feed_forward: bool) -> None:
        self._model = model
        self._period = period
        self._step = time_step
        self._pole = servo_pole
        self._feed_forward = feed_forward
        self._gains = {}
        self._history = None

    def reset(self, targets: np.ndarray) -> None:
        """Hold the targets (2, 3) (x and y of each mass) as the last three of the history."""
        self._history = np.repeat(targets[None], 3, axis=0)

    def jerk(self, targets: np.ndarray, state: np.ndarray, duration: float) -> np.ndarray:
        """Jerks (2, 3) that follow the cubic through the last four targets of each mass.

        :param targets: (2, 3) new targets of the masses (m)
        :param state: (2, 9) the plant's state now
        :param duration: duration of the call (s)
        """
        history = np.concatenate([self._history, targets[None]], axis=0)  # (4, 2, 3)
        self._history = history[1:]
        h = duration
        p_minus2, p_minus1, p_now, p_next = history
        jerk_ff = (p_next - 3.0 * p_now + 3.0 * p_minus1 - p_minus2) / h ** 3
        acceleration = (p_next - 2.0 * p_now + p_minus1) / h ** 2
        velocity = (p_next - p_minus1) / (2.0 * h) - jerk_ff * h ** 2 / 6.0
        if not self._feed_forward:
            jerk_ff = np.zeros_like(jerk_ff)
        jerk = np.empty((N_PLANES, 3))
        for mass in MASSES:
            block = slice(state_index(mass, POSITION), state_index(mass, POSITION) + 3)
            target = np.stack([p_now[:, mass], velocity[:, mass], acceleration[:, mass]], axis=1)
            jerk[:, mass] = jerk_ff[:, mass] + (target - state[:, block]) @ self._gain(h)
        return jerk

    def _gain(self, duration: float) -> np.ndarray:
        """Servo gain for calls of this duration, with the pole scaled to keep its time constant.

        The pole is servo_pole per control period, servo_pole ** (duration / period) per call.
        """
        key = round(duration / self._step)
        gain = self._gains.get(key)
        if gain is None:
            discrete = self._model.discretize(duration)
            block = slice(state_index(TORSO, POSITION), state_index(TORSO, POSITION) + 3)
            pole = self._pole ** (duration / self._period)
            gain = placement_gain(discrete.a[block, block], discrete.b[block, TORSO], pole)
            self._gains[key] = gain
        return gain
