"""Contact-aware end of a swing: seek the ground after the planned landing, freeze on contact."""
from dataclasses import dataclass
import math
from typing import Optional

from biped_mpc.errors import ConfigError, InputError
from biped_mpc.validation import check_period
from biped_planner.parameter_fields import parameter, validate_fields

# SupportTimingEvent kinds.
SHRINK = 'shrink'
STRETCH = 'stretch'
RESUME = 'resume'
MISSED = 'missed'
EVENT_KINDS = (SHRINK, STRETCH, RESUME, MISSED)

# SwingLandingResult modes.
SWINGING = 'swinging'
SEEKING = 'seeking'
LANDED = 'landed'
FAILED = 'failed'


@dataclass(frozen=True)
class SupportTimingEvent:
    """A change of the single support's duration for the state machine and the references.

    Kinds:

    - 'shrink': the swing foot touched down at t, before its planned landing time: single
      support ends now, the double support (and the rest of the plan) moves earlier;
    - 'stretch': the planned landing time t passed without contact: single support goes on
      (the reference generator holds its phase) until 'resume' or 'missed';
    - 'resume': the stretched single support ends with the touchdown at t; the plan restarts
      from there, shifted by t minus the planned landing time;
    - 'missed': at t the foot reached its largest extra depth without contact: a failure
      (no ground where the plan expected it), to stop or replan.

    :param kind: one of EVENT_KINDS
    :param t: when it happened (s)
    """

    kind: str
    t: float

    def __post_init__(self) -> None:
        if self.kind not in EVENT_KINDS:
            raise InputError(f'kind must be one of {EVENT_KINDS}, got {self.kind!r}')


@dataclass(frozen=True)
class SwingLandingParams:
    """Descent after the planned landing (see SwingLanding)."""

    descent_speed: float = parameter(0.15, 'speed of the search for the ground after the '
                                     'planned landing (m/s)', low=0.01, high=1.0)
    max_extra_depth: float = parameter(0.06, 'deepest search below the planned landing '
                                       'height (m)', low=0.0, high=0.3)
    max_lead: float = parameter(0.003, 'largest distance the seeking target runs below the '
                                'measured sole (m): a foot the ground holds is not pushed '
                                'into it while the touchdown detector confirms', low=0.0,
                                high=0.3)
    seek: bool = parameter(True, 'descend after the planned landing until contact (false: '
                           'the planned swing to its end, held where the sole touches)')

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)


@dataclass(frozen=True)
class SwingLandingResult:
    """Output of one SwingLanding update.

    :param height: sole height target of the swing foot (m)
    :param mode: 'swinging' (the plan), 'seeking' (descending after the planned landing),
        'landed' (frozen at the contact) or 'failed' (at the largest depth, no contact)
    :param event: the timing event of this update, or None
    :param extra_depth: how far below the planned landing height the target is (m), >= 0
    :param failed: mode == 'failed'
    """

    height: float
    mode: str
    event: Optional[SupportTimingEvent]
    extra_depth: float
    failed: bool


