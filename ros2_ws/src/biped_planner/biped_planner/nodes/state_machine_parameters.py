"""The state machine node's own parameters (those of its libraries come from their dataclasses),
each with its default, description and range."""

NODE_PARAMETERS = {
    'publish_rate': (50.0, 'walking_state messages per second besides transitions (Hz)',
                     (0.1, 1000.0)),
    'update_rate': (200.0, 'timer checking phase ends (Hz)', (1.0, 10000.0)),
    'fall_detection': (True, 'detect and report falls', None),
    'map_frame': ('map', 'the frame of goals (goal_pose, GOTO)', None),
    'odom_frame': ('map', 'the frame of odom (the simulator\'s frame_id)', None),
    'cmd_vel_timeout': (0.5, 'a walk driven by cmd_vel stops when no cmd_vel came for '
                        'this long, on the clock and in wall time (s)', (0.05, 60.0)),
    'input_timeout': (0.5, 'an input silent this long, on the clock and in wall time, '
                      'is reported in stale_inputs (s)', (0.05, 60.0)),
    'use_planner': (True, 'walks are planned by the footstep planner (plan_walk), '
                    'which a request waits for up to planner_timeout; false: START, '
                    'OMNI and cmd_vel walk in place and GOTO is refused', None),
    'planner_timeout': (10.0, 'wall time within which plan_walk must answer (s)',
                        (0.1, 60.0)),
    'reset_timeout': (5.0, 'wall time within which simulator/reset must answer (s)',
                      (0.1, 60.0)),
    'max_stamp_ahead': (0.2, 'odom stamped this far ahead of the clock is refused (s)',
                        (0.0, 10.0))}
READ_ONLY = ('publish_rate', 'update_rate', 'map_frame', 'odom_frame', 'use_planner')
