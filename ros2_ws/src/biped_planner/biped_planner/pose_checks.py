"""Checks of measured poses (odometry, sole poses) before a node believes them.

A pose from another node is rejected when it holds NaN or inf, lies beyond the workspace or
carries an orientation that is not a unit quaternion: a physically impossible reading must not
be taken as true (the previous valid one is kept by the caller).
"""
from dataclasses import dataclass
import math

from biped_planner.errors import ConfigError, InputError
from biped_planner.parameter_fields import parameter, validate_fields


@dataclass(frozen=True)
class PoseBounds:
    """What a measured pose may be (ranges in each parameter())."""

    workspace: float = parameter(1000.0, 'largest |x|, |y|, |z| of a measured pose (m)',
                                 low=1.0, high=1e6)
    quaternion_tolerance: float = parameter(
        0.01, 'largest | |q| - 1 | of a measured orientation quaternion', low=1e-6, high=0.5)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


def check_pose(name: str, position, orientation_xyzw, bounds: PoseBounds) -> None:
    """:param name: what the pose is, for the message (e.g. 'odom')
    :param position: (x, y, z) (m)
    :param orientation_xyzw: quaternion (x, y, z, w)
    :raises InputError: naming the field and its value when the pose is not finite, lies
        beyond bounds.workspace or its quaternion's norm is not 1 within the tolerance
    """
    for axis, value in zip('xyz', position):
        value = float(value)
        if not math.isfinite(value) or abs(value) > bounds.workspace:
            raise InputError(f'{name} position.{axis} {value} outside '
                             f'[-{bounds.workspace}, {bounds.workspace}] m')
    q = tuple(float(v) for v in orientation_xyzw)
    if not all(math.isfinite(v) for v in q):
        raise InputError(f'{name} orientation {q} is not finite')
    norm = math.sqrt(sum(v * v for v in q))
    if abs(norm - 1.0) > bounds.quaternion_tolerance:
        raise InputError(f'{name} orientation is not a unit quaternion: |q| = {norm:.6g}')


class PoseStream:
    """The checks a stream of measured poses (odometry) passes before a node believes it: the
    expected frame, a believable pose (check_pose), stamps that never go back and are not
    ahead of the node's clock, and none from before the last reset.

    :param name: the stream's name, for the messages (e.g. 'odom')
    :param frame: the frame its poses must be in
    """

    def __init__(self, name: str, frame: str) -> None:
        self.name = name
        self.frame = frame
        self.last_stamp = None   # s, of the last accepted pose
        self.reset_stamp = None  # s: poses stamped at or before it predate the reset

    def check(self, frame_id: str, stamp: float, position, orientation_xyzw, now: float,
              bounds: PoseBounds, max_ahead: float) -> None:
        """Accept a pose (its stamp becomes the last one) or refuse it.

        :param now: the node's clock (s); 0 (no clock yet) skips the check against it
        :param max_ahead: how far a stamp may be ahead of now (s)
        :raises InputError: naming what is wrong
        """
        if self.reset_stamp is not None and stamp <= self.reset_stamp:
            raise InputError(f'{self.name} stamp {stamp:.3f} s: measured before the reset at '
                             f'{self.reset_stamp:.3f} s')
        if frame_id != self.frame:
            raise InputError(f'{self.name} frame {frame_id!r}, expected {self.frame!r}')
        check_pose(self.name, position, orientation_xyzw, bounds)
        if self.last_stamp is not None and stamp < self.last_stamp:
            raise InputError(f'{self.name} stamp {stamp:.3f} s before the previous '
                             f'{self.last_stamp:.3f} s')
        if now > 0.0 and stamp > now + max_ahead:
            raise InputError(f'{self.name} stamp {stamp:.3f} s ahead of the clock {now:.3f} s '
                             f'by more than {max_ahead} s')
        self.last_stamp = stamp

    def reset(self, stamp: float) -> None:
        """A reset at clock time stamp: older poses are refused, the stamp order restarts."""
        self.reset_stamp, self.last_stamp = stamp, None

    def since_reset(self, stamp: float) -> float:
        """:return: how long after the last reset a pose was stamped (inf: no reset pending)."""
        return math.inf if self.reset_stamp is None else stamp - self.reset_stamp
