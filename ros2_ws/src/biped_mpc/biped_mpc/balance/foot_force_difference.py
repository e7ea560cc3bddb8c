"""Foot force difference control: the feet's vertical offset from their normal-force difference."""
from dataclasses import dataclass
import math

import numpy as np

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.validation import check_period, finite_array
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
    swing_return_rate: float = parameter(10.0, 'rate at which a swinging foot\'s offset returns '
                                         'to zero, so that it lands where planned (1/s); 0: '
                                         'it keeps its offset', low=0.0, high=1000.0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


@dataclass(frozen=True)
class FootForceDifferenceResult:
    """Output of one FootForceDifference update.

    :param dz: z_L - z_R offset (m)
    :param offsets: (2,) vertical offsets of the sole targets per side, LEFT then RIGHT; dz is
        their difference, split (+dz/2, -dz/2) while both feet support (m)
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

    A swinging foot's offset returns to zero at swing_return_rate, the supporting foot keeps its
    own: the offset was made for the ground the foot is leaving, and carried into the swing it
    set the next landing dz / 2 off the planned height (2.5 cm at the bound), step after step in
    a fast gait whose short double supports leave large force errors (lipm_walking_controller
    likewise acts in double support only and plans each swing from where the foot is).

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
        self._offsets = np.zeros(2)

    @property
    def dz(self) -> float:
        """The current z_L - z_R offset (m)."""
        return float(self._offsets[LEFT] - self._offsets[RIGHT])

    def reset(self, dz: float = 0.0) -> None:
        """Set the offset.

        :param dz: new z_L - z_R (m), clipped to +-max_offset
        :raises InputError: if it is not finite
        """
        if not (isinstance(dz, (int, float)) and math.isfinite(dz)):
            raise InputError(f'dz must be a finite number (m), got {dz!r}')
        dz = min(max(float(dz), -self.params.max_offset), self.params.max_offset)
        self._offsets = np.zeros(2)
        self._offsets[LEFT], self._offsets[RIGHT] = 0.5 * dz, -0.5 * dz

    def update(self, dt: float, double_support: bool, desired_forces, measured_forces,
               swinging=(False, False)) -> FootForceDifferenceResult:
        """One control cycle.

        :param dt: control period (s), > 0
        :param double_support: both feet are in contact (measured, not only planned)
        :param desired_forces: (2,) desired normal forces, LEFT then RIGHT (N)
        :param measured_forces: (2,) measured normal forces (N)
        :param swinging: (2,) the feet in swing (not supporting in the plan), LEFT then RIGHT
        :return: the offsets
        :raises InputError: for a non-finite or misshaped input or dt <= 0
        """
        check_period(dt)
        desired = finite_array('desired_forces', desired_forces, (2,))
        measured = finite_array('measured_forces', measured_forces, (2,))
        if len(swinging) != 2:
            raise InputError(f'swinging must have one entry per foot, got {swinging!r}')
        p = self.params
        error = 0.0
        if double_support:
            error = float((measured[LEFT] - measured[RIGHT]) - (desired[LEFT] - desired[RIGHT]))
        drive = p.gain * error
        dz_before = self.dz
        if p.leak_rate > 0.0:
            decay = math.exp(-p.leak_rate * dt)
            dz = decay * dz_before + (1.0 - decay) * drive / p.leak_rate
        else:
            dz = dz_before + drive * dt
        dz = min(max(dz, -p.max_offset), p.max_offset)
        swing = [bool(s) for s in swinging]
        if double_support or not any(swing):
            change = 0.5 * (dz - dz_before)  # split between the feet
            self._offsets[LEFT] += change
            self._offsets[RIGHT] -= change
        else:
            # the supporting foot leaks as dz does; a swinging one returns to zero
            returned = math.exp(-p.swing_return_rate * dt)
            leaked = math.exp(-p.leak_rate * dt)
            for side in (LEFT, RIGHT):
                self._offsets[side] *= returned if swing[side] else leaked
        dz = self.dz
        return FootForceDifferenceResult(dz, self._offsets.copy(), error,
                                         abs(dz) >= p.max_offset, bool(double_support))
