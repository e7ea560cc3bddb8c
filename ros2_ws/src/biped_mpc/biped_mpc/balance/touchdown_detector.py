"""Touchdown and liftoff of one foot: force hysteresis, dwell time and swing-phase gating."""
from dataclasses import dataclass
import enum
import math
from typing import Optional

from biped_mpc.errors import ConfigError, InputError
from biped_planner.parameter_fields import parameter, validate_fields

# A dwell is complete when the condition has held this much less than dwell_time, so that
# samples on a grid of the dwell time are not lost to rounding.
_TIME_EPSILON = 1e-9


class ContactEvent(enum.IntEnum):
    """What changed in one update."""

    NONE = 0
    TOUCHDOWN = 1
    LIFTOFF = 2


@dataclass(frozen=True)
class TouchdownParams:
    """Thresholds and gates of the contact detection (see TouchdownDetector)."""

    on_force: float = parameter(50.0, 'normal force above which a foot touches (N)', low=0.0,
                                high=5000.0, low_open=True)
    off_force: float = parameter(25.0, 'normal force below which a foot has lifted (N)',
                                 low=0.0, high=5000.0)
    dwell_time: float = parameter(0.01, 'time a crossing must hold to count (s)', low=0.0,
                                  high=1.0)
    gate_phase: float = parameter(0.5, 'share of the swing after which a touchdown is '
                                  'accepted (1)', low=0.0, high=1.0)
    gate_distance: float = parameter(0.05, 'largest distance of the foot from its landing '
                                     'target for a touchdown (m)', low=0.0, high=1.0,
                                     low_open=True)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        if self.off_force >= self.on_force:
            raise ConfigError(f'TouchdownParams.off_force must be below on_force = '
                              f'{self.on_force!r} N, got {self.off_force!r}')


@dataclass(frozen=True)
class ContactState:
    """One foot's contact after an update.

    :param in_contact: the foot supports
    :param event: TOUCHDOWN or LIFTOFF when the state changed in this update, else NONE
    :param event_time: when the crossing that caused the event began (s): the touchdown or
        liftoff instant, dwell_time or less before the update that reports it; NaN with NONE
    :param normal_force: the normal force of the update (N)
    :param gated: the force was above on_force but the swing gate refused it
    :param pending: a crossing is holding and waiting for its dwell time
    """

    in_contact: bool
    event: ContactEvent
    event_time: float
    normal_force: float
    gated: bool
    pending: bool


class TouchdownDetector:
    """Contact state of one foot from its normal force, robust to impacts and inertia.

    Input: the normal ground force with the foot's own weight and inertia removed
    (ft_filter.compensate_foot_inertia: the raw ankle reading of our robot shows 38 N with the
    foot in the air). Hysteresis: off -> on above on_force, on -> off below off_force
    (iCub: 150 / 120 N). Dwell: the crossing must hold for dwell_time (10 ms on iCub), which
    rejects impact spikes and the chatter of a bouncing sole. Gate while the plan says the
    foot swings: a touchdown is accepted only from gate_phase of the swing on (HRP-4: after the
    first third of single support; BaselineWalkingController: the last 0.2 s) and within
    gate_distance of the landing target (3 cm, 5 cm there). After the planned landing time
    the phase stays at 1 and late contacts pass. A foot the plan does not swing (phase None)
    is not gated. Liftoff is never gated.
    """

    def __init__(self, params: TouchdownParams = TouchdownParams(),
                 in_contact: bool = True) -> None:
        """Create the detector.

        :param params: thresholds and gates
        :param in_contact: the initial state (standing: True)
        """
        self.params = params
        self.reset(in_contact)

    @property
    def in_contact(self) -> bool:
        """The current contact state."""
        return self._contact

    def reset(self, in_contact: bool = True) -> None:
        """Set the state and forget any crossing in progress.

        :param in_contact: the new state
        """
        self._contact = bool(in_contact)
        self._since: Optional[float] = None
        self._last_time = -math.inf

    def update(self, t: float, normal_force: float, swing_phase: Optional[float] = None,
               distance_to_target: Optional[float] = None) -> ContactState:
        """Process one sample.

        :param t: time of the sample (s), not before the previous one
        :param normal_force: compensated normal ground force (N)
        :param swing_phase: elapsed share of the planned swing, [0, 1] (1 after the planned
            landing); None when the plan has the foot in support
        :param distance_to_target: distance of the sole from its landing target (m); None to
            skip the distance gate
        :return: the contact state and the event of this sample
        :raises InputError: for a non-finite value or a time going backwards
        """
        for name, value in (('t', t), ('normal_force', normal_force)):
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise InputError(f'{name} must be a finite number, got {value!r}')
        if t < self._last_time:
            raise InputError(f't must not go backwards: {t!r} s after {self._last_time!r} s')
        self._last_time = t
        p = self.params
        gate_open = True
        if swing_phase is not None:
            if not (isinstance(swing_phase, (int, float)) and math.isfinite(swing_phase)):
                raise InputError(f'swing_phase must be a finite number, got {swing_phase!r}')
            gate_open = swing_phase >= p.gate_phase
        if distance_to_target is not None:
            if not (isinstance(distance_to_target, (int, float))
                    and math.isfinite(distance_to_target)):
                raise InputError(f'distance_to_target must be a finite number, got '
                                 f'{distance_to_target!r}')
            gate_open = gate_open and distance_to_target <= p.gate_distance
        gated = False
        if self._contact:
            crossing = normal_force < p.off_force
        else:
            high = normal_force >= p.on_force
            gated = high and not gate_open
            crossing = high and gate_open
        if not crossing:
            self._since = None
            return ContactState(self._contact, ContactEvent.NONE, math.nan, float(normal_force),
                                gated, False)
        if self._since is None:
            self._since = float(t)
        if t - self._since < p.dwell_time - _TIME_EPSILON:
            return ContactState(self._contact, ContactEvent.NONE, math.nan, float(normal_force),
                                False, True)
        self._contact = not self._contact
        event_time, self._since = self._since, None
        event = ContactEvent.TOUCHDOWN if self._contact else ContactEvent.LIFTOFF
        return ContactState(self._contact, event, event_time, float(normal_force), False, False)
