"""Step timing: single and double support durations, and their choice from a target speed."""
from dataclasses import dataclass

from biped_planner.errors import ConfigError
from biped_planner.input_checks import check_number
from biped_planner.parameter_fields import parameter, validate_fields

MIN_SINGLE_SUPPORT = 0.05  # s: the shortest T_ss a step may have

@dataclass(frozen=True)
class StepTiming:
    """Durations of the two phases of one step (the paper's T_ss and T_ds)."""

    single_support: float = parameter(
        0.4, 'T_ss: one foot on the ground while the other swings (s)',
        low=MIN_SINGLE_SUPPORT, high=5.0)
    double_support: float = parameter(
        0.1, 'T_ds: both feet on the ground while the ZMP moves to the next support foot (s)',
        low=0.01, high=5.0)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)

    @property
    def step_time(self) -> float:
        """Duration of one step, T_ss + T_ds (s)."""
        return self.single_support + self.double_support


@dataclass(frozen=True)
class StepTimingLimits:
    """Bounds used to choose a step timing from a target walking speed.

    Besides each field's own range: min_step_time <= nominal_step_time <= max_step_time and
    min_double_support <= min_step_time / 2.
    """

    min_step_time: float = parameter(0.3, 'shortest step, T_ss + T_ds (s)', low=0.1, high=5.0)
    max_step_time: float = parameter(1.5, 'longest step, at least min_step_time (s)',
                                     low=0.1, high=10.0)
    nominal_step_time: float = parameter(
        0.5, 'step time when the target speed or step is zero (walking in place) (s)',
        low=0.1, high=10.0)
    double_support_ratio: float = parameter(0.2, 'T_ds / (T_ss + T_ds)', low=0.05, high=0.8)
    min_double_support: float = parameter(0.05, 'shortest double support (s)',
                                          low=0.01, high=2.5)

    def __post_init__(self) -> None:
        validate_fields(self, ConfigError)
        check_number('StepTimingLimits.max_step_time', self.max_step_time,
                     self.min_step_time, 10.0)
        check_number('StepTimingLimits.nominal_step_time', self.nominal_step_time,
                     self.min_step_time, self.max_step_time)
        check_number('StepTimingLimits.min_double_support', self.min_double_support, 0.01,
                     0.5 * self.min_step_time)


def timing_for_speed(step_length: float, speed: float,
                     limits: StepTimingLimits = StepTimingLimits()) -> StepTiming:
    """Choose the step timing that walks step_length per step at the target speed, within limits.

    step_time = clip(|step_length| / speed, min_step_time, max_step_time) (nominal_step_time when
    the step or the speed is zero); T_ds = max(ratio * step_time, min_double_support),
    T_ss = step_time - T_ds.

    :param step_length: distance between consecutive footsteps (m), finite
    :param speed: target walking speed (m/s), >= 0 and finite
    :param limits: the bounds
    :return: the step timing
    :raises ConfigError: if step_length or speed is not finite, or speed < 0
    """
    check_number('step_length', step_length)
    check_number('speed', speed, low=0.0, unit=' m/s')
    if speed == 0.0 or step_length == 0.0:
        step_time = limits.nominal_step_time
    else:
        step_time = min(max(abs(step_length) / speed, limits.min_step_time), limits.max_step_time)
    double_support = max(limits.double_support_ratio * step_time, limits.min_double_support)
    return StepTiming(single_support=step_time - double_support, double_support=double_support)
