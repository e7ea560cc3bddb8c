"""The balance loop of the controller (biped_mpc.balance.balance_loop) on hand-made cases."""
import numpy as np
import pytest

from biped_mpc.balance.balance_loop import BalanceLoop, BalanceLoopParams, planned_landing
from biped_mpc.balance.stabilizer import StabilizerReference
from biped_mpc.controller_params import WalkingControllerParams
from biped_mpc.errors import ConfigError
from biped_mpc.ik_targets import IkTargets
from biped_planner.sides import LEFT, RIGHT, SUPPORT_DOUBLE, SUPPORT_RIGHT

DT = 0.02
FOOT_MASS = 0.75
G = 9.81


def loop_with(coman_like_model, **fields):
    """A balance loop of the controller's parameters with these fields changed."""
    params = WalkingControllerParams(robot=coman_like_model, **fields)
    return BalanceLoop(BalanceLoopParams.from_controller(params, 30.95, 0.497))


@pytest.fixture
def loop(coman_like_model):
    return loop_with(coman_like_model)


def flat_soles(x_left=0.0, x_right=0.0):
    return ((np.array([x_left, 0.07, 0.0]), np.eye(3)), (np.array([x_right, -0.07, 0.0]),
                                                          np.eye(3)))


def sensor_wrench(normal_force, cop_x=0.0, sensor_height=0.04, foot_mass=FOOT_MASS):
    """What the ankle sensor reads for a ground force through (cop_x, 0) of a still foot:
    the foot on the leg, f_s = F_g - m g, tau_s about the sensor (sole 0.04 m below)."""
    ground = np.array([0.0, 0.0, normal_force])
    force = ground - foot_mass * np.array([0.0, 0.0, G])
    arm = np.array([cop_x, 0.0, -sensor_height])  # CoP from the sensor origin
    com_arm = np.array([0.0, 0.0, -0.0275])
    torque = np.cross(arm, ground) + np.cross(com_arm, -foot_mass * np.array([0.0, 0.0, -G]))
    return np.concatenate([force, torque])


class Window:
    """A reference window: the left foot swinging from sample 0, landing at sample k (k = 0:
    already down)."""

    def __init__(self, n=30, landing=20, x_landing=0.1):
        self.support = np.array([SUPPORT_RIGHT] * landing + [SUPPORT_DOUBLE] * (n - landing))
        self.left_foot = np.tile([0.0, 0.07, 0.0], (n, 1))
        self.right_foot = np.tile([0.0, -0.07, 0.0], (n, 1))
        self.left_foot[:, 0] = np.minimum(np.arange(n) / max(landing, 1), 1.0) * x_landing
        self.left_foot[landing:, 2] = 0.0


def test_planned_landing_is_the_first_support_sample():
    window = Window(landing=20)
    landing = planned_landing(window, LEFT, 1.0, DT)
    assert landing[0] == pytest.approx(1.0 + 20 * DT)
    np.testing.assert_allclose(landing[1], [0.1, 0.07, 0.0])
    assert planned_landing(window, RIGHT, 1.0, DT)[0] == pytest.approx(1.0 + DT)


def walk_to_landing(loop, x_left, duration=0.8, moved_landing=None):
    """The left foot swings (landing planned 0.1 m ahead at 0.4 s), is loaded with 300 N from
    0.3 s on where x_left puts it; returns the warnings of every cycle. moved_landing (t, x):
    from t on the plan lands the foot at x instead (a step adjustment)."""
    air, load = sensor_wrench(0.0), sensor_wrench(300.0)
    events = []
    for k in range(int(round(duration / DT))):
        t = k * DT
        x_landing = 0.1
        if moved_landing is not None and t >= moved_landing[0] - 1e-9:
            x_landing = moved_landing[1]
        window = Window(landing=max(20 - k, 0), x_landing=x_landing)  # sampled at t
        loop.sense(t, DT, np.array([air if t < 0.3 - 1e-9 else load, load]),
                   flat_soles(x_left=x_left), window)
        events += loop.take_events()
    return events


def test_a_loaded_foot_refused_by_the_distance_gate_is_reported_once(loop):
    events = walk_to_landing(loop, x_left=0.0)  # 0.1 m from its landing: the gate refuses it
    assert loop.contacts == (False, True)
    assert len(events) == 1
    assert events[0].startswith('left foot: 300 N on it 0.20 s after its planned landing')
    assert '0.100 m from its planned landing' in events[0]


def test_a_foot_landing_where_an_adjustment_moved_its_step_is_confirmed(coman_like_model):
    # the plan moves the landing 0.1 -> 0.2 m at 0.2 s; the foot lands there, 0.1 m from the
    # point planned at lift-off (touchdown_gate_distance 0.05 m)
    loop = loop_with(coman_like_model)
    events = walk_to_landing(loop, x_left=0.2, moved_landing=(0.2, 0.2))
    assert loop.contacts == (True, True)
    assert events == []