class SwingLanding:
    """The height target of one swing foot near its landing, and the timing events.

    Before the planned landing time t_L the target is the planned swing height, but while the
    sole touches (a normal force the detector has not confirmed yet) at least max_lead below the
    measured sole: a foot meeting a higher tile is not pushed into it by the rest of its planned
    descent, which threw the body up (docs/controller_notes.md, "The landing kick's last part");
    with seek false the same holds after t_L, with no descent and no events of a late landing. A
    touchdown (touchdown_detector) freezes the target at the sole's measured height, where it
    met the ground: before t_L that is an early contact on raised ground, event 'shrink'.
    Without contact at t_L the target keeps descending at the bounded speed v (IHMC 0.12-0.3
    m/s) from where it is, h_k = min(h_planned, h_(k-1) - v dt), down to h_L - d_max, event
    'stretch'; a touchdown then freezes it (event 'resume'); reaching d_max without one is a
    failure (event 'missed') and the target stays there. The descent starts from the planned
    target of the moment, not from h_L: the planned swing reaches the controller through a lag
    and is still millimetres above h_L at t_L, and a target jumping to h_L there hit flat ground
    in one cycle. While seeking, the target stays at most max_lead below the measured sole, h(t)
    >= z_measured - max_lead, and it holds while the sole is touching (a normal force seen
    before the detector confirms it): a free foot follows the descent, a foot the ground already
    holds is not pushed further into it while the detector's filter and dwell confirm the
    contact (without those bounds, on flat ground every landing was seen 1-3 cycles late and the
    stiff leg pushed the robot up by the depth run in that time). A contact on the first update
    at or after t_L, before a 'stretch' was raised, is on time: no event. Call reset at each
    lift-off.
    """

    def __init__(self, params: SwingLandingParams = SwingLandingParams()) -> None:
        """Create the landing logic; call reset before the first swing.

        :param params: descent speed and depth
        """
        self.params = params
        self.reset(math.inf, 0.0)

    def reset(self, landing_time: float, landing_height: float) -> None:
        """Start a swing.

        :param landing_time: planned landing time t_L (s); inf for a swing without one
        :param landing_height: planned landing sole height h_L (m)
        :raises InputError: if the time is NaN or the height not finite
        """
        if math.isnan(landing_time) or not math.isfinite(landing_height):
            raise InputError(f'landing time and height must be numbers, got {landing_time!r} '
                             f'and {landing_height!r}')
        self._landing_time = float(landing_time)
        self._landing_height = float(landing_height)
        self._mode = SWINGING
        self._height = float(landing_height)
        self._stretched = False

    @property
    def mode(self) -> str:
        """SWINGING, SEEKING, LANDED or FAILED (the last update's)."""
        return self._mode

    def retime(self, landing_time: float) -> None:
        """The plan moved the landing time of the swing under way (a step adjustment).

        Taken only while the foot still swings to the planned time: once the target seeks the
        ground or has landed, the events already raised keep their time.

        :param landing_time: the new planned landing time t_L (s)
        :raises InputError: if the time is NaN
        """
        if math.isnan(landing_time):
            raise InputError(f'landing time must be a number, got {landing_time!r}')
        if self._mode == SWINGING and not self._stretched:
            self._landing_time = float(landing_time)

    def update(self, t: float, dt: float, planned_height: float, in_contact: bool,
               measured_height: float, touching: bool = False) -> SwingLandingResult:
        """One control cycle.

        :param t: time (s)
        :param dt: control period (s), > 0: the seeking target descends by descent_speed dt
        :param planned_height: the swing trajectory's sole height at t (m)
        :param in_contact: the touchdown detector's state of this foot
        :param measured_height: the sole's measured height (m)
        :param touching: a normal force on the sole that the detector has not confirmed yet:
            the seeking target holds
        :return: the height target and the timing event, if any
        :raises InputError: for a non-finite input or dt <= 0
        """
        check_period(dt)
        for name, value in (('t', t), ('planned_height', planned_height),
                            ('measured_height', measured_height)):
            if not (isinstance(value, (int, float)) and math.isfinite(value)):
                raise InputError(f'{name} must be a finite number, got {value!r}')
        event = None
        if self._mode in (LANDED, FAILED):
            pass
        elif in_contact:
            self._mode, self._height = LANDED, float(measured_height)
            if t < self._landing_time:
                event = SupportTimingEvent(SHRINK, float(t))
            elif self._stretched:
                event = SupportTimingEvent(RESUME, float(t))
        elif t < self._landing_time or not self.params.seek:
            self._height = float(planned_height)
            if touching:  # early on raised ground: not pushed in while the detector confirms
                self._height = max(self._height, float(measured_height) - self.params.max_lead)
        else:
            p = self.params
            deepest = self._landing_height - p.max_extra_depth
            descended = self._height if touching else min(
                float(planned_height), self._height - p.descent_speed * dt)
            self._mode = SEEKING
            if descended <= deepest:
                descended = deepest
                self._mode = FAILED
                event = SupportTimingEvent(MISSED, float(t))
            elif not self._stretched:
                event = SupportTimingEvent(STRETCH, self._landing_time)
            self._stretched = True
            self._height = max(descended,
                               min(float(measured_height) - p.max_lead, self._height))
        extra = max(self._landing_height - self._height, 0.0) if self._mode != SWINGING else 0.0
        return SwingLandingResult(self._height, self._mode, event, extra,
                                  self._mode == FAILED)
