"""Make the ROS 2 Jazzy wheels' CMake files usable in this venv (idempotent).

The wheels export CMake targets that name the include directories of the container they were built
in (/opt/python/cp311-cp311/...). CMake refuses imported targets with non-existent paths, so a
rosidl package (biped_msgs) does not build until those paths name this venv's Python and numpy.
"""
import pathlib
import sys
import sysconfig

import numpy

BUILD_PREFIX = '/opt/python/cp311-cp311'
REPLACEMENTS = {
    f'{BUILD_PREFIX}/include/python3.11': sysconfig.get_paths()['include'],
    f'{BUILD_PREFIX}/lib/python3.11/site-packages/numpy/_core/include': numpy.get_include(),
}


def main() -> int:
    share = pathlib.Path(sys.prefix) / 'share'
    patched = 0
    for cmake_file in share.rglob('*.cmake'):
        text = cmake_file.read_text()
        if BUILD_PREFIX not in text:
            continue
        for old, new in REPLACEMENTS.items():
            text = text.replace(old, new)
        cmake_file.write_text(text)
        patched += 1
    if not pathlib.Path(REPLACEMENTS[f'{BUILD_PREFIX}/include/python3.11']).joinpath(
            'Python.h').exists():
        print('error: Python headers not found; install python3-dev', file=sys.stderr)
        return 1
    print(f'patched {patched} CMake files of the ROS wheels')
    return 0


if __name__ == '__main__':
    sys.exit(main())
