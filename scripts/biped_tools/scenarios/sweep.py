"""The largest setting that completes: bisection over an ordered grid of candidate values.

Assumes completion is monotone in the setting (a longer step or a larger command scale is never
easier). Every tried value and its outcome is kept, so the table can show the evidence.
"""
from typing import Callable, Dict, List, Optional, Sequence


def largest_completing(values: Sequence[float], completes: Callable[[float], bool],
                       first: Optional[float] = None) -> tuple:
    """Bisection for the last value of the ascending grid `values` that completes.

    :param values: ascending candidates
    :param completes: runs one trial, True when it completes
    :param first: value to try first (e.g. the paper's nominal setting); default the middle
    :return: (largest completing value or None when even the smallest fails,
              {value: completed} of every trial run)
    """
    values = list(values)
    if values != sorted(values) or not values:
        raise ValueError('values must be a non-empty ascending sequence')
    tried: Dict[float, bool] = {}
    low, high = -1, len(values)        # invariant: values[low] completes, values[high] fails
    probe = values.index(first) if first in values else (len(values) - 1) // 2
    while high - low > 1:
        tried[values[probe]] = completes(values[probe])
        if tried[values[probe]]:
            low = probe
        else:
            high = probe
        probe = (low + high) // 2 if high - low > 1 else probe
    return (values[low] if low >= 0 else None), tried


def grid(start: float, stop: float, step: float) -> List[float]:
    """start, start + step, ... up to stop inclusive, rounded to the step's decimals."""
    count = int(round((stop - start) / step)) + 1
    decimals = max(0, len(f'{step:.10f}'.rstrip('0').split('.')[1]))
    return [round(start + k * step, decimals) for k in range(count)]
