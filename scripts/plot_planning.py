#!/usr/bin/env python3
"""Draw the paper's planning figure for the START-GOAL example map (see --help)."""
import sys

from biped_tools.planning_figure import main

if __name__ == '__main__':
    sys.exit(main())
