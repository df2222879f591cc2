"""The worked example (examples/python/stress_ratio.py) runs against a real server."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

from conftest import ROOT, Server


def test_the_worked_example_submits_waits_and_plots(server: Server, tmp_path: Path) -> None:
    out = tmp_path / "stress_ratio.png"
    env = dict(os.environ, PYTHONPATH=str(ROOT / "python"))
    run = subprocess.run([sys.executable, str(ROOT / "examples" / "python" / "stress_ratio.py"), "--server",
                          server.url, "--out", str(out)], env=env, capture_output=True, text=True, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "succeeded" in run.stdout and "φ =" in run.stdout
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
