#!/usr/bin/env bash
# Quick start, command 1: set up (first run only) and run the main job headless, with plots.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$ROOT/scripts/setup.sh"
export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
exec "$ROOT/.venv/bin/python" "$ROOT/scripts/demo.py" "$@"
