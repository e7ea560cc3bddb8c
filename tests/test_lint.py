"""The tree passes ruff with the project's ruff.toml (undefined or unused names, syntax errors,
lines over 100 columns), so a slip shows in CI instead of in a later session."""
from pathlib import Path
import subprocess
import sys

ROOT = Path(__file__).resolve().parent.parent


def test_ruff_finds_nothing_in_the_tree():
    result = subprocess.run([sys.executable, '-m', 'ruff', 'check', '--no-cache',
                             '--output-format', 'concise', str(ROOT)],
                            cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert result.returncode == 0, result.stdout + result.stderr
