"""Balance stabilizer between the MPC and the leg IK: one concept per module, pure numpy.

Every module takes time or the interval as an argument, has a frozen parameter dataclass whose
fields carry their description, unit and range (biped_planner.parameter_fields), a class with
reset(...) and update(...), and returns a frozen result dataclass:

- dcm_feedback: DCM (capture point) PI feedback on the desired ZMP, clamped to the support
  polygon; also the support polygon helpers (rectangles, convex hull, projection).
- ft_filter: foot inertia removed from the ankle F/T reading, low-pass, centres of pressure.
- wrench_distribution: the net wrench split between the feet by a small QP.
- foot_damping: ankle roll / pitch admittance on the ankle torque error.
- foot_force_difference: vertical feet offset from the normal-force difference.
- vertical_drift: slow correction of the mean feet height.
- touchdown_detector: contact on / off with hysteresis, dwell and swing-phase gating.
- swing_landing: contact-seeking swing end and the support timing events it raises.
- stabilizer: one control cycle of all of the above, wired together.
- balance_loop: the stabilizer in the walking controller's cycle (sensing, contacts, targets).
- measured_dcm: the DCM of the measured three-mass state (pelvis + leg kinematics), what the
  step adjuster (biped_planner.step_adjuster, run by the reference generator) answers.

Frames: world x forward, y left, z up; a sole frame has its origin at the sole centre and z
along the sole normal. Wrenches are (fx, fy, fz, tx, ty, tz) in N and N m.
"""
