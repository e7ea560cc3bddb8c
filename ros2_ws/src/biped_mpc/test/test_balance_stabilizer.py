"""Stabilizer composition: a few cycles standing, with imposed errors, and their signs."""
import numpy as np
import pytest

from biped_mpc.balance.ft_filter import FootWrench
from biped_mpc.balance.stabilizer import (
    Stabilizer, StabilizerMeasurement, StabilizerParams, StabilizerReference)
from biped_mpc.balance.wrench_distribution import DistributionStatus
from biped_mpc.errors import ConfigError, InputError
from biped_planner.sides import LEFT, RIGHT

DT = 0.02
MASS = 30.95
FEET = np.array([[0.0, 0.1, 0.0], [0.0, -0.1, 0.0]])


def foot_wrench(normal, cop_local, position):
    """A flat foot (yaw 0) loaded with normal N at cop_local (x, y) from its sole centre."""
    torque = np.array([cop_local[1] * normal, -cop_local[0] * normal, 0.0])
    force = np.array([0.0, 0.0, normal])
    cop = np.array([position[0] + cop_local[0], position[1] + cop_local[1], position[2]])
    return FootWrench(force, torque, force, torque, float(normal), cop, force, torque)


def measurement(normals=(MASS * 9.81 / 2,) * 2, cops=((0.0, 0.0), (0.0, 0.0)),
                contacts=(True, True), dcm=(0.0, 0.0), heights=None, planned=None):
    wrenches = tuple(foot_wrench(normals[s], cops[s], FEET[s]) for s in (LEFT, RIGHT))
    return StabilizerMeasurement(np.array([dcm[0], dcm[1], 0.497]), np.array(dcm), wrenches,
                                 contacts, FEET, np.zeros(2), heights, planned)


REFERENCE = StabilizerReference(np.zeros(2), np.zeros(2))


def run(stabilizer, cycles, reference=REFERENCE, **kwargs):
    for _ in range(cycles):
        output = stabilizer.update(DT, reference, measurement(**kwargs))
    return output


