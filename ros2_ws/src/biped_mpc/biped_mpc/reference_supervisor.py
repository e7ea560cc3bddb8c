"""Which references the controller follows each cycle: the planner's, or a safe stance.

The planner's reference window is followed while it is fresh (at most stale_timeout old). When
it goes stale, or the sensor data does, the controller switches to a
:class:`biped_mpc.safe_stance.SafeStance` that finishes the step along the last window and then
stands; it leaves that stance only for a fresh reference that fits the feet it stands on. After
a reset of the robot the old references are dropped and the robot stands where it is until a
reference fits.
"""
import dataclasses
from typing import Optional, Sequence, Tuple

import numpy as np

from biped_mpc.safe_stance import reference_misfit, SafeStance, SafeStanceParams


def window_from(window, start: int, n: int):
    """Samples start .. start + n - 1 of a window, the last sample repeated past its end."""
    last = len(window.t) - 1
    index = np.minimum(np.arange(start, start + n), last)
    return dataclasses.replace(window, **{f.name: getattr(window, f.name)[index]
                                          for f in dataclasses.fields(window)})


class ReferenceSupervisor:
    """Keeps the newest reference window and decides what the controller follows.

    :param params: how the safe stance stands
    :param dt: the controller's period, the references' sample period (s)
    :param horizon: samples per window the controller uses (Np + 1)
    """

    def __init__(self, params: SafeStanceParams, dt: float, horizon: int) -> None:
        self.params = params
        self._dt = dt
        self._horizon = horizon
        self.reference = None
        self._reference_start = None  # its first horizon samples, cut once
        self.hold: Optional[SafeStance] = None
        self.hold_reason = ''
        self.events = []  # what changed since the last take_events(), for the log

    def set_reference(self, window) -> None:
        """A new reference window (checked by the caller)."""
        self.reference = window
        # the horizon from its first sample, cut now: references come ahead of their period
        self._reference_start = window_from(window, 0, self._horizon)

    def stand(self, left: Sequence[float], right: Sequence[float], t: float,
              reason: str) -> None:
        """Drop the references and stand on these feet (after a reset of the robot).

        :param left: left sole x, y, z (m), yaw (rad)
        :param right: right sole x, y, z (m), yaw (rad)
        """
        self.reference = self._reference_start = None
        self.hold = SafeStance.standing(self.params, left, right, t)
        self.hold_reason = reason

    def take_events(self) -> list:
        events, self.events = self.events, []
        return events

    def window(self, t: float, stale_timeout: float, stale_sensors: str,
               latched: Sequence[Optional[np.ndarray]],
               feet_now: Optional[Tuple[np.ndarray, np.ndarray]]):
        """The window to follow from t and why the robot holds a stance (None: it does not).

        :param t: now (s)
        :param stale_timeout: references older than this are lost (s)
        :param stale_sensors: why the sensor data cannot be trusted ('' when it can)
        :param latched: [left, right] feet the robot stands on (None: not on the ground)
        :param feet_now: (left, right) feet to stand on when no reference was ever received
            (None: nothing to stand on yet)
        :return: (window or None when there is nothing to follow yet, reason or None)
        """
        reference = self.reference
        current = None
        if reference is not None and -self._dt - 1e-9 <= t - reference.t[0] <= stale_timeout:
            start = max(0, int(round((t - reference.t[0]) / self._dt)))
            current = self._reference_start if start == 0 else \
                window_from(reference, start, self._horizon)
        if self.hold is None:
            if reference is None and feet_now is None:
                return None, 'waiting for a reference'
            if not stale_sensors and current is not None:
                return current, None
            if stale_sensors:
                self._start_hold(t, stale_sensors, feet_now)
            else:
                age = 'none received' if reference is None else \
                    f'the last is {t - reference.t[0]:.2f} s old (> {stale_timeout} s)'
                self._start_hold(t, f'reference_trajectory lost: {age}; finishing the step, '
                                 f'then standing', feet_now)
        reason = stale_sensors or self.hold_reason
        if current is not None and not stale_sensors:
            misfit = 'a foot is not down yet' if any(foot is None for foot in latched) else \
                reference_misfit(current, latched, self.params.feet_tolerance)
            if misfit is None:
                self.events.append(f'references fit the stance at t={t:.2f} s: following them '
                                   f'again (held because {self.hold_reason})')
                self.hold = None
                return current, None
            reason = f'{self.hold_reason}; the new reference does not fit: {misfit}'
        return self.hold.window(t, self._horizon, self._dt), reason

    def _start_hold(self, t: float, reason: str, feet_now) -> None:
        if self.reference is not None:
            self.hold = SafeStance.finishing_step(self.params, self.reference, t)
        else:
            self.hold = SafeStance.standing(self.params, feet_now[0], feet_now[1], t)
        self.hold_reason = reason
        self.events.append(f'holding a stance from t={t:.2f} s: {reason}')
