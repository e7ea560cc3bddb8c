"""The swing retarget: a replanned swing's target stays continuous and lands at rest."""
import numpy as np
import pytest

from biped_mpc.errors import InputError
from biped_mpc.swing_retarget import FALLBACK_FADE, SwingRetarget
from biped_planner.sides import LEFT
from biped_planner.swing_trajectory import swing_progress

DT = 0.02
SWINGING_LEFT = (False, True)   # the left foot swings, the right stands


def path(t):
    """A planned left swing from x = 0 to 0.1 m over 0.3 s, the right foot at rest."""
    s = np.clip(t / 0.3, 0.0, 1.0)
    return np.array([[0.1 * swing_progress(s), 0.07], [0.0, -0.07]])


def run(retarget, times, moved_at=None, move=np.zeros(2), touchdown=0.3):
    """Targets (planned + offset) of the left foot at each time; the landing moves by `move`
    from moved_at on (the plan's own jump)."""
    out = []
    for t in times:
        planned, after = path(t), path(t + DT)
        if moved_at is not None and t >= moved_at - 1e-12:   # a window of the moved plan
            planned[LEFT] += move * swing_progress(np.clip(t / 0.3, 0.0, 1.0))
            after[LEFT] += move * swing_progress(np.clip((t + DT) / 0.3, 0.0, 1.0))
        offsets = retarget.update(t, DT, SWINGING_LEFT, planned, after, [None, touchdown])
        out.append(planned[LEFT] + offsets[LEFT])
    return np.array(out)


def test_a_plan_that_does_not_move_is_followed_as_it_is():
    retarget = SwingRetarget()
    times = np.arange(0.0, 0.3, DT)
    np.testing.assert_allclose(run(retarget, times, touchdown=0.3),
                               [path(t)[LEFT] for t in times], atol=1e-12)


def test_a_moved_landing_keeps_the_target_where_it_was_and_fades_in_as_the_swing_quintic():
    retarget = SwingRetarget()
    move = np.array([0.06, 0.0])
    times = np.arange(0.0, 0.3 + 1e-9, DT)
    moved_at = times[10]   # two thirds into the swing: the stretched curve jumps by h(2/3) move
    targets = run(retarget, times, moved_at, move)
    jump = move * swing_progress(moved_at / 0.3)
    assert jump[0] > 0.04
    # continuous: the first target after the move is where the old plan would have been
    np.testing.assert_allclose(targets[10], path(moved_at)[LEFT], atol=1e-12)
    # the offset is the negative jump times 1 - h(tau), tau from the move to the touchdown
    for k in range(10, len(times)):
        tau = (times[k] - moved_at) / (0.3 - moved_at)
        new_plan = path(times[k])[LEFT] + move * swing_progress(min(times[k] / 0.3, 1.0))
        np.testing.assert_allclose(targets[k], new_plan - jump * (1.0 - swing_progress(tau)),
                                   atol=1e-12)
    # lands on the moved footstep, at rest
    np.testing.assert_allclose(targets[-1], path(0.3)[LEFT] + move, atol=1e-12)
    steps = np.diff(targets[:, 0])
    assert abs(steps[-1]) < 0.15 * np.max(np.abs(steps))
    assert np.max(np.abs(steps)) < jump[0]   # no period moves the target as far as the jump


def test_differences_below_the_threshold_and_held_feet_give_no_offset():
    retarget = SwingRetarget(threshold=1e-3)
    planned = path(0.1)
    retarget.update(0.1, DT, SWINGING_LEFT, planned, planned, [None, 0.3])
    nudged = planned.copy()
    nudged[LEFT, 0] += 5e-4
    assert not retarget.update(0.1 + DT, DT, SWINGING_LEFT, nudged, nudged, [None, 0.3]).any()
    jumped = planned.copy()
    jumped[LEFT, 0] += 0.02
    assert retarget.update(0.1 + 2 * DT, DT, SWINGING_LEFT, jumped, jumped,
                           [None, 0.3])[LEFT, 0] == pytest.approx(-0.02 + 5e-4)
    assert not retarget.update(0.1 + 3 * DT, DT, (True, True), jumped, jumped, [None, None]).any()


def test_a_cycle_that_is_not_one_period_after_the_last_takes_no_jump():
    retarget = SwingRetarget()
    retarget.update(0.1, DT, SWINGING_LEFT, path(0.1), path(0.1 + DT), [None, 0.3])
    later = 0.1 + 2 * DT   # a period skipped: its target differs by the curve's own motion
    assert not retarget.update(later, DT, SWINGING_LEFT, path(later), path(later + DT),
                               [None, 0.3]).any()


def test_without_a_touchdown_in_the_window_a_jump_fades_over_the_fallback():
    retarget = SwingRetarget()
    planned = path(0.1)
    retarget.update(0.0, DT, SWINGING_LEFT, planned, planned, [None, None])
    jumped = planned.copy()
    jumped[LEFT, 1] += 0.03
    retarget.update(DT, DT, SWINGING_LEFT, jumped, jumped, [None, None])
    assert retarget.offset_at(LEFT, DT)[1] == pytest.approx(-0.03)
    assert retarget.offset_at(LEFT, DT + FALLBACK_FADE)[1] == pytest.approx(0.0)
    assert retarget.offset_at(LEFT, DT + 0.5 * FALLBACK_FADE)[1] == pytest.approx(-0.015)


@pytest.mark.parametrize('planned, after, held, touchdowns', [
    (np.full((2, 2), np.nan), np.zeros((2, 2)), (True, False), [None, None]),
    (np.zeros((2, 3)), np.zeros((2, 2)), (True, False), [None, None]),
    (np.zeros((2, 2)), np.zeros((2, 2)), (True,), [None, None]),
])
def test_bad_inputs_are_refused(planned, after, held, touchdowns):
    with pytest.raises(InputError):
        SwingRetarget().update(0.0, DT, held, planned, after, touchdowns)


def test_a_negative_threshold_is_refused():
    with pytest.raises(InputError):
        SwingRetarget(threshold=-1.0)
