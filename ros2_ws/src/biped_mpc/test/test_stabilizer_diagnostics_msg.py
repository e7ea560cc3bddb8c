"""The stabilizer's terms reach controller_diagnostics, the hip strategy's trunk tilt, the
command leash's shift and the lift-off gate's holds too."""
from types import SimpleNamespace

import numpy as np

from biped_mpc.nodes.conversions import stabilizer_terms
from biped_msgs.msg import ControllerDiagnostics


def test_every_stabilizer_term_is_copied_into_the_message():
    output = SimpleNamespace(
        zmp_desired=np.array([0.01, -0.02]), zmp_error=np.array([0.0, 0.003]),
        dcm_error=np.array([0.004, -0.05]), foot_torque_errors=np.arange(4.0).reshape(2, 2),
        foot_contacts=(False, True), ankle_offsets=np.full((2, 2), 0.01),
        ankle_conformance=np.array([[0.0, 0.05], [-0.02, 0.0]]),
        vertical_offsets=np.array([0.001, -0.001]), landing_modes=('swinging', 'support'),
        trunk_tilt=np.array([0.12, -0.03]), command_leash_shift=np.array([0.0, 0.031]),
        dcm_leash_shift=np.array([-0.012, 0.004]), lift_held=(False, True))
    diag = ControllerDiagnostics()
    stabilizer_terms(diag, output)
    assert list(diag.trunk_tilt) == [0.12, -0.03]
    assert list(diag.command_leash_shift) == [0.0, 0.031]
    assert list(diag.dcm_leash_shift) == [-0.012, 0.004]
    assert list(diag.dcm_error) == [0.004, -0.05]
    assert list(diag.ankle_conformance) == [0.0, 0.05, -0.02, 0.0]
    assert list(diag.foot_torque_errors) == [0.0, 1.0, 2.0, 3.0]
    assert list(diag.foot_contacts) == [False, True]
    assert list(diag.landing_modes) == ['swinging', 'support']
    assert list(diag.lift_held) == [False, True]


def test_the_landing_of_the_last_cycle_fills_the_balance_estimate_in_the_planner_words():
    from biped_mpc.nodes.conversions import landing_of
    from biped_msgs.msg import BalanceEstimate
    from biped_planner.landing_hold import LANDING_STATES
    output = SimpleNamespace(landing_modes=('support', 'seeking'),
                             landing_depths=np.array([0.0, 0.012]))
    msg = BalanceEstimate()
    msg.landing_modes, msg.landing_depths = landing_of(output)
    assert list(msg.landing_modes) == ['none', 'seeking']
    assert list(msg.landing_depths) == [0.0, 0.012]
    assert set(msg.landing_modes) <= set(LANDING_STATES)
    assert landing_of(None) == (['none', 'none'], [0.0, 0.0])  # before the first cycle
    # every mode the controller's landing logic has is one the landing hold knows
    from biped_mpc.balance.swing_landing import FAILED, LANDED, SEEKING, SWINGING
    assert {SWINGING, SEEKING, LANDED, FAILED} <= set(LANDING_STATES)
