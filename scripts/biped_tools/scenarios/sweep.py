"""The largest setting that completes: bisection over an ordered grid of candidate values,
then the limit confirmed by repeats.

Assumes completion is monotone in the setting (a longer step or a larger command scale is never
easier). Every trial and its outcome is kept, so the table can show the evidence. A limit from
single trials can move between runs (a trial near it may pass once and fail once), so the limit
and the setting above it are each run `repeats` times and judged by the median outcome.
"""
from typing import Callable, Dict, List, Optional, Sequence


def check_repeats(repeats: int) -> int:
    """:return: repeats, an odd number >= 1 (a median of runs); :raises ValueError: else"""
    if repeats < 1 or repeats % 2 == 0:
        raise ValueError(f'repeats must be odd and >= 1 (a median), got {repeats}')
    return repeats


def median_run(runs: Sequence[dict], key: str) -> dict:
    """The run with the median runs[i][key], the lower one of an even count (a limit is not
    rounded up)."""
    return sorted(runs, key=lambda r: r[key])[(len(runs) - 1) // 2]


def largest_completing(values: Sequence[float], completes: Callable[[float, int], bool],
                       first: Optional[float] = None, repeats: int = 1) -> tuple:
    """Bisection for the last value of the ascending grid `values` that completes.

    With repeats > 1, the value found and the one above it are then run until each has
    `repeats` outcomes; a limit whose median outcome is a failure moves one value down, a value
    above it whose median completes moves the limit up, until both hold.

    :param values: ascending candidates
    :param completes: completes(value, run) runs one trial (run = 0, 1, ... of that value),
        True when it completes
    :param first: value to try first (e.g. the paper's nominal setting); default the middle
    :param repeats: odd number of runs at the limit and above it (1: the bisection's only)
    :return: (largest completing value or None when even the smallest fails,
              {value: [outcome of each run, in order]} of every trial run)
    """
    values = list(values)
    if values != sorted(values) or not values:
        raise ValueError('values must be a non-empty ascending sequence')
    check_repeats(repeats)
    tried: Dict[float, List[bool]] = {}

    def run(index: int) -> List[bool]:
        outcomes = tried.setdefault(values[index], [])
        outcomes.append(bool(completes(values[index], len(outcomes))))
        return outcomes

    low, high = -1, len(values)        # invariant: values[low] completes, values[high] fails
    probe = values.index(first) if first in values else (len(values) - 1) // 2
    while high - low > 1:
        if run(probe)[0]:
            low = probe
        else:
            high = probe
        probe = (low + high) // 2 if high - low > 1 else probe
    if repeats == 1:
        return (values[low] if low >= 0 else None), tried

    def median(index: int) -> bool:
        while len(tried.get(values[index], ())) < repeats:
            run(index)
        return 2 * sum(tried[values[index]]) > len(tried[values[index]])

    while True:  # ends: a value's median is fixed once run, so low never returns
        if low >= 0 and not median(low):
            low -= 1
        elif low + 1 < len(values) and median(low + 1):
            low += 1
        else:
            return (values[low] if low >= 0 else None), tried


def run_name(setting: str, run: int) -> str:
    """A trial's name for run `run` of a setting: the first keeps the setting's own name."""
    return setting if run == 0 else f'{setting}_run{run + 1}'


def grid(start: float, stop: float, step: float) -> List[float]:
    """start, start + step, ... up to stop inclusive, rounded to the step's decimals."""
    count = int(round((stop - start) / step)) + 1
    decimals = max(0, len(f'{step:.10f}'.rstrip('0').split('.')[1]))
    return [round(start + k * step, decimals) for k in range(count)]
