"""The package installs offline beside Debian's packages, as docs/python.md says:
a virtual environment with the system's site packages, pip install --no-build-isolation."""
from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

from conftest import ROOT


def test_it_installs_offline_into_a_venv_over_debians_packages(tmp_path: Path) -> None:
    source = tmp_path / "src"  # a copy: building writes build/ and *.egg-info beside the sources
    shutil.copytree(ROOT / "python", source, ignore=shutil.ignore_patterns("__pycache__", "tests", "build",
                                                                           "*.egg-info"))
    venv = tmp_path / "venv"
    # without its own pip (ensurepip takes most of the time): the system's pip, seen through the
    # system site packages, installs into the environment it runs in
    subprocess.run([sys.executable, "-m", "venv", "--system-site-packages", "--without-pip", str(venv)], check=True,
                   timeout=120)
    run = subprocess.run([str(venv / "bin" / "python"), "-m", "pip", "install", "--no-build-isolation", "--no-index",
                          str(source)],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stdout + run.stderr
    check = subprocess.run([str(venv / "bin" / "python"), "-c",
                            "import wiredem, wiredem.plots, pathlib; print(pathlib.Path(wiredem.__file__).parent)"],
                           capture_output=True, text=True, cwd=tmp_path, env={"PATH": "/usr/bin:/bin"}, timeout=60)
    assert check.returncode == 0, check.stderr
    installed = Path(check.stdout.strip())
    assert installed.is_relative_to(venv) and (installed / "py.typed").is_file()
    assert {p.name for p in (ROOT / "python" / "wiredem").glob("*.py")} <= {p.name for p in installed.glob("*.py")}
