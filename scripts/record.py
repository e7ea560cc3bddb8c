#!/usr/bin/env python3
"""Record topics into a rosbag2 directory, like `ros2 bag record` (see --help)."""
import sys

from biped_tools.recording.command import main

if __name__ == '__main__':
    sys.exit(main())
