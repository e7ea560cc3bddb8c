#!/usr/bin/env python3
"""Run several nodes of the graph in one process (see biped_tools.node_container)."""
import sys

from biped_tools.node_container import main

if __name__ == '__main__':
    sys.exit(main())