def test_a_gate_held_at_the_lift_off_landing_refuses_the_moved_step(coman_like_model):
    loop = loop_with(coman_like_model, touchdown_gate_follows_plan=False)
    events = walk_to_landing(loop, x_left=0.2, moved_landing=(0.2, 0.2))
    assert loop.contacts == (False, True)
    assert len(events) == 1
    assert '0.100 m from the landing planned at its lift-off' in events[0]


def walk_behind_the_plan(loop, x_left, stance_behind):
    """walk_to_landing with the stance (right) foot measured stance_behind (m) behind its
    planned place: a robot that slid back on its blind plan."""
    air, load = sensor_wrench(0.0), sensor_wrench(300.0)
    events = []
    for k in range(40):
        t = k * DT
        loop.sense(t, DT, np.array([air if t < 0.3 - 1e-9 else load, load]),
                   flat_soles(x_left=x_left, x_right=-stance_behind),
                   Window(landing=max(20 - k, 0)))
        events += loop.take_events()
    return events


def test_the_gate_measures_the_step_from_the_stance_foot(coman_like_model):
    # the stance foot slid 8 cm back; the left foot makes the planned 0.1 m step from it,
    # landing 8 cm short of the plan's point in the world (touchdown_gate_distance 0.05 m)
    loop = loop_with(coman_like_model, touchdown_gate_from_stance=True)
    assert walk_behind_the_plan(loop, x_left=0.02, stance_behind=0.08) == []
    assert loop.contacts == (True, True)
    # the same foot on the plan's point made an 8 cm longer step than planned: refused
    loop = loop_with(coman_like_model, touchdown_gate_from_stance=True)
    events = walk_behind_the_plan(loop, x_left=0.1, stance_behind=0.08)
    assert loop.contacts == (False, True)
    assert '0.080 m from its planned landing (from the stance foot)' in events[0]


def test_the_default_gate_in_the_world_refuses_a_step_made_from_a_slid_stance_foot(loop):
    events = walk_behind_the_plan(loop, x_left=0.02, stance_behind=0.08)
    assert loop.contacts == (False, True)
    assert '0.080 m from its planned landing (touchdown_gate_distance' in events[0]


def land_off_plan_then_lift_the_other_foot(loop, lift_at):
    """The left foot lands 0.1 m short of its landing (planned at 0.4 s) and is loaded with 300
    N from 0.3 s; the right foot is unloaded from lift_at on, as when the plan lifts it:
    the contact states of every cycle."""
    air, load = sensor_wrench(0.0), sensor_wrench(300.0)
    states = []
    for k in range(50):
        t = k * DT
        loop.sense(t, DT, np.array([air if t < 0.3 - 1e-9 else load,
                                    load if t < lift_at - 1e-9 else air]),
                   flat_soles(x_left=0.0), Window(landing=max(20 - k, 0)))
        states.append(loop.contacts)
    return states


def test_a_foot_off_its_plan_is_confirmed_once_the_other_foot_is_off_the_ground(
        coman_like_model):
    loop = loop_with(coman_like_model, touchdown_gate_needs_other_foot=True)
    states = land_off_plan_then_lift_the_other_foot(loop, lift_at=0.6)
    # refused while the right foot stands (0.1 m from the landing, the gate 0.05 m) ...
    assert all(state == (False, True) for state in states[15:30])
    # ... confirmed once its detector reads it gone (the F/T low-pass and the dwell: two
    # cycles after the unloading), within two cycles: the robot stands on the left foot
    gone = next(k for k, state in enumerate(states) if not state[RIGHT])
    assert gone == 32
    assert states[gone + 2:] == [(True, False)] * (len(states) - gone - 2)


def test_by_default_a_foot_off_its_plan_stays_refused_with_no_foot_down(loop):
    states = land_off_plan_then_lift_the_other_foot(loop, lift_at=0.6)
    assert states[-1] == (False, False)


def test_a_moved_landing_time_moves_the_gate_phase(coman_like_model):
    # planned at 0.4 s, the step is moved to land at 0.6 s: loaded at 0.3 s on the planned
    # point, the foot is inside the gate distance but at phase 0.3 / 0.6 = 0.5 only from 0.3 s
    loop = loop_with(coman_like_model, touchdown_gate_phase=0.6)
    air, load = sensor_wrench(0.0), sensor_wrench(300.0)
    confirmed, lifted = None, False
    for k in range(30):
        t = k * DT
        window = Window(landing=max(30 - k, 0) if t >= 0.1 - 1e-9 else max(20 - k, 0))
        loop.sense(t, DT, np.array([air if t < 0.3 - 1e-9 else load, load]),
                   flat_soles(x_left=0.1), window)
        lifted = lifted or not loop.contacts[LEFT]
        if confirmed is None and lifted and loop.contacts[LEFT]:
            confirmed = t
    # phase 0.6 of a swing from 0 to 0.6 s is 0.36 s (at 0.4 s without the move: 0.3 s)
    assert confirmed == pytest.approx(0.36 + DT, abs=DT + 1e-9)


