"""The package rules of CONVENTIONS: libraries without ROS, dependencies one way, plumbing shared.

- Library modules never import rclpy or message packages (libraries first).
- Packages depend one way, biped_planner <- biped_mpc <- biped_sim: a package imports only
  itself and the packages before it in that order.
- No code imports another package's `nodes` modules; shared node plumbing lives in the public
  biped_planner.node_support, which library modules never import.
- Every biped package a package imports is declared in its package.xml.
"""
import ast
from pathlib import Path
import xml.etree.ElementTree as ElementTree

import pytest

ROOT = Path(__file__).resolve().parent.parent
SRC = ROOT / 'ros2_ws' / 'src'
ORDER = ('biped_planner', 'biped_mpc', 'biped_sim')
FORBIDDEN = ('rclpy', 'rcl_interfaces', 'rosidl', 'rosidl_runtime_py', 'builtin_interfaces')
ROS_PARTS = ('nodes', 'node_support')


def python_files(package: str):
    return sorted((SRC / package / package).rglob('*.py'))


def is_library(path: Path) -> bool:
    return not any(part in ROS_PARTS for part in path.parts)


LIBRARY_MODULES = [p for package in ORDER for p in python_files(package) if is_library(p)]
ALL_MODULES = [(package, p) for package in ORDER for p in python_files(package)]


def imported_modules(path: Path):
    tree = ast.parse(path.read_text(), filename=str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            yield from (alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.module


def test_there_are_library_modules_to_check():
    assert len(LIBRARY_MODULES) >= 30


@pytest.mark.parametrize('path', LIBRARY_MODULES, ids=lambda p: str(p.relative_to(SRC)))
def test_library_module_imports_no_ros(path):
    bad = sorted(name for name in set(imported_modules(path))
                 if name.split('.')[0] in FORBIDDEN
                 or name.split('.')[0].endswith(('_msgs', '_srvs', '_interfaces'))
                 or '.node_support' in name or '.nodes' in name)
    assert not bad, f'{path} imports {bad}; move that code to a nodes/ module'


@pytest.mark.parametrize('package, path', ALL_MODULES,
                         ids=lambda v: str(v.relative_to(SRC)) if isinstance(v, Path) else v)
def test_package_dependencies_run_one_way(package, path):
    allowed = ORDER[:ORDER.index(package) + 1]
    bad = sorted(name for name in set(imported_modules(path))
                 if name.split('.')[0] in ORDER and name.split('.')[0] not in allowed)
    assert not bad, f'{path} imports {bad}: {package} may use only {allowed}'


@pytest.mark.parametrize('package, path', ALL_MODULES,
                         ids=lambda v: str(v.relative_to(SRC)) if isinstance(v, Path) else v)
def test_no_module_imports_another_packages_nodes(package, path):
    bad = sorted(name for name in set(imported_modules(path))
                 if name.split('.')[0] != package and '.nodes' in name)
    assert not bad, f'{path} imports {bad}: share it through biped_planner.node_support'


@pytest.mark.parametrize('package', ORDER)
def test_package_xml_declares_every_biped_package_used(package):
    used = {name.split('.')[0] for path in python_files(package)
            for name in imported_modules(path)}
    used = {name for name in used if name.startswith('biped_') and name != package}
    tree = ElementTree.parse(SRC / package / 'package.xml')
    declared = {element.text for element in tree.getroot()
                if element.tag in ('depend', 'exec_depend')}
    assert used <= declared, f'{package}/package.xml lacks {sorted(used - declared)}'


def test_no_script_edits_sys_path():
    offenders = [str(p.relative_to(ROOT)) for folder in ('scripts', 'tests')
                 for p in (ROOT / folder).rglob('*.py') if 'sys.path.' + 'insert' in p.read_text()]
    assert not offenders, f'these edit sys.path instead of importing the tools package: {offenders}'
