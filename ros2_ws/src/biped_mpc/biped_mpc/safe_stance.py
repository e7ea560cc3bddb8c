"""The safe stance: what the controller follows when its references stop or cannot be trusted.

A robot that loses its references mid-step must not stop where it is: frozen on one foot, its
momentum carries the centre of mass past the stance foot (in the node graph that fell in 5 of 6
runs). So a :class:`SafeStance` finishes the step being taken the way the last reference window
planned it (a window spans Np Ts = 1.8 s, longer than a step), puts the swing foot down where that
window lands it (the first double-support sample from now), then moves the ZMP and the hip over
the middle of the feet within settle_time and holds that stance for as long as it is asked for.

A robot that stands (after a reset, or the stance above) leaves the safe stance only for a
reference that fits it: the feet the reference has on the ground are those the robot stands on
(:func:`reference_misfit`). A reference of another walk, or of the robot before a reset, would
otherwise move its feet by the difference in one period.
"""
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.reference_window import ReferenceWindow
from biped_planner.sides import LEFT, RIGHT, SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT
from biped_planner.support_polygon import double_support_box, scaled_foot_box


@dataclass(frozen=True)
class SafeStanceParams:
    """How the safe stance stands.

    Each field's description and range are in its parameter().
    """

    settle_time: float = parameter(0.6, 'time to bring the ZMP and hip over the middle of the '
                                   'feet once both are down (s)', low=0.0, high=10.0)
    feet_tolerance: float = parameter(0.05, 'largest distance between a stance foot of a new '
                                      'reference and where the robot stands on it, to leave '
                                      'the safe stance (m)', low=0.001, high=1.0)
    foot_length: float = parameter(0.2, 'sole length, for the standing ZMP bounds (m)',
                                   low=0.0, high=1.0, low_open=True)
    foot_width: float = parameter(0.1, 'sole width, for the standing ZMP bounds (m)', low=0.0,
                                  high=1.0, low_open=True)
    support_scale: float = parameter(0.9, 'scale of the feet in the standing ZMP bounds',
                                     low=0.1, high=1.0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


def _on_ground(side: int, support: int) -> bool:
    return support in ((SUPPORT_LEFT if side == LEFT else SUPPORT_RIGHT), SUPPORT_DOUBLE)


def _smoothstep(s: np.ndarray) -> np.ndarray:
    s = np.clip(s, 0.0, 1.0)
    return s * s * (3.0 - 2.0 * s)


class SafeStance:
    """References that finish the current step, then stand on both feet (see the module doc).

    Build it with :meth:`finishing_step` (from the last reference window) or :meth:`standing`
    (from the feet the robot stands on); then :meth:`window` gives the references of any time.

    :param params: settle time and foot size
    :param feet: (2, 4) left and right sole x, y, z (m), yaw (rad) once both are down
    :param t_down: time from which both feet are down (s)
    :param zmp_down: (2,) ZMP reference at t_down, moved to the middle of the feet after it (m)
    :param hip_down: (2,) hip reference at t_down (m)
    :param last: the window followed before t_down (None: standing from t_down on)
    :param step_index: step index of the standing samples
    """

    def __init__(self, params: SafeStanceParams, feet: np.ndarray, t_down: float,
                 zmp_down: np.ndarray, hip_down: np.ndarray, last=None,
                 step_index: int = 0) -> None:
        self.params = params
        self.feet = np.array(feet, dtype=float).reshape(2, 4)
        if not np.all(np.isfinite(self.feet)):
            raise InputError(f'safe stance feet must be finite, got {self.feet.tolist()}')
        self.t_down = float(t_down)
        self._zmp_down = np.asarray(zmp_down, dtype=float).reshape(2)
        self._hip_down = np.asarray(hip_down, dtype=float).reshape(2)
        self._last = last
        self._step_index = int(step_index)
        self.middle = 0.5 * (self.feet[LEFT, :2] + self.feet[RIGHT, :2])
        self._zmp_min, self._zmp_max = double_support_box(*(
            scaled_foot_box(foot[0], foot[1], foot[3], params.foot_length, params.foot_width,
                            params.support_scale) for foot in self.feet))

    @classmethod
    def finishing_step(cls, params: SafeStanceParams, last, t: float) -> 'SafeStance':
        """Follow the last window from t until both feet are down, then stand there.

        :param last: the last reference window received (ReferenceWindow, >= 1 sample)
        :param t: now (s); the step in progress at t is finished
        :raises InputError: for an empty window
        """
        n = len(last.t)
        if n < 1:
            raise InputError('the last reference window has no samples')
        dt = float(last.t[1] - last.t[0]) if n > 1 else 0.02
        now = int(np.clip(round((t - last.t[0]) / dt), 0, n - 1))
        double = np.flatnonzero(np.asarray(last.support[now:]) == SUPPORT_DOUBLE)
        down = now + int(double[0]) if double.size else n - 1
        feet = np.array([[*last.left_foot[down], last.left_yaw[down]],
                         [*last.right_foot[down], last.right_yaw[down]]], dtype=float)
        return cls(params, feet, max(float(last.t[down]), t), last.zmp[down], last.hip[down],
                   last if down > now else None, int(last.step_index[down]))

    @classmethod
    def standing(cls, params: SafeStanceParams, left: Sequence[float], right: Sequence[float],
                 t: float, hip: Optional[Sequence[float]] = None) -> 'SafeStance':
        """Stand on these feet from t.

        :param left: left sole x, y, z (m), yaw (rad)
        :param right: right sole x, y, z (m), yaw (rad)
        :param hip: (2,) where the hip is now, moved to the middle within settle_time (None:
            already there)
        """
        feet = np.array([left, right], dtype=float)
        middle = 0.5 * (feet[LEFT, :2] + feet[RIGHT, :2])
        start = middle if hip is None else np.asarray(hip, dtype=float)
        return cls(params, feet, t, start, start)

    @property
    def finishing(self) -> bool:
        """Whether a step is still being finished (a foot may be in the air before t_down)."""
        return self._last is not None

    def window(self, t: float, n: int, dt: float):
        """The references of n samples from t, dt apart: a ReferenceWindow.

        :param t: time of the first sample (s)
        :param n: number of samples, >= 1
        :param dt: sample period (s), > 0
        """
        times = t + dt * np.arange(n)
        settled = _smoothstep((times - self.t_down) / max(self.params.settle_time, 1e-9))[:, None]
        zmp = self._zmp_down + settled * (self.middle - self._zmp_down)
        hip = self._hip_down + settled * (self.middle - self._hip_down)

        def repeat(row) -> np.ndarray:
            return np.tile(np.asarray(row, dtype=float), (n, 1))

        feet_xy = self.feet[:, :2]
        arrays = dict(
            t=times, zmp=zmp, hip=hip, left_foot=repeat(self.feet[LEFT, :3]),
            right_foot=repeat(self.feet[RIGHT, :3]), left_yaw=np.full(n, self.feet[LEFT, 3]),
            right_yaw=np.full(n, self.feet[RIGHT, 3]), left_mass=0.5 * (feet_xy[LEFT] + hip),
            right_mass=0.5 * (feet_xy[RIGHT] + hip), zmp_min=repeat(self._zmp_min),
            zmp_max=repeat(self._zmp_max), left_landing_min=np.full((n, 2), -np.inf),
            left_landing_max=np.full((n, 2), np.inf), right_landing_min=np.full((n, 2), -np.inf),
            right_landing_max=np.full((n, 2), np.inf),
            support=np.full(n, SUPPORT_DOUBLE, dtype=np.uint8),
            step_index=np.full(n, self._step_index, dtype=np.int64))
        before = times < self.t_down - 1e-9
        if self._last is not None and before.any():
            last = self._last
            last_dt = float(last.t[1] - last.t[0]) if len(last.t) > 1 else dt
            index = np.clip(np.round((times[before] - last.t[0]) / last_dt).astype(int), 0,
                            len(last.t) - 1)
            for name, values in arrays.items():
                if name != 't':
                    values[before] = np.asarray(getattr(last, name))[index]
        return ReferenceWindow(**arrays)


def reference_misfit(window, latched: Sequence[Optional[np.ndarray]],
                     tolerance: float) -> Optional[str]:
    """Why a reference does not fit the robot's stance, None when it does.

    It fits when its first sample is a double support (no foot lifts at once) and each foot it
    has on the ground is within tolerance of where the robot stands on that foot.

    :param window: reference window whose sample 0 is now
    :param latched: [left, right] sole x, y, z, yaw the robot stands on (None: not on the ground)
    :param tolerance: largest distance in x, y (m)
    """
    support = int(window.support[0])
    if support != SUPPORT_DOUBLE:
        return 'it starts in single support'
    for side, name in ((LEFT, 'left'), (RIGHT, 'right')):
        latch = latched[side]
        if latch is None or not _on_ground(side, support):
            continue
        foot = np.asarray(window.left_foot if side == LEFT else window.right_foot)[0]
        distance = float(np.hypot(foot[0] - latch[0], foot[1] - latch[1]))
        if not distance <= tolerance:
            return (f'its {name} foot ({foot[0]:.3f}, {foot[1]:.3f}) is {distance:.3f} m from '
                    f'where the robot stands on it (> {tolerance} m)')
    return None
