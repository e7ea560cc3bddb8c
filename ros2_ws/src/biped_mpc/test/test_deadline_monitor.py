import math

import numpy as np
import pytest

from biped_mpc.deadline_monitor import DeadlineMonitor
from biped_mpc.errors import ConfigError


def test_late_periods_are_those_over_the_deadline():
    monitor = DeadlineMonitor(0.002)
    flags = [monitor.record(x) for x in (0.001, 0.002, 0.0021, 0.010, 0.0005)]
    assert flags == [False, False, True, True, False]
    report = monitor.report()
    assert (report.periods, report.late) == (5, 2)
    assert report.late_per_10000 == pytest.approx(4000.0)


def test_quantiles_match_numpy_over_the_window_only():
    rng = np.random.default_rng(3)
    old = rng.uniform(0.5, 1.0, 500)      # start-up: slow, out of the window by the end
    recent = rng.exponential(0.001, 1000)
    monitor = DeadlineMonitor(0.02, window=1000)
    for x in np.concatenate([old, recent]):
        monitor.record(float(x))
    report = monitor.report()
    assert report.p50 == pytest.approx(np.percentile(recent, 50), rel=1e-12)
    assert report.p99 == pytest.approx(np.percentile(recent, 99), rel=1e-12)
    assert report.max == pytest.approx(recent.max())
    assert report.periods == 1500 and report.late == 500  # the count is over the whole run


def test_a_latency_that_is_not_a_number_counts_as_late():
    monitor = DeadlineMonitor(0.02)
    assert monitor.record(math.nan) and monitor.record(-0.001)
    assert not monitor.record(0.001)
    report = monitor.report()
    assert (report.periods, report.late) == (3, 2)
    assert report.max == pytest.approx(0.001)


def test_no_period_yet_reports_nan_quantiles_and_no_misses():
    report = DeadlineMonitor(0.02).report()
    assert report.periods == 0 and report.late_per_10000 == 0.0 and math.isnan(report.p99)


@pytest.mark.parametrize('deadline, window', [(0.0, 10), (math.inf, 10), (0.02, 0), (0.02, 1.5)])
def test_bad_settings_are_refused(deadline, window):
    with pytest.raises(ConfigError):
        DeadlineMonitor(deadline, window)


def test_quantiles_follow_a_small_window_with_repeated_values():
    rng = np.random.default_rng(5)
    values = rng.integers(0, 4, 60) * 0.001   # many equal latencies leave and enter
    monitor = DeadlineMonitor(0.02, window=7)
    for k, x in enumerate(values):
        monitor.record(float(x))
        window = values[max(0, k - 6):k + 1]
        report = monitor.report()
        assert report.p50 == pytest.approx(np.percentile(window, 50), abs=1e-15)
        assert report.p99 == pytest.approx(np.percentile(window, 99), abs=1e-15)
        assert report.max == window.max()
