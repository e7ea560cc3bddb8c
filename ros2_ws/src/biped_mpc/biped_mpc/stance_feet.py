"""The stance feet: latched where they landed, released when the reference lifts them.

A stance foot does not move, so the controller keeps its pose from touch-down instead of
re-measuring it: its target is that pose, the pelvis estimate of pelvis_source 'imu_kinematics'
hangs from it (pelvis = latched sole - R_imu FK(sole)), and its leg mass is constrained midway
between it and the torso (stance-leg projection).
"""
from typing import Optional

import numpy as np

from biped_mpc.leg_kinematics import sole_pose
from biped_mpc.linear_model import LEFT_LEG, POSITION, RIGHT_LEG, state_index, TORSO
from biped_planner.sides import LEFT, RIGHT, SIDES, SUPPORT_DOUBLE, SUPPORT_LEFT, SUPPORT_RIGHT


def on_support(side: int, support: int) -> bool:
    """True when the support label (SUPPORT_*) has this foot on the ground."""
    return support in ((SUPPORT_LEFT if side == LEFT else SUPPORT_RIGHT), SUPPORT_DOUBLE)


class StanceFeet:
    """Latched sole poses (x, y, z, yaw) of the feet on the ground, and the anchor foot.

    The anchor is the foot on the ground longest. With relatch_followers (pelvis_source
    'imu_kinematics', where the pelvis is estimated from the anchor) a foot that lands later is
    latched again at every cycle from that estimate until the anchor lifts off, so it is
    anchored where it settled: a foot that lands tilted and then rolls flat moves its sole
    centre by millimetres, which would accumulate into the pelvis estimate at every step.

    :param relatch_followers: latch the non-anchor feet again every cycle while in contact
    """

    def __init__(self, relatch_followers: bool) -> None:
        self._relatch = relatch_followers
        self._latched = [None, None]
        self._anchors = []
        self._last_ground = 0.0

    def reset(self, soles: tuple) -> None:
        """Both feet on the ground where they are.

        :param soles: ((position, rotation) of the left sole, same of the right one)
        """
        self._latched = [sole_pose(*soles[side]) for side in SIDES]
        self._anchors = [LEFT, RIGHT]
        self._last_ground = float(np.mean([latch[2] for latch in self._latched]))

    @property
    def latched(self) -> list:
        """[left, right] latched poses (4,), None for a foot not on the ground."""
        return self._latched

    @property
    def anchor(self) -> Optional[int]:
        """The foot on the ground longest, None while none is latched."""
        return self._anchors[0] if self._anchors else None

    @property
    def standing(self) -> tuple:
        """(left, right): True for a latched foot."""
        return tuple(latch is not None for latch in self._latched)

    def update(self, support: Optional[int], soles: tuple, contacts: tuple) -> None:
        """Latch a foot where it is on touch-down, release it when the reference lifts it.

        :param support: the reference's support label now, None without a reference (no change)
        :param soles: measured ((position, rotation) left, (position, rotation) right)
        :param contacts: (left, right) contact flags
        """
        if support is None:
            return
        for side in SIDES:
            if not on_support(side, support):
                self._latched[side] = None
                if side in self._anchors:
                    self._anchors.remove(side)
            elif contacts[side] and (self._latched[side] is None or (
                    self._relatch and self._anchors and self._anchors[0] != side)):
                self._latched[side] = sole_pose(*soles[side])
                if side not in self._anchors:
                    self._anchors.append(side)

    def held(self, support: int) -> list:
        """[left, right]: the foot is latched and stays on the ground for this support label."""
        return [self._latched[side] is not None and on_support(side, support) for side in SIDES]

    def ground_height(self, support: int, zmp: Optional[np.ndarray] = None) -> float:
        """Height of the ground the robot stands on, from the feet held for this support label.

        Without zmp the mean height of the held feet. With zmp, on two held feet, their heights
        interpolated at the ZMP's projection on the segment between them (clamped to it): the
        ground moves with the weight. The mean steps at each touchdown and lift-off by half
        the feet's difference in height, and on tiles the stiff legs took that step at once
        (docs/controller_notes.md, "Touchdowns that kick"); under the ZMP nothing changes at a
        touchdown (the weight is still on the stance foot) nor at the lift-off (it has left).

        Between the lift-off of the old stance foot and the confirmed touchdown of the new one
        no foot is held; the ground is then where the feet last stood, not the world's zero
        (on tiles 25-50 mm high that fallback dropped the pelvis target by 45 mm for a cycle).

        :param support: the support label (SUPPORT_*) the targets are for
        :param zmp: (2,) the ZMP (m) to weigh two held feet by, None for their mean
        :return: ground height (m)
        """
        held = self.held(support)
        if all(held) and zmp is not None:
            left, right = self._latched[LEFT], self._latched[RIGHT]
            between = right[:2] - left[:2]
            share = float(np.clip(np.dot(np.asarray(zmp, dtype=float) - left[:2], between)
                                  / max(float(np.dot(between, between)), 1e-12), 0.0, 1.0))
            self._last_ground = float((1.0 - share) * left[2] + share * right[2])
            return self._last_ground
        grounds = [self._latched[side][2] for side, on in enumerate(held) if on]
        if grounds:
            self._last_ground = float(np.mean(grounds))
        return self._last_ground

    def project_legs(self, state: np.ndarray) -> None:
        """Put each stance leg's mass midway between its latched sole and the torso, in place.

        A stance foot does not move, so its leg mass (midway between the sole and the hip) has
        half the torso's velocity and acceleration; the free model lets it drift from there,
        and at lift-off the swing foot target 2 * leg - hip would jump by twice the drift.

        :param state: (2, 9) model state per plane
        """
        torso = slice(state_index(TORSO, POSITION), state_index(TORSO, POSITION) + 3)
        for side, mass in ((LEFT, LEFT_LEG), (RIGHT, RIGHT_LEG)):
            latch = self._latched[side]
            if latch is None:
                continue
            leg = slice(state_index(mass, POSITION), state_index(mass, POSITION) + 3)
            state[:, leg] = 0.5 * state[:, torso]
            state[:, state_index(mass, POSITION)] += 0.5 * latch[:2]
