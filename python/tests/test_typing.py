"""The package's annotations hold (mypy, Debian's python3-mypy)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from conftest import ROOT


def test_the_annotations_type_check(tmp_path: Path) -> None:
    run = subprocess.run([sys.executable, "-m", "mypy", "--ignore-missing-imports", "--check-untyped-defs",
                          "--cache-dir", str(tmp_path / "cache"), "wiredem"], cwd=ROOT / "python",
                         capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stdout + run.stderr
