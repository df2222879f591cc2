"""The package installs offline with Debian's setuptools (pip install --no-build-isolation ./python)."""
from __future__ import annotations

import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

from conftest import ROOT


def test_a_wheel_builds_offline_and_holds_the_package(tmp_path: Path) -> None:
    source = tmp_path / "src"  # a copy: building writes build/ and *.egg-info beside the sources
    shutil.copytree(ROOT / "python", source, ignore=shutil.ignore_patterns("__pycache__", "tests", "build",
                                                                           "*.egg-info"))
    run = subprocess.run([sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "--no-index",
                          "--wheel-dir", str(tmp_path / "dist"), str(source)], capture_output=True, text=True,
                         timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    wheel = next((tmp_path / "dist").glob("wiredem-*.whl"))
    names = set(zipfile.ZipFile(wheel).namelist())
    expected = {f"wiredem/{p.name}" for p in (ROOT / "python" / "wiredem").glob("*.py")} | {"wiredem/py.typed"}
    assert expected <= names, expected - names
