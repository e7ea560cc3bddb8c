"""What a step adjuster needs to know of a walking plan, and how an adjusted landing moves it.

The planner side of step adjustment (the QP itself is biped_planner.step_adjustment): the
step under way at a time, read from a WalkingReference, and the later landings carried along
with a moved landing so that the rest of the walk keeps its shape.
"""
from dataclasses import dataclass
import math
from typing import Optional, Sequence, Tuple

import numpy as np

from biped_planner.footsteps import Footstep
from biped_planner.input_checks import check_finite_array, check_integer


@dataclass(frozen=True)
class SwingStep:
    """The step whose foot is swinging at a time, as the plan has it.

    :param step: step index k (it lands footsteps[k + 2])
    :param lift_off: start of its single support (s)
    :param touchdown: end of its single support, the planned landing time (s)
    :param stance: the stance foot's footstep
    :param landing: the planned landing footstep
    :param zmp: (2,) reference ZMP at the time (m): the stance sole centre
    :param zmp_half_size: (2,) half size of the reference's ZMP box at the time (m)
    :param dcm: (2,) the reference's hip DCM at the time (m)
    :param dcm_at_touchdown: (2,) the reference's hip DCM at touchdown (m)
    :param dcm_at_lift_off: (2,) the reference's hip DCM at lift-off (m)
    :param omega: the reference's LIPM natural frequency (1/s)
    """

    step: int
    lift_off: float
    touchdown: float
    stance: Footstep
    landing: Footstep
    zmp: np.ndarray
    zmp_half_size: np.ndarray
    dcm: np.ndarray
    dcm_at_touchdown: np.ndarray
    dcm_at_lift_off: np.ndarray
    omega: float

    def reference_dcm(self, t: float) -> Tuple[float, float]:
        """The reference's hip DCM at a time of this single support, in closed form (m).

        The reference holds its ZMP on the stance centre through single support, so its DCM
        obeys xi(t) = p + (xi(t_lift_off) - p) exp(omega (t - t_lift_off)); the step adjuster
        asks for it every cycle, and the closed form costs a few floating-point operations
        where sampling the reference costs numpy calls.

        :param t: time in [lift_off, touchdown] (s)
        :return: (x, y) of the DCM (m)
        """
        growth = math.exp(self.omega * (t - self.lift_off))
        zmp_x, zmp_y = float(self.zmp[0]), float(self.zmp[1])
        return (zmp_x + (float(self.dcm_at_lift_off[0]) - zmp_x) * growth,
                zmp_y + (float(self.dcm_at_lift_off[1]) - zmp_y) * growth)

    @property
    def duration(self) -> float:
        """Planned step duration, lift-off to touchdown (s)."""
        return self.touchdown - self.lift_off


def swing_step_at(reference, t: float) -> Optional[SwingStep]:
    """The step in single support at t, None in double support, standing, after the walk or
    while the plan holds a late landing (WalkingReference.hold_landing: the swing is over,
    the foot waits for the ground on its landing).

    :param reference: a WalkingReference
    :param t: time (s)
    :return: the swing step or None
    """
    index = reference.single_support_at(t)
    if index is None or index != reference.swing_of_late_landing(t):
        return None
    phase = reference.phases[index]
    step = phase.step_index - 1
    footsteps = reference.footsteps
    swing_order = (footsteps[1], footsteps[0]) + tuple(footsteps[2:])
    window = reference.sample(t, 1, 0.01)
    return SwingStep(step=step, lift_off=phase.t_begin, touchdown=phase.t_end,
                     stance=swing_order[step + 1], landing=footsteps[step + 2],
                     zmp=np.asarray(window.zmp[0], dtype=float),
                     zmp_half_size=0.5 * (np.asarray(window.zmp_max[0], dtype=float)
                                          - np.asarray(window.zmp_min[0], dtype=float)),
                     dcm=reference.lipm.state_at(t)[1],
                     dcm_at_touchdown=reference.lipm.state_at(phase.t_end)[1],
                     dcm_at_lift_off=reference.lipm.state_at(phase.t_begin)[1],
                     omega=float(reference.omega))


def moved_landings(footsteps: Sequence[Footstep], index: int,
                   location: Sequence[float]) -> Tuple[Footstep, ...]:
    """footsteps[index:] with footsteps[index] at location and the later ones moved with it.

    The later landings are translated by the same displacement, so the walk keeps its step
    lengths and widths from where the foot actually lands (headings unchanged).

    :param footsteps: the footstep list
    :param index: the moved landing, >= 2 (the initial feet do not move)
    :param location: (2,) its new sole centre (m)
    :return: the landings from index on
    :raises ConfigError: for an index outside the landings or a non-finite location
    """
    check_integer('index', index, low=2, high=len(footsteps) - 1)
    location = check_finite_array('location (x, y)', location, shape=(2,))
    dx = float(location[0]) - footsteps[index].x
    dy = float(location[1]) - footsteps[index].y
    return tuple(Footstep(step.side, step.x + dx, step.y + dy, step.yaw)
                 for step in footsteps[index:])
