#!/usr/bin/env bash
# Quick start, command 2: set up (first run only) and run every test, two workers in parallel.
# Each worker gets its own ROS_DOMAIN_ID (tests/ros_harness.py); discovery stays on localhost.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$ROOT/scripts/setup.sh"
export ROS_AUTOMATIC_DISCOVERY_RANGE=LOCALHOST
cd "$ROOT"
exec "$ROOT/.venv/bin/python" -m pytest -n 2 -p no:warnings "$@"
