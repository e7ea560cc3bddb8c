"""Landings off the plan's time: the single support lasts until the swing foot meets the ground.

The controller lowers a swing foot that reaches its planned landing time without contact
(biped_mpc.balance.swing_landing, 'seeking') and reports its landing state every period; this
holds the plan's single support meanwhile (WalkingReference.hold_landing), so that the ZMP
stays on the stance foot, the double support and every later phase wait, and the reference,
the state machine and the MPC agree on the new timing. The touchdown ends the hold. A foot
that meets the ground before its planned time (raised ground: the controller stops it there,
'landed') ends the single support at once (WalkingReference.adjust_step to the same
footsteps), so the double support starts early.
"""
from dataclasses import dataclass
from typing import Optional, Sequence

from biped_planner.errors import ConfigError, InputError
from biped_planner.parameter_fields import parameter, validate_fields
from biped_planner.reference_phases import PHASE_SINGLE_SUPPORT
from biped_planner.step_timing import MIN_SINGLE_SUPPORT

# The controller's landing states of the swing foot (biped_mpc.balance.swing_landing modes).
LANDING_NONE = 'none'          # no swing under way
LANDING_SWINGING = 'swinging'  # before its planned landing time
LANDING_SEEKING = 'seeking'    # past it without contact: the foot descends to find the ground
LANDING_LANDED = 'landed'      # it met the ground
LANDING_FAILED = 'failed'      # no ground down to the deepest search
LANDING_STATES = (LANDING_NONE, LANDING_SWINGING, LANDING_SEEKING, LANDING_LANDED,
                  LANDING_FAILED)

HOLD = 'hold'
RESUME = 'resume'
EARLY = 'early'
# s from the report of the touchdown to the end of the hold: the next period's reference is
# already in the double support
RESUME_LEAD = 1e-3
MAX_LANDING_DEPTH = 1.0  # m: a reported search deeper than this is not a foot's


@dataclass(frozen=True)
class LandingHoldParams:
    """When the plan waits for a late landing."""

    enabled: bool = parameter(False, 'hold the single support of a swing foot that reaches '
                              'its planned landing time without contact, until it touches down')
    hold_time: float = parameter(
        0.2, 'longest wait past the planned landing time (s): the double support then starts '
        'as planned (at 0.15 m/s the foot searches 30 mm below its landing in 0.2 s)',
        low=0.0, high=1.0)
    min_depth: float = parameter(
        0.005, 'how far below its planned landing height the late foot must search before the '
        'plan holds (m): on flat ground the lagging swing target is still millimetres above the '
        'ground at the planned landing time and every landing came 40-80 ms late, each held',
        low=0.0, high=0.3)
    end_early: bool = parameter(
        False, 'end the single support when the swing foot meets the ground before its planned '
        'landing time: the double support and every later phase start early')
    early_lead: float = parameter(
        0.02, 'how long before its planned landing time a touchdown must come to end the single '
        'support early (s): one nearer is on time', low=0.0, high=1.0)
    early_min_share: float = parameter(
        0.5, 'share of the swing that must have passed before a landing ends it early: the '
        'controller\'s touchdown gate refuses contacts before its own share (gate_phase 0.5)',
        low=0.0, high=1.0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)

    @property
    def answers_landings(self) -> bool:
        """The plan follows the controller's landing reports (a hold or an early end is on)."""
        return self.enabled or self.end_early


@dataclass(frozen=True)
class LandingHoldChange:
    """A hold begun or ended.

    :param kind: HOLD (the single support waits), RESUME (the foot is down: it ends now) or
        EARLY (the foot met the ground before its planned time: it ends now)
    :param reference: the retimed WalkingReference
    :param step: the step whose touchdown moved (it lands footsteps[step + 2])
    :param touchdown: its new touchdown time (s)
    :param planned_touchdown: its touchdown before the change (s)
    """

    kind: str
    reference: object
    step: int
    touchdown: float
    planned_touchdown: float


