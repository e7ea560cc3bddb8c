#!/usr/bin/env bash
# One idempotent setup step: .venv with pinned dependencies, the ROS wheels' CMake files patched,
# the colcon workspace built, a .pth that makes the workspace importable without sourcing, and the
# scripts' package biped_tools linked into the venv.
# Each stage runs only when its inputs changed, so a second run takes a few seconds.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
VENV="$ROOT/.venv"
WS="$ROOT/ros2_ws"
STAMPS="$VENV/.biped_stamps"
log() { echo "[setup] $*"; }

find_python() {
  for candidate in "${PYTHON:-}" python3.11 python3; do
    [ -n "$candidate" ] || continue
    if command -v "$candidate" >/dev/null 2>&1 &&
       "$candidate" -c 'import sys; sys.exit(sys.version_info[:2] != (3, 11))' 2>/dev/null; then
      command -v "$candidate"; return 0
    fi
  done
  return 1
}

# System tools the build needs (Debian 12 names); installed only when missing and we are root.
need_apt=()
command -v cmake >/dev/null 2>&1 || need_apt+=(cmake)
command -v g++ >/dev/null 2>&1 || need_apt+=(g++)
PY=$(find_python) || need_apt+=(python3 python3-dev python3-venv)
if [ -n "$PY" ] && ! "$PY" -c 'import ensurepip, venv' 2>/dev/null; then need_apt+=(python3-venv); fi
if [ ${#need_apt[@]} -gt 0 ]; then
  if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null; then
    log "installing system packages: ${need_apt[*]}"
    apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need_apt[@]}" >/dev/null
    PY=$(find_python)
  else
    echo "[setup] error: missing ${need_apt[*]} (Python 3.11, cmake, g++); install them first" >&2
    exit 1
  fi
fi

# 1. venv and pinned Python dependencies
if [ ! -x "$VENV/bin/python" ]; then
  log "creating $VENV with $PY"
  "$PY" -m venv "$VENV"
fi
mkdir -p "$STAMPS"
req_hash=$(cat "$ROOT/requirements.txt" "$ROOT/constraints.txt" | sha1sum | cut -d' ' -f1)
if [ "$(cat "$STAMPS/requirements" 2>/dev/null)" != "$req_hash" ]; then
  log "installing Python dependencies (first time: a few minutes)"
  "$VENV/bin/python" -m pip install -q --disable-pip-version-check --upgrade pip
  "$VENV/bin/python" -m pip install -q --disable-pip-version-check \
    -r "$ROOT/requirements.txt" -c "$ROOT/constraints.txt"
  "$VENV/bin/python" "$ROOT/scripts/setup/patch_ros_wheels.py"
  echo "$req_hash" > "$STAMPS/requirements"
  rm -f "$STAMPS/build"
fi
# Optional extras, e.g. BIPED_EXTRAS=robots: other humanoids (example-robot-data, 440 MB).
for extra in ${BIPED_EXTRAS:-}; do
  file="$ROOT/requirements-$extra.txt"
  [ -f "$file" ] || { echo "[setup] error: no $file for BIPED_EXTRAS=$extra" >&2; exit 1; }
  extra_hash=$(sha1sum "$file" | cut -d' ' -f1)
  if [ "$(cat "$STAMPS/extra-$extra" 2>/dev/null)" != "$extra_hash" ]; then
    log "installing the $extra extra"
    "$VENV/bin/python" -m pip install -q --disable-pip-version-check -r "$file"
    echo "$extra_hash" > "$STAMPS/extra-$extra"
  fi
done

# 2. colcon build (symlinked Python sources: editing a .py file needs no rebuild)
src_hash=$( (cd "$WS/src" && find . -type f ! -name '*.pyc' ! -path '*/__pycache__/*' \
  \( ! -name '*.py' -o -name setup.py \) | LC_ALL=C sort | xargs sha1sum) | sha1sum | cut -d' ' -f1)
if [ "$(cat "$STAMPS/build" 2>/dev/null)" != "$src_hash" ] || [ ! -d "$WS/install" ]; then
  log "building the colcon workspace"
  (
    cd "$WS"
    export AMENT_PREFIX_PATH="$VENV" CMAKE_PREFIX_PATH="$VENV" PATH="$VENV/bin:$PATH"
    unset PYTHONPATH
    "$VENV/bin/colcon" --log-base "$WS/log" build --symlink-install \
      --event-handlers console_direct- summary+ \
      --cmake-args -DPython3_EXECUTABLE="$VENV/bin/python" -DBUILD_TESTING=OFF
  )
  echo "$src_hash" > "$STAMPS/build"
fi

# 3. the workspace environment, loaded by every Python start in the venv
site_packages=$("$VENV/bin/python" -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')
packages=$(cd "$WS/src" && ls -d */ | tr -d / | sed "s/.*/'&'/" | paste -sd, -)
sed -e "s|@INSTALL@|$WS/install|" -e "s|@PACKAGES@|[$packages]|" \
  "$ROOT/scripts/setup/workspace_env.py.in" > "$site_packages/biped_stack_env.py"
# Sorts before ros_wheels_bootstrapper.pth, which re-executes Python with the library path.
echo 'import biped_stack_env' > "$site_packages/biped_stack_env.pth"
# The scripts' shared package, linked like an editable install: `import biped_tools` works in
# every Python of the venv, and only that name is added (not every script in scripts/).
ln -sfn "$ROOT/scripts/biped_tools" "$site_packages/biped_tools"
log "ready: $VENV/bin/python has rclpy, biped_msgs, the biped packages and biped_tools"
