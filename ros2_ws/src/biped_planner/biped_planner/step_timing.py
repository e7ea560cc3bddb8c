"""Step timing: single and double support durations, and their choice from a target speed."""
from dataclasses import dataclass
import math

from biped_planner.errors import ConfigError


def _check_number(owner: str, name: str, value: float, low: float, high: float) -> None:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value) \
            or not low <= value <= high:
        raise ConfigError(f'{owner}.{name} must be a finite number in [{low}, {high}], '
                          f'got {value!r}')


@dataclass(frozen=True)
class StepTiming:
    """Durations of the two phases of one step (the paper's T_ss and T_ds).

    :param single_support: T_ss, one foot on the ground while the other swings (s), [0.05, 5]
    :param double_support: T_ds, both feet on the ground while the ZMP moves to the next
        support foot (s), [0.01, 5]
    """

    single_support: float = 0.4
    double_support: float = 0.1

    def __post_init__(self) -> None:
        _check_number('StepTiming', 'single_support', self.single_support, 0.05, 5.0)
        _check_number('StepTiming', 'double_support', self.double_support, 0.01, 5.0)

    @property
    def step_time(self) -> float:
        """Duration of one step, T_ss + T_ds (s)."""
        return self.single_support + self.double_support


@dataclass(frozen=True)
class StepTimingLimits:
    """Bounds used to choose a step timing from a target walking speed.

    :param min_step_time: shortest step, T_ss + T_ds (s), [0.1, 5]
    :param max_step_time: longest step (s), [min_step_time, 10]
    :param nominal_step_time: step time when the target speed or step is zero (walking in
        place) (s), [min_step_time, max_step_time]
    :param double_support_ratio: T_ds / (T_ss + T_ds), [0.05, 0.8]
    :param min_double_support: shortest double support (s), [0.01, min_step_time / 2]
    """

    min_step_time: float = 0.3
    max_step_time: float = 1.5
    nominal_step_time: float = 0.5
    double_support_ratio: float = 0.2
    min_double_support: float = 0.05

    def __post_init__(self) -> None:
        _check_number('StepTimingLimits', 'min_step_time', self.min_step_time, 0.1, 5.0)
        _check_number('StepTimingLimits', 'max_step_time', self.max_step_time,
                      self.min_step_time, 10.0)
        _check_number('StepTimingLimits', 'nominal_step_time', self.nominal_step_time,
                      self.min_step_time, self.max_step_time)
        _check_number('StepTimingLimits', 'double_support_ratio', self.double_support_ratio,
                      0.05, 0.8)
        _check_number('StepTimingLimits', 'min_double_support', self.min_double_support, 0.01,
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
    for name, value in (('step_length', step_length), ('speed', speed)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            raise ConfigError(f'{name} must be a finite number, got {value!r}')
    if speed < 0.0:
        raise ConfigError(f'speed must be >= 0 m/s, got {speed!r}')
    if speed == 0.0 or step_length == 0.0:
        step_time = limits.nominal_step_time
    else:
        step_time = min(max(abs(step_length) / speed, limits.min_step_time), limits.max_step_time)
    double_support = max(limits.double_support_ratio * step_time, limits.min_double_support)
    return StepTiming(single_support=step_time - double_support, double_support=double_support)
