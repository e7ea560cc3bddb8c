"""The COMAN-like walk of the library closed loop (no ROS), as the probe and the closed-loop
benchmark set it up: reference parameters, step width and timing, start time, leg servo gain.

They are the values the library's closed-loop tests walk with; the node graph takes its own from
the nodes' config files.
"""
from biped_planner.step_timing import StepTiming
from biped_planner.walking_reference import ReferenceParams

COM_HEIGHT = 0.497   # m: the LIPM height, the robot's COM standing
REFERENCE = ReferenceParams(com_height=COM_HEIGHT, swing_height=0.04, foot_length=0.2,
                            foot_width=0.1)
STEP_WIDTH = 0.14    # m between the feet's centres
TIMING = StepTiming(single_support=0.4, double_support=0.2)
T_START = 0.5        # s standing before the first step
LEG_KP = 2000.0      # PyBulletConfig.leg_kp of the walks (N m / rad)
