"""The LIPM baseline in the shared layout: cart-table ZMP, massless kinematic legs."""
import numpy as np
import pytest

from biped_mpc.errors import ConfigError
from biped_mpc.linear_model import OUTPUT_ZMP
from biped_mpc.lipm_model import lipm_model, LipmParams
from biped_mpc.three_mass_model import ThreeMassParams


def test_zmp_is_the_cart_table_of_the_single_mass():
    params = LipmParams(mass=60.0, com_height=0.8, gravity=9.8)
    model = lipm_model(params)
    rng = np.random.default_rng(1)
    for _ in range(10):
        state = rng.normal(size=9)
        expected = state[3] - 0.8 / 9.8 * state[5]
        assert model.c[OUTPUT_ZMP] @ state == pytest.approx(expected, rel=1e-12, abs=1e-14)


def test_legs_are_kinematic_and_absent_from_the_zmp():
    model = lipm_model()
    assert np.all(model.zmp_row[[0, 1, 2, 6, 7, 8]] == 0.0)
    assert model.c.shape == (3, 9) and model.b.shape == (9, 3)
    assert model.force_input[4] == pytest.approx(1.0 / 80.0)


def test_from_three_mass_keeps_mass_and_com_height():
    params = LipmParams.from_three_mass(ThreeMassParams())
    assert params.mass == pytest.approx(80.0)
    assert params.com_height == pytest.approx(0.9375)


@pytest.mark.parametrize('field, value', [('mass', -1.0), ('mass', 0.0), ('com_height', 0.0),
                                          ('com_height', float('nan')), ('gravity', -9.81)])
def test_bad_parameters_raise(field, value):
    with pytest.raises(ConfigError, match=field):
        LipmParams(**{field: value})