class LandingHold:
    """Holds the single support of a late swing until the controller reports its touchdown.

    Each period, with the swing foot's landing state of that period: a foot 'seeking' past
    its planned landing time t_L, its target min_depth or more below the planned landing
    height (and no hold yet), holds the single support until t_L + hold_time; in a hold, any
    other state (landed; failed; the swing lost) ends it now.
    A hold that runs out lets the plan go on. With end_early, a foot 'landed' more than
    early_lead before t_L, and once early_min_share of its swing has passed, ends the single
    support now. Nothing else changes the plan: the footsteps, and a landing that comes on
    time, are the plan's.

    :param params: when to hold
    """

    def __init__(self, params: LandingHoldParams = LandingHoldParams()) -> None:
        self.params = params

    def update(self, t: float, reference, modes: Sequence[str],
               depths: Sequence[float] = (0.0, 0.0),
               hip: Optional[Sequence[float]] = None,
               dcm: Optional[Sequence[float]] = None) -> Optional[LandingHoldChange]:
        """One period.

        :param t: time of the landing report (s)
        :param reference: the WalkingReference walked, None when no walk is under way
        :param modes: (left, right) landing states of the feet (LANDING_STATES); the swing
            foot's is answered
        :param depths: (left, right) how far below its planned landing height a seeking
            foot's target is (m)
        :param hip: (2,) estimated hip (COM) at t (m) to replan from, None for the plan's
        :param dcm: (2,) estimated DCM at t (m), with hip
        :return: the change, or None (off, no late swing, nothing to change)
        :raises InputError: for a report that is not two known states and two depths finite
            and in [0, MAX_LANDING_DEPTH] (checked whether or not the hold is on)
        """
        modes, depths = tuple(modes), tuple(depths)
        if len(modes) != 2 or len(depths) != 2:
            raise InputError(f'landing modes and depths must be (left, right), got {modes} and '
                             f'{depths}')
        if not all(mode in LANDING_STATES for mode in modes):
            raise InputError(f'landing modes must be in {LANDING_STATES}, got {modes}')
        if not all(isinstance(d, (int, float)) and 0.0 <= d <= MAX_LANDING_DEPTH
                   for d in depths):
            raise InputError(f'landing depths {depths} must be finite and in [0, '
                             f'{MAX_LANDING_DEPTH}] m')
        if reference is None or not self.params.answers_landings:
            return None
        swing = reference.swing_of_late_landing(t)
        if swing is None:
            return None
        phases = reference.phases
        phase = phases[swing]
        step = phase.step_index - 1
        landing, depth = modes[phase.swing_side], float(depths[phase.swing_side])
        held = swing + 1 < len(phases) and phases[swing + 1].kind == PHASE_SINGLE_SUPPORT \
            and phases[swing + 1].step_index == phase.step_index
        if not held and landing == LANDING_LANDED and self.params.end_early:
            touchdown = t + RESUME_LEAD
            shortest = max(self.params.early_min_share * (phase.t_end - phase.t_begin),
                           MIN_SINGLE_SUPPORT)
            if touchdown + self.params.early_lead > phase.t_end or \
                    touchdown - phase.t_begin < shortest:
                return None
            early = reference.adjust_step(t, reference.footsteps[step + 2:], touchdown, hip, dcm)
            return LandingHoldChange(EARLY, early, step, touchdown, phase.t_end)
        if not self.params.enabled:
            return None
        if not held:
            touchdown = phase.t_end + self.params.hold_time
            if landing != LANDING_SEEKING or depth < self.params.min_depth or \
                    t < phase.t_end or touchdown <= t:
                return None
            return LandingHoldChange(HOLD, reference.hold_landing(t, touchdown, hip, dcm), step,
                                     touchdown, phase.t_end)
        hold_end = phases[swing + 1].t_end
        if landing == LANDING_SEEKING or t + RESUME_LEAD >= hold_end:
            return None
        touchdown = t + RESUME_LEAD
        return LandingHoldChange(RESUME, reference.hold_landing(t, touchdown, hip, dcm), step,
                                 touchdown, hold_end)
