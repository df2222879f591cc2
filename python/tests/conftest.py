"""Fixtures of the wiredem package's tests: a real wiredem-server and a real job.

The binaries come from $WIREDEM_SERVER_BIN and $WIREDEM_BIN (ctest passes the
built ones: tests/CMakeLists.txt), else build/release/bin of the repository.
The server listens on a free loopback port (--listen 127.0.0.1:0, --port-file)
with its own temporary data directory, runs one job at a time, and is stopped
with SIGTERM at the end of the session. The tiny job (examples/tiny.json: 150
grains, two pressures, ~7 s in Release) runs once per session and is fetched
once; the tests read that download.
"""
from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any, Dict, Iterator

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "python"))  # usable from the source tree

import wiredem  # noqa: E402

TINY = ROOT / "examples" / "tiny.json"


def _binary(env: str, name: str) -> Path:
    given = os.environ.get(env)
    path = Path(given) if given else ROOT / "build" / "release" / "bin" / name
    if not path.is_file():
        if given:  # asked for explicitly (ctest): a missing binary is a failure, not a skip
            raise FileNotFoundError(f"${env} = {given}: no such file")
        pytest.skip(f"no {name} (build it, or set ${env})")
    return path


class Server:
    """A running wiredem-server: its URL, data directory and process."""

    def __init__(self, process: "subprocess.Popen[bytes]", url: str, data_dir: Path, log: Path) -> None:
        self.process, self.url, self.data_dir, self.log = process, url, data_dir, log

    def client(self) -> wiredem.Client:
        return wiredem.Client(self.url, timeout_s=30)


@pytest.fixture(scope="session")
def runner_bin() -> Path:
    return _binary("WIREDEM_BIN", "wiredem")


@pytest.fixture(scope="session")
def server(tmp_path_factory: pytest.TempPathFactory, runner_bin: Path) -> Iterator[Server]:
    server_bin = _binary("WIREDEM_SERVER_BIN", "wiredem-server")
    base = tmp_path_factory.mktemp("server")
    data_dir, port_file, log = base / "data", base / "port", base / "server.log"
    with open(log, "wb") as out:
        process = subprocess.Popen([str(server_bin), "--listen", "127.0.0.1:0", "--port-file", str(port_file),
                                    "--data-dir", str(data_dir), "--runner", str(runner_bin), "--jobs", "1",
                                    "--web-dir", "none", "--log-level", "warn"],
                                   stdout=out, stderr=subprocess.STDOUT)
    try:
        deadline = time.monotonic() + 30
        while not (port_file.is_file() and port_file.read_text().strip()):
            if process.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError(f"wiredem-server did not start: {log.read_text()}")
            time.sleep(0.05)
        s = Server(process, f"http://127.0.0.1:{port_file.read_text().strip()}", data_dir, log)
        assert s.client().health()["status"] == "ok"
        yield s
    finally:
        process.send_signal(signal.SIGTERM)
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()


@pytest.fixture(scope="session")
def tiny_job(server: Server) -> Dict[str, Any]:
    """examples/tiny.json, submitted and waited for: its final job document."""
    client = server.client()
    job = client.submit(TINY)
    return client.wait(job["id"], interval_s=0.2, timeout_s=240)


@pytest.fixture(scope="session")
def tiny_dir(server: Server, tiny_job: Dict[str, Any], tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The tiny job fetched: a folder with summary.json and result.h5."""
    return server.client().fetch(tiny_job["id"], tmp_path_factory.mktemp("tiny") / "out")


@pytest.fixture()
def bare_h5(tiny_dir: Path, tmp_path: Path) -> Path:
    """The tiny job's result.h5 alone in a folder (no summary.json)."""
    dst = tmp_path / "bare" / "result.h5"
    dst.parent.mkdir()
    shutil.copyfile(tiny_dir / "result.h5", dst)
    return dst
