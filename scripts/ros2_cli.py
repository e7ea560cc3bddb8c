#!/usr/bin/env python3
"""A stand-in for `ros2 topic pub/echo` and `ros2 service call` (see --help)."""
import sys

from biped_tools.ros2_cli import main

if __name__ == '__main__':
    sys.exit(main())
