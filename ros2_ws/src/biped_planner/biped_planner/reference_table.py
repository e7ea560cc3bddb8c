"""Fast sampling of a walking reference: one table row per ZMP segment, evaluated in bulk.

Each row holds everything a sample time in that segment needs: the segment's LIPM terms (start,
span, ZMP and its slope, the stable and unstable coefficients of biped_planner.lipm_trajectory)
and its phase's feet, swing height, ZMP box, landing boxes, support and step index. Sampling N
times is one search of the knot times, one gather of rows and column arithmetic: the hip of
PiecewiseLipm.evaluate, x = p + A exp(-omega tau) + B exp(-omega (span - tau)), the swing feet of
biped_planner.swing_trajectory and the leg masses midway between each sole centre and the hip.
"""
import numpy as np

from biped_planner.lipm_trajectory import PiecewiseLipm
from biped_planner.reference_phases import PhaseTable
from biped_planner.reference_window import ReferenceWindow
from biped_planner.swing_trajectory import swing_lift, swing_progress

_PRECOMPUTED_SAMPLES = 1024
_TABLE_WIDTHS = (('_T0', 1), ('_SPAN', 1), ('_ZMP', 2), ('_SLOPE', 2), ('_STABLE', 2),
                 ('_UNSTABLE', 2), ('_PHASE_T0', 1), ('_PHASE_RATE', 1), ('_FEET_START', 6),
                 ('_FEET_DELTA', 6), ('_FEET_HEIGHT', 2), ('_ZMP_MIN', 2), ('_ZMP_MAX', 2),
                 ('_LEFT_LANDING_MIN', 2), ('_LEFT_LANDING_MAX', 2), ('_RIGHT_LANDING_MIN', 2),
                 ('_RIGHT_LANDING_MAX', 2), ('_SUPPORT', 1), ('_STEP', 1))


def _table_columns() -> dict:
    columns = {}
    first = 0
    for name, width in _TABLE_WIDTHS:
        columns[name] = first if width == 1 else slice(first, first + width)
        first += width
    return columns


_COLUMNS = _table_columns()
_T0, _SPAN, _ZMP, _SLOPE = (_COLUMNS[n] for n in ('_T0', '_SPAN', '_ZMP', '_SLOPE'))
_STABLE, _UNSTABLE = _COLUMNS['_STABLE'], _COLUMNS['_UNSTABLE']
_PHASE_T0, _PHASE_RATE = _COLUMNS['_PHASE_T0'], _COLUMNS['_PHASE_RATE']
_FEET_START, _FEET_DELTA = _COLUMNS['_FEET_START'], _COLUMNS['_FEET_DELTA']
_FEET_HEIGHT, _ZMP_MIN, _ZMP_MAX = (_COLUMNS[n] for n in ('_FEET_HEIGHT', '_ZMP_MIN',
                                                          '_ZMP_MAX'))
_LEFT_LANDING_MIN, _LEFT_LANDING_MAX = (_COLUMNS['_LEFT_LANDING_MIN'],
                                        _COLUMNS['_LEFT_LANDING_MAX'])
_RIGHT_LANDING_MIN, _RIGHT_LANDING_MAX = (_COLUMNS['_RIGHT_LANDING_MIN'],
                                          _COLUMNS['_RIGHT_LANDING_MAX'])
_SUPPORT, _STEP = _COLUMNS['_SUPPORT'], _COLUMNS['_STEP']
_RAMP = np.arange(_PRECOMPUTED_SAMPLES, dtype=float)


class ReferenceTable:
    """The per-segment table of a hip trajectory and its phases."""

    def __init__(self, lipm: PiecewiseLipm, phases: PhaseTable) -> None:
        """Build one row per ZMP segment.

        :param lipm: the hip trajectory (its knots are the segment boundaries)
        :param phases: the phases, each segment belonging to the phase it starts in
        """
        knots = lipm.times
        segment_phase = np.searchsorted(phases.t0, knots[:-1], side='right') - 1
        np.clip(segment_phase, 0, phases.t0.size - 1, out=segment_phase)
        columns = [knots[:-1, None], lipm.span[:, None], lipm.zmp[:-1], lipm.slope,
                   lipm.coef_stable, lipm.coef_unstable, phases.t0[segment_phase, None],
                   phases.rate[segment_phase, None], phases.feet_start[segment_phase],
                   phases.feet_delta[segment_phase], phases.feet_height[segment_phase],
                   phases.zmp_min[segment_phase], phases.zmp_max[segment_phase],
                   phases.landing[segment_phase], phases.support[segment_phase, None],
                   phases.step_index[segment_phase, None]]
        self._table = np.hstack([np.asarray(column, dtype=float) for column in columns])
        self._knot_times = knots
        self._segment_count = knots.size - 1
        self._omega = lipm.omega

    def sample(self, t0: float, n: int, dt: float) -> ReferenceWindow:
        """References at t0, t0 + dt, ..., t0 + (n - 1) dt (arguments checked by the caller).

        Times before the first knot or after the last one hold the end values.
        """
        ramp = _RAMP[:n] if n <= _PRECOMPUTED_SAMPLES else np.arange(n, dtype=float)
        t = t0 + dt * ramp
        j = np.searchsorted(self._knot_times, t, side='right') - 1
        np.clip(j, 0, self._segment_count - 1, out=j)
        row = self._table[j]
        tau = np.minimum(np.maximum(t - row[:, _T0], 0.0), row[:, _SPAN])
        zmp = row[:, _ZMP] + row[:, _SLOPE] * tau[:, None]
        omega = self._omega
        stable = np.exp(-omega * tau)
        unstable = np.exp(omega * (tau - row[:, _SPAN]))
        hip = zmp + row[:, _STABLE] * stable[:, None] + row[:, _UNSTABLE] * unstable[:, None]
        s = (t - row[:, _PHASE_T0]) * row[:, _PHASE_RATE]
        np.clip(s, 0.0, 1.0, out=s)
        feet = row[:, _FEET_START] + row[:, _FEET_DELTA] * swing_progress(s)[:, None]
        lift = row[:, _FEET_HEIGHT] * swing_lift(s)[:, None]
        left_foot = np.empty((n, 3))
        left_foot[:, :2] = feet[:, 0:2]
        left_foot[:, 2] = lift[:, 0]
        right_foot = np.empty((n, 3))
        right_foot[:, :2] = feet[:, 3:5]
        right_foot[:, 2] = lift[:, 1]
        return ReferenceWindow(
            t=t, zmp=zmp, hip=hip, left_foot=left_foot, right_foot=right_foot,
            left_yaw=feet[:, 2], right_yaw=feet[:, 5],
            left_mass=0.5 * (feet[:, 0:2] + hip), right_mass=0.5 * (feet[:, 3:5] + hip),
            zmp_min=row[:, _ZMP_MIN], zmp_max=row[:, _ZMP_MAX],
            left_landing_min=row[:, _LEFT_LANDING_MIN], left_landing_max=row[:, _LEFT_LANDING_MAX],
            right_landing_min=row[:, _RIGHT_LANDING_MIN],
            right_landing_max=row[:, _RIGHT_LANDING_MAX],
            support=row[:, _SUPPORT].astype(np.uint8), step_index=row[:, _STEP].astype(np.int64))