def test_a_foot_landing_at_its_target_is_confirmed_and_not_reported(loop):
    events = walk_to_landing(loop, x_left=0.1)
    assert loop.contacts == (True, True)
    assert events == []


def test_the_sensor_wrench_becomes_the_ground_reaction_and_its_cop(loop):
    soles = flat_soles()
    wrenches = np.array([sensor_wrench(150.0, 0.03), sensor_wrench(150.0, -0.01)])
    sensed = loop.sense(0.0, DT, wrenches, soles, None)
    # The foot's weight is added back: the ground pushes 150 N on each foot.
    assert sensed.wrenches[LEFT].normal_force == pytest.approx(150.0)
    np.testing.assert_allclose(sensed.wrenches[LEFT].cop[:2], [0.03, 0.07], atol=1e-9)
    # Both feet in contact: the ZMP is the force-weighted mean of the CoPs.
    np.testing.assert_allclose(sensed.zmp, [0.01, 0.0], atol=1e-9)
    assert sensed.contacts == (True, True)


def test_a_foot_in_the_air_reads_no_contact_after_the_dwell_and_no_zmp(loop):
    soles = flat_soles()
    air = sensor_wrench(0.0)
    for k in range(3):
        sensed = loop.sense(k * DT, DT, np.array([air, sensor_wrench(300.0)]), soles, None)
    assert sensed.contacts == (False, True)
    np.testing.assert_allclose(sensed.zmp, [0.0, -0.07], atol=1e-9)


def test_stabilized_targets_tilt_a_sole_whose_cop_sits_off_its_centre(loop):
    soles = flat_soles()
    targets = IkTargets(np.array([0.0, 0.0, 0.54]), np.array([0.0, 0.07, 0.0, 0.0]),
                        np.array([0.0, -0.07, 0.0, 0.0]), 0.0)
    reference = StabilizerReference(zmp=np.zeros(2), dcm=np.zeros(2))
    wrenches = np.array([sensor_wrench(152.0, 0.05), sensor_wrench(152.0, 0.05)])
    for k in range(10):
        sensed = loop.sense(k * DT, DT, wrenches, soles, None)
        result = loop.update(k * DT, DT, targets, sensed, soles, np.array([0.0, 0.0, 0.54]),
                             reference, np.array([0.0, 0.0, 0.497]), np.zeros(2))
    # Pressure ahead of the desired CoP: the pitch offset is negative (toes up, heel down),
    # which moves the CoP back; the rate limit caps its speed.
    rate_limit = loop.params.stabilizer.damping.rate_limit
    pitch = result.targets.foot_tilts[:, 1]
    assert np.all(pitch < 0.0)
    assert np.all(pitch >= -rate_limit * 10 * DT - 1e-12)
    np.testing.assert_allclose(result.targets.foot_tilts[:, 0], 0.0, atol=1e-6)


def test_controller_balance_fields_are_checked(coman_like_model):
    with pytest.raises(ConfigError, match='touchdown_off_force'):
        WalkingControllerParams(robot=coman_like_model, touchdown_on_force=20.0,
                                touchdown_off_force=30.0)
    with pytest.raises(ConfigError, match='balance'):
        WalkingControllerParams(robot=coman_like_model, balance='closed')
    with pytest.raises(ConfigError, match='cop_margin'):
        WalkingControllerParams(robot=coman_like_model, cop_margin=0.04, sole_width=0.05)


def test_the_hip_strategy_swings_the_trunk_in_single_support_only(coman_like_model):
    """The DCM far right of the right sole: on the right foot alone the pelvis target rolls
    towards the fall (positive roll, its top towards -y); planned on both feet it stays
    upright (sole edges in a double support are the foot damping's)."""
    loop = loop_with(coman_like_model, hip_strategy_gain=1.0)
    soles = flat_soles()
    targets = IkTargets(np.array([0.0, 0.0, 0.54]), np.array([0.0, 0.07, 0.05, 0.0]),
                        np.array([0.0, -0.07, 0.0, 0.0]), 0.0)
    reference = StabilizerReference(zmp=np.zeros(2), dcm=np.zeros(2))
    wrenches = np.array([sensor_wrench(0.0), sensor_wrench(300.0)])
    rolls = {}
    for planned in ((False, True), (True, True)):
        loop.reset(None)
        for k in range(10):
            sensed = loop.sense(k * DT, DT, wrenches, soles, None)
            result = loop.update(k * DT, DT, targets, sensed, soles,
                                 np.array([0.0, -0.1, 0.54]), reference,
                                 np.array([0.0, -0.1, 0.497]), np.array([0.0, -0.2]),
                                 planned)
        rolls[planned] = result.targets.trunk_tilt
    assert rolls[(False, True)][0] > 0.01 and abs(rolls[(False, True)][1]) < 1e-9
    np.testing.assert_array_equal(rolls[(True, True)], 0.0)
