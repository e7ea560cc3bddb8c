from biped_planner.teleop_gate import TeleopAction, TeleopGate

FORWARD, REFRESH, DEFER = TeleopAction.FORWARD, TeleopAction.REFRESH, TeleopAction.DEFER


def driving_gate(velocity=(0.1, 0.0, 0.0), timed_out=False) -> TeleopGate:
    gate = TeleopGate()
    assert gate.received(velocity, 0.0, 0.0, False, False, False) == FORWARD
    gate.driving = True  # the walk it asked for started
    if timed_out:
        assert gate.timed_out(1.0, 1.0, 0.5, walking=True)
    return gate


def test_a_first_cmd_vel_is_forwarded_and_a_repeated_one_only_refreshes():
    gate = driving_gate()
    assert gate.received((0.1, 0.0, 0.0), 0.1, 0.1, True, False, False) == REFRESH
    assert gate.received((0.1, 0.0, 0.0), 0.2, 0.2, True, False, False) == REFRESH
    assert gate.last_heard == (0.2, 0.2)


def test_a_new_velocity_steers_the_walk():
    gate = driving_gate()
    assert gate.received((0.1, 0.05, 0.0), 0.1, 0.1, True, False, False) == FORWARD
    assert gate.velocity == (0.1, 0.05, 0.0)
    assert gate.received((0.1, 0.05, 0.0), 0.2, 0.2, True, False, False) == REFRESH


def test_a_repeat_while_the_start_waits_for_its_plan_does_not_supersede_it():
    gate = TeleopGate()
    assert gate.received((0.1, 0.0, 0.0), 0.0, 0.0, False, False, False) == FORWARD
    assert gate.received((0.1, 0.0, 0.0), 0.1, 0.1, False, False, True) == REFRESH


def test_the_same_velocity_after_a_walk_ended_starts_a_new_walk():
    gate = driving_gate()
    gate.ended()
    assert gate.received((0.1, 0.0, 0.0), 5.0, 5.0, False, False, False) == FORWARD


def test_the_walk_times_out_only_when_both_clocks_say_silent():
    gate = driving_gate()
    # the simulated clock ran ahead (lockstep faster than real time): the operator is there
    assert not gate.timed_out(0.9, 0.3, 0.5, walking=True)
    # the wall ran ahead (a stalled simulation): the walk has not had the time to react
    assert not gate.timed_out(0.3, 0.9, 0.5, walking=True)
    assert gate.timed_out(0.51, 0.51, 0.5, walking=True)
    assert not gate.driving
    assert not gate.timed_out(2.0, 2.0, 0.5, walking=True)  # once


def test_a_walk_not_driven_by_cmd_vel_never_times_out():
    gate = TeleopGate()
    gate.received((0.1, 0.0, 0.0), 0.0, 0.0, False, False, False)
    assert not gate.timed_out(10.0, 10.0, 0.5, walking=True)  # driving is False


def test_a_cmd_vel_while_stopping_is_deferred_and_restarts_the_walk_once_idle():
    gate = driving_gate(timed_out=True)
    assert gate.received((0.0, 0.1, 0.0), 1.0, 1.0, True, True, False) == DEFER
    assert gate.received((0.0, 0.2, 0.0), 1.1, 1.1, True, True, False) == DEFER
    gate.ended()
    assert gate.restart(1.3, 1.3, 0.5) == (0.0, 0.2, 0.0)  # the newest one
    assert gate.deferred is None
    # its repeats while the new walk waits for its plan do not supersede that start
    assert gate.received((0.0, 0.2, 0.0), 1.4, 1.4, False, False, True) == REFRESH


def test_a_deferred_cmd_vel_from_an_operator_gone_silent_is_dropped():
    gate = driving_gate(timed_out=True)
    gate.received((0.0, 0.1, 0.0), 1.0, 1.0, True, True, False)
    gate.ended()
    assert gate.restart(1.6, 1.6, 0.5) is None
    assert gate.deferred is None


def test_a_cmd_vel_while_a_walk_stops_for_a_stop_command_is_not_deferred():
    gate = driving_gate()
    gate.driving = False  # STOP
    assert gate.received((0.0, 0.1, 0.0), 1.0, 1.0, True, True, False) == FORWARD  # refused
    assert gate.deferred is None


def test_a_fall_drops_the_deferred_velocity():
    gate = driving_gate(timed_out=True)
    gate.received((0.0, 0.1, 0.0), 1.0, 1.0, True, True, False)
    gate.ended(drop_deferred=True)
    assert gate.deferred is None and gate.restart(1.1, 1.1, 0.5) is None
