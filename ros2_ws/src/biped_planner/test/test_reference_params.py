"""Tests of biped_planner.reference_params."""
import math

import pytest

from biped_planner.errors import ConfigError
from biped_planner.reference_params import ReferenceParams


@pytest.mark.parametrize('field, value', [
    ('com_height', 0.0), ('com_height', math.nan), ('swing_height', -0.01),
    ('foot_length', 0.0), ('foot_width', 2.0), ('support_scale', 1.1), ('support_scale', 0.0),
    ('gravity', 0.0), ('landing_half_length', -0.1), ('landing_half_width', math.inf),
    ('initial_shift_time', 0.0), ('final_settle_time', 20.0), ('com_height', True)])
def test_params_reject_bad_values(field, value):
    with pytest.raises(ConfigError, match=field):
        ReferenceParams(**{field: value})


def test_params_omega():
    assert ReferenceParams(com_height=0.5, gravity=9.81).omega == pytest.approx(
        math.sqrt(9.81 / 0.5))
