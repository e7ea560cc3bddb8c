#!/usr/bin/env python3
"""The main job: the humanoid walks START -> GOAL through the node graph (see --help)."""
import sys

from biped_tools.demo import main

if __name__ == '__main__':
    sys.exit(main())
