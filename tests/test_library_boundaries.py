"""Library modules never import rclpy or message packages (CONVENTIONS: libraries first)."""
import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parent.parent / 'ros2_ws' / 'src'
FORBIDDEN = ('rclpy', 'rcl_interfaces', 'rosidl', 'rosidl_runtime_py', 'builtin_interfaces')
LIBRARY_MODULES = sorted(
    path for package in ('biped_planner', 'biped_mpc', 'biped_sim')
    for path in (SRC / package / package).glob('*.py'))


def imported_roots(path: Path):
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name.split('.')[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.module.split('.')[0]


def test_there_are_library_modules_to_check():
    assert len(LIBRARY_MODULES) >= 3


@pytest.mark.parametrize('path', LIBRARY_MODULES, ids=lambda p: f'{p.parent.name}/{p.name}')
def test_library_module_imports_no_ros(path):
    bad = sorted(root for root in set(imported_roots(path))
                 if root in FORBIDDEN or root.endswith(('_msgs', '_srvs', '_interfaces')))
    assert not bad, f'{path} imports {bad}; move that code to {path.parent.name}/nodes/'