def test_nominal_standing_changes_nothing():
    output = run(Stabilizer(), 10)
    np.testing.assert_allclose(output.zmp, [0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(output.wrenches[:, 2], MASS * 9.81 / 2, rtol=1e-4)
    np.testing.assert_allclose(output.ankle_offsets, 0.0, atol=1e-5)
    np.testing.assert_allclose(output.vertical_offsets, 0.0, atol=1e-6)
    diagnostics = output.diagnostics
    assert diagnostics.distribution_status == DistributionStatus.OK
    np.testing.assert_allclose(diagnostics.measured_zmp, [0.0, 0.0], atol=1e-12)
    assert diagnostics.contacts == (True, True) and not diagnostics.in_the_air


def test_pressure_on_the_heels_pitches_the_soles_toes_down():
    output = run(Stabilizer(), 10, cops=((-0.02, 0.0), (-0.02, 0.0)))
    np.testing.assert_allclose(output.diagnostics.zmp_error, [0.02, 0.0], atol=1e-9)
    # measured tau_y = -x_cop f_z > desired 0: positive pitch lifts the heel (toes press)
    assert np.all(output.ankle_offsets[:, 1] > 0.0)
    np.testing.assert_allclose(output.ankle_offsets[:, 0], 0.0, atol=1e-5)
    assert np.all(output.diagnostics.torque_errors[:, 1] > 0.0)


def test_pressure_on_the_outer_edges_rolls_the_soles_outwards_up():
    output = run(Stabilizer(), 10, cops=((0.0, 0.03), (0.0, -0.03)))
    assert output.ankle_offsets[LEFT, 0] > 0.0 > output.ankle_offsets[RIGHT, 0]


def test_dcm_ahead_moves_the_zmp_and_the_feet_cops_forward():
    output = run(Stabilizer(), 1, dcm=(0.01, 0.0))
    assert output.zmp[0] > 0.01
    assert np.all(output.local_wrenches[:, 4] < 0.0)  # tau_y = -x_cop f_z
    # the horizontal force of the LIPM pulls the COM back over the ZMP
    assert output.wrenches[:, 0].sum() < 0.0


def test_left_foot_overloaded_is_lifted_relative_to_the_right():
    weight = MASS * 9.81
    output = run(Stabilizer(), 5, normals=(0.65 * weight, 0.35 * weight))
    assert output.diagnostics.force_difference_error > 0.0
    assert output.vertical_offsets[LEFT] > 0.0 > output.vertical_offsets[RIGHT]
    assert output.vertical_offsets[LEFT] == pytest.approx(-output.vertical_offsets[RIGHT])


def test_vertical_drift_raises_both_feet_when_the_legs_sag():
    reference = StabilizerReference(np.zeros(2), np.zeros(2), mean_sole_height=-0.54)
    output = run(Stabilizer(), 5, reference, heights=-0.55)
    np.testing.assert_allclose(output.vertical_offsets, 5 * DT * 1.0 * 0.01, rtol=1e-3)


def test_single_support_gives_everything_to_the_stance_foot():
    stabilizer = Stabilizer()
    run(stabilizer, 10, cops=((-0.02, 0.0), (-0.02, 0.0)))
    assert stabilizer.damping[RIGHT].offset[1] > 0.0
    output = run(stabilizer, 10, normals=(MASS * 9.81, 0.0), cops=((0.0, 0.0), (0.0, 0.0)),
                 contacts=(True, False), dcm=(0.0, 0.1))
    np.testing.assert_array_equal(output.wrenches[RIGHT], 0.0)
    np.testing.assert_allclose(output.wrenches[LEFT, 2], MASS * 9.81, rtol=1e-3)
    np.testing.assert_array_equal(output.ankle_offsets[RIGHT], 0.0)  # released at 1 rad/s
    assert output.diagnostics.contacts == (True, False)


def test_a_planned_foot_not_yet_touching_gets_its_share_and_is_lowered():
    weight = MASS * 9.81
    # The plan has both feet down; the right one hovers over a lower tile: no force, no
    # detected contact. With the detected contacts it is left alone (single support) ...
    detected = run(Stabilizer(), 5, normals=(weight, 0.0), contacts=(True, False))
    np.testing.assert_array_equal(detected.vertical_offsets, 0.0)
    np.testing.assert_array_equal(detected.wrenches[RIGHT], 0.0)
    # ... with the plan's support it carries half the weight and the force difference
    # lowers it relative to the overloaded left foot: dz_dot = K_f (f_L - f_R - 0)
    planned = run(Stabilizer(), 5, normals=(weight, 0.0), contacts=(True, False),
                  planned=(True, True))
    np.testing.assert_allclose(planned.wrenches[:, 2], weight / 2, rtol=1e-3)
    dz = 1e-4 * weight * 5 * DT  # leak 0.1/s: within 1 %
    np.testing.assert_allclose(planned.vertical_offsets, [dz / 2, -dz / 2], rtol=0.01)
    # the measured ZMP stays the one of the detected contact: the left sole centre
    np.testing.assert_allclose(planned.diagnostics.measured_zmp, FEET[LEFT, :2], atol=1e-12)
    assert planned.diagnostics.contacts == (True, False)


def test_in_the_air_only_the_dcm_feedback_runs():
    stabilizer = Stabilizer()
    run(stabilizer, 3, dcm=(0.01, 0.0))
    integral = stabilizer.dcm_feedback.integral
    output = run(stabilizer, 3, contacts=(False, False), dcm=(0.01, 0.0))
    np.testing.assert_array_equal(stabilizer.dcm_feedback.integral, integral)
    np.testing.assert_array_equal(output.wrenches, 0.0)
    assert output.diagnostics.in_the_air and output.diagnostics.distribution_status is None
    stabilizer.reset()
    np.testing.assert_array_equal(stabilizer.dcm_feedback.integral, [0.0, 0.0])


def test_bad_values_are_refused():
    with pytest.raises(ConfigError):
        StabilizerParams(mass=0.0)
    with pytest.raises(ConfigError):
        StabilizerParams(dcm=None)
    with pytest.raises(InputError):
        Stabilizer().update(0.0, REFERENCE, measurement())
    bad = StabilizerMeasurement(np.zeros(3), np.zeros(2), measurement().wrenches, (True,),
                                FEET, np.zeros(2))
    with pytest.raises(InputError):
        Stabilizer().update(DT, REFERENCE, bad)


def test_the_zmp_beyond_the_soles_is_reported_as_the_excess():
    """A DCM 5 cm right of the right sole asks for a ZMP farther right than the sole reaches:
    the clamp keeps it on the sole and the rest is the excess, towards the DCM; inside the
    soles there is none."""
    inside = run(Stabilizer(), 3)
    np.testing.assert_array_equal(inside.zmp_excess, 0.0)
    output = run(Stabilizer(), 1, dcm=(0.0, -0.15), contacts=(False, True),
                 planned=(False, True))
    assert output.diagnostics.zmp_clamped
    assert output.zmp_excess[1] < -0.05 and abs(output.zmp_excess[0]) < 1e-9
    half_width = (Stabilizer().params.distribution.sole_width
                  - 2.0 * Stabilizer().params.distribution.cop_margin) / 2.0
    assert output.zmp[1] == pytest.approx(FEET[RIGHT, 1] - half_width)


def test_a_cut_foothold_keeps_the_desired_zmp_and_the_sole_torque_on_its_ground():
    """The left sole alone, cut at x = 0.02 of its frame (a partial foothold, its toe over a
    lower tile); the DCM 5 cm ahead asks for the ZMP past the cut: the support polygon (the cut
    sole shrunk by the 1 cm CoP margin) stops it at x = 0.01, and the foot's desired CoP too."""
    from dataclasses import replace
    cut = [(1.0, 0.0, 0.02)]
    weight = (MASS * 9.81, 0.0)
    whole = measurement(normals=weight, contacts=(True, False), dcm=(0.05, 0.1))
    stabilizer = Stabilizer()
    free = stabilizer.update(DT, REFERENCE, whole)
    assert free.zmp[0] > 0.05  # within the whole sole (x up to 0.09)
    stabilizer = Stabilizer()
    output = stabilizer.update(DT, REFERENCE, replace(whole, footholds=(cut, [])))
    assert output.zmp[0] == pytest.approx(0.01, abs=1e-9)
    assert output.diagnostics.zmp_clamped
    local = output.local_wrenches[LEFT]
    assert -local[4] / local[2] == pytest.approx(0.01, abs=2e-4)  # the foot's CoP x
    # none for the other foot, and footholds=None is the whole sole
    np.testing.assert_allclose(Stabilizer().update(
        DT, REFERENCE, replace(whole, footholds=([], []))).zmp, free.zmp, atol=1e-12)
