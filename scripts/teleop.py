#!/usr/bin/env python3
"""Keyboard teleop on cmd_vel, like teleop_twist_keyboard (see --help)."""
import sys

from biped_tools.teleop import main

if __name__ == '__main__':
    sys.exit(main())
