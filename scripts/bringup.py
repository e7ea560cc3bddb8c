#!/usr/bin/env python3
"""Bring up the biped node graph, one process per node (see --help)."""
import sys

from biped_tools.bringup import main

if __name__ == '__main__':
    sys.exit(main())
