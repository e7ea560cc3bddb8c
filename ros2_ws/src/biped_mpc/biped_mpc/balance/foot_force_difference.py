"""Foot force difference control: the feet's vertical offset from their normal-force difference."""
from dataclasses import dataclass
import math

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.validation import finite_array
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.sides import LEFT, RIGHT


@dataclass(frozen=True)
class FootForceDifferenceParams:
    """Gain and limits of the foot force difference control (see FootForceDifference)."""

    gain: float = parameter(1e-4, 'admittance K_f of the force difference (m/(N s))', low=0.0,
                            high=0.01)
    leak_rate: float = parameter(0.1, 'leak 1 / T_damp pulling dz back to zero (1/s); '
                                 '0: none', low=0.0, high=100.0)
    max_offset: float = parameter(0.05, 'largest |dz| = |z_L - z_R| (m)', low=0.0, high=0.3)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


@dataclass(frozen=True)
class FootForceDifferenceResult:
    """Output of one FootForceDifference update.

    :param dz: z_L - z_R offset (m)
    :param offsets: (2,) vertical offsets of the sole targets per side, (+dz/2, -dz/2) (m)
    :param error: (f_L - f_R) - (f_L_des - f_R_des) (N); zero outside double support
    :param limited: True when dz sits at +-max_offset
    :param active: True when the force term acted (double support)
    """

    dz: float
    offsets: np.ndarray
    error: float
    limited: bool
    active: bool


class FootForceDifference:
    """Vertical offset between the feet that makes them share the load as desired.

    Kajita 2010, "foot force difference control": with dz = z_L - z_R the offset of the left
    sole target above the right one (added as +dz/2 and -dz/2),

        dz_dot = K_f ((f_L - f_R) - (f_L_des - f_R_des)) - dz / T_damp

    in double support, f the normal forces. Sign: a left foot carrying more than its share
    (f_L - f_R above its target) is lifted relative to the right one, which unloads it; the
    paper and lipm_walking_controller write the same law for z_R - z_L with the error
    (f_L_des - f_R_des) - (f_L - f_R). Outside double support only the leak acts, so dz
    relaxes with T_damp and never jumps. |dz| <= max_offset.

    Two feet on tiles whose heights differ by dh, pressed by a contact (leg + ground) stiffness
    k each, give f_L - f_R = k (dh - dz): dz converges to dh K_f k / (K_f k + 1 / T_damp) with
    the rate K_f k + 1 / T_damp, leaving (1 / T_damp) dz / K_f of force difference. Stability
    of the sampled loop needs K_f k dt < 1 (K_f = 1e-4 m/(N s), dt = 0.02 s: k < 5e5 N/m).
    Discretisation: exact for the error held over dt.
    """

    def __init__(self, params: FootForceDifferenceParams = FootForceDifferenceParams()) -> None:
        """Create the control with dz = 0.

        :param params: gain and limits
        """
        self.params = params
        self._dz = 0.0

    @property
    def dz(self) -> float:
        """The current z_L - z_R offset (m)."""
        return self._dz

    def reset(self, dz: float = 0.0) -> None:
        """Set the offset.

        :param dz: new z_L - z_R (m), clipped to +-max_offset
        :raises InputError: if it is not finite
        """
        if not (isinstance(dz, (int, float)) and math.isfinite(dz)):
            raise InputError(f'dz must be a finite number (m), got {dz!r}')
        self._dz = min(max(float(dz), -self.params.max_offset), self.params.max_offset)

    def update(self, dt: float, double_support: bool, desired_forces,
               measured_forces) -> FootForceDifferenceResult:
        """One control cycle.

        :param dt: control period (s), > 0
        :param double_support: both feet are in contact (measured, not only planned)
        :param desired_forces: (2,) desired normal forces, LEFT then RIGHT (N)
        :param measured_forces: (2,) measured normal forces (N)
        :return: the offsets
        :raises InputError: for a non-finite or misshaped input or dt <= 0
        """
        if not (isinstance(dt, (int, float)) and math.isfinite(dt) and dt > 0.0):
            raise InputError(f'dt must be a finite number > 0 s, got {dt!r}')
        desired = finite_array('desired_forces', desired_forces, (2,))
        measured = finite_array('measured_forces', measured_forces, (2,))
        p = self.params
        error = 0.0
        if double_support:
            error = float((measured[LEFT] - measured[RIGHT]) - (desired[LEFT] - desired[RIGHT]))
        drive = p.gain * error
        if p.leak_rate > 0.0:
            decay = math.exp(-p.leak_rate * dt)
            dz = decay * self._dz + (1.0 - decay) * drive / p.leak_rate
        else:
            dz = self._dz + drive * dt
        self._dz = min(max(dz, -p.max_offset), p.max_offset)
        offsets = np.zeros(2)
        offsets[LEFT], offsets[RIGHT] = 0.5 * self._dz, -0.5 * self._dz
        return FootForceDifferenceResult(self._dz, offsets, error,
                                         abs(self._dz) >= p.max_offset, bool(double_support))
