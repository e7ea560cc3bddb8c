#!/usr/bin/env python3
"""The paper's COMAN experiments through the node graph (see --help)."""
import sys

from biped_tools.scenarios.command import main

if __name__ == '__main__':
    sys.exit(main())
