"""The client against a real wiredem-server: the OpenAPI document, jobs, errors,
resumable downloads, live series and a study."""
from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import time
from pathlib import Path
from typing import Any, Dict, List

import numpy as np
import pytest

import wiredem
from conftest import ROOT, TINY, Server

SMALL = ROOT / "examples" / "small.json"


def _resolve(doc: Dict[str, Any], obj: Dict[str, Any]) -> Dict[str, Any]:
    """An OpenAPI object with its $ref followed (#/components/…)."""
    while "$ref" in obj:
        node: Any = doc
        for part in obj["$ref"].lstrip("#/").split("/"):
            node = node[part]
        obj = node
    return obj


def test_every_route_the_client_sends_is_served_with_its_parameters(server: Server) -> None:
    doc = server.client().openapi()
    assert doc["openapi"].startswith("3.")
    for name, route in wiredem.ROUTES.items():
        item = doc["paths"].get(route.path)
        assert item is not None, f"{name}: {route.path} is not in the served document"
        op = item.get(route.method.lower())
        assert op is not None, f"{name}: {route.method} {route.path} is not in the served document"
        assert op.get("operationId") == route.operation_id, name
        params = [_resolve(doc, p) for p in item.get("parameters", []) + op.get("parameters", [])]
        declared = {(p["in"], p["name"].lower() if p["in"] == "header" else p["name"]) for p in params}
        for q in route.query:
            assert ("query", q) in declared, f"{name}: query parameter {q} is not declared"
        for h in route.headers:
            assert ("header", h.lower()) in declared, f"{name}: header {h} is not declared"
        in_path = {p["name"] for p in params if p["in"] == "path"}
        assert set(re.findall(r"{(\w+)}", route.path)) == in_path, name


def test_the_client_sends_nothing_its_route_table_does_not_declare(server: Server) -> None:
    client = server.client()
    with pytest.raises(wiredem.WiredemError, match="takes no parameter"):
        client._send("getJob", path_params={"id": "0" * 24}, query={"verbose": 1})
    with pytest.raises(wiredem.WiredemError, match="sends no header"):
        client._send("getJob", path_params={"id": "0" * 24}, headers={"X-Other": "1"})
    assert client.sent == [], "a refused request must not have been counted as sent"


def test_a_submitted_job_is_waited_for_with_progress_and_succeeds(server: Server, tiny_job: Dict[str, Any]) -> None:
    client = server.client()
    seen: List[Dict[str, Any]] = []
    job = client.submit(json.loads(TINY.read_text()))
    assert job["state"] == "queued" and re.fullmatch(r"[0-9a-f]{24}", job["id"])
    done = client.wait(job["id"], interval_s=0.2, timeout_s=240, progress=seen.append)
    assert done["state"] == "succeeded"
    assert seen and seen[-1]["state"] == "succeeded"
    assert {j["state"] for j in seen} <= {"queued", "preparing", "running", "succeeded"}
    assert all(j["progress"] is None or 0.0 <= j["progress"] <= 1.0 for j in seen)
    assert job["id"] in [j["id"] for j in client.jobs(state="succeeded", all_pages=True)]
    one_by_one = [j["id"] for j in client.jobs(limit=1, all_pages=True)]  # following next_cursor (2 jobs or more)
    assert len(one_by_one) >= 2 and one_by_one == [j["id"] for j in client.jobs(limit=500)]
    assert len(client.jobs(limit=1)) == 1
    assert client.summary(job["id"])["name"] == "tiny"


def test_an_invalid_spec_raises_the_servers_error_with_the_field(server: Server) -> None:
    with pytest.raises(wiredem.ApiError) as e:
        server.client().submit({"seed": -1, "specimen": {"grain_count": 0}})
    err = e.value
    assert err.status == 400 and err.code == "invalid_job"
    fields = {d["field"] for d in err.details}
    assert {"seed", "specimen.grain_count"} <= fields, err.details
    assert "seed" in str(err) and "specimen.grain_count" in str(err)


def test_unknown_and_malformed_ids_raise_not_found_and_bad_id(server: Server) -> None:
    client = server.client()
    with pytest.raises(wiredem.ApiError) as e:
        client.job("0" * 24)
    assert (e.value.status, e.value.code) == (404, "not_found")
    with pytest.raises(wiredem.ApiError) as e:
        client.job("not-an-id")
    assert (e.value.status, e.value.code) == (400, "bad_id")


def test_an_unreachable_server_is_a_network_error() -> None:
    client = wiredem.Client("http://127.0.0.1:9", timeout_s=2)  # the discard port: nothing listens
    with pytest.raises(wiredem.NetworkError):
        client.health()


def test_a_cancelled_job_raises_on_wait_and_can_be_removed(server: Server) -> None:
    client = server.client()
    job = client.submit(SMALL)  # ~50 s of work: it cannot end before it is cancelled
    with pytest.raises(wiredem.ApiError) as e:
        client.summary(job["id"])
    assert (e.value.status, e.value.code) == (409, "not_succeeded")
    assert client.cancel(job["id"])["state"] == "cancelled"
    with pytest.raises(wiredem.JobCancelled):
        client.wait(job["id"], interval_s=0.1, timeout_s=30)
    assert client.wait(job["id"], check=False)["state"] == "cancelled"
    client.remove(job["id"])
    with pytest.raises(wiredem.ApiError) as e:
        client.job(job["id"])
    assert e.value.status == 404


def test_a_partial_download_resumes_from_its_size(server: Server, tiny_job: Dict[str, Any], tiny_dir: Path,
                                                  tmp_path: Path) -> None:
    whole = (tiny_dir / "result.h5").read_bytes()
    etag = (tiny_dir / "result.h5.etag").read_text().strip()
    target = tmp_path / "result.h5"
    (tmp_path / "result.h5.part").write_bytes(whole[: len(whole) // 3])
    (tmp_path / "result.h5.part.etag").write_text(etag + "\n")
    client = server.client()
    client.download_result(tiny_job["id"], target)
    assert target.read_bytes() == whole
    assert ("getJobResult", (), ("If-Range", "Range")) in client.sent  # it asked for the rest only
    assert not (tmp_path / "result.h5.part").exists()
    assert (tmp_path / "result.h5.etag").read_text().strip() == etag

    # complete, same ETag: only the HEAD
    client.sent.clear()
    client.download_result(tiny_job["id"], target)
    assert [s[0] for s in client.sent] == ["getJobResultHead"]


def test_a_partial_download_of_another_result_starts_over(server: Server, tiny_job: Dict[str, Any], tiny_dir: Path,
                                                          tmp_path: Path) -> None:
    whole = (tiny_dir / "result.h5").read_bytes()
    (tmp_path / "result.h5.part").write_bytes(b"x" * 1000)
    (tmp_path / "result.h5.part.etag").write_text('"another-result"\n')
    client = server.client()
    client.download_result(tiny_job["id"], tmp_path / "result.h5")
    assert (tmp_path / "result.h5").read_bytes() == whole
    assert ("getJobResult", (), ()) in client.sent


def test_the_served_series_are_the_files_series(server: Server, tiny_job: Dict[str, Any], tiny_dir: Path) -> None:
    client = server.client()
    result = wiredem.open(tiny_dir)
    listed = client.tests(tiny_job["id"])
    assert [t["name"] for t in listed["tests"]] == [t.name for t in result.tests]
    for test in result.tests:
        served = client.series(tiny_job["id"], test.name)
        local = test.series
        for column in served.columns:
            np.testing.assert_array_equal(served[column].to_numpy(), local[column].to_numpy(), err_msg=column)
            assert served.attrs["units"][column] == local.attrs["units"][column]
        few = client.series(tiny_job["id"], test.name, max_points=5, columns=["axial_strain", "stress_ratio"])
        assert list(few.columns) == ["axial_strain", "stress_ratio"] and len(few) == 5
        assert few.index[0] == 0 and few.index[-1] == len(local) - 1
        np.testing.assert_array_equal(few["stress_ratio"].to_numpy(), local["stress_ratio"].to_numpy()[few.index])


def test_the_wire_autocorrelation_of_a_column_without_wire_says_why_there_is_none(
        server: Server, tiny_job: Dict[str, Any]) -> None:
    reply = server.client().wire_autocorrelation(tiny_job["id"], "sigma3_20000", 2)
    assert reply["first_maximum_lag_m"] is None and reply["error"]


def test_a_study_is_one_tidy_frame_from_the_server_and_from_its_fetched_folder(server: Server,
                                                                               tmp_path: Path) -> None:
    client = server.client()
    base = json.loads(TINY.read_text())
    base["triaxial"]["target_axial_strain"] = 0.04  # half the loading: the frame's plumbing, not the physics
    base["triaxial"]["snapshot_strains"] = [0.04]
    study = client.submit_study({"name": "seeds", "base": base, "vary": {"seed": [1, 2]}})
    done = client.wait_study(study["id"], interval_s=0.2, timeout_s=240)
    assert done["jobs_by_state"]["succeeded"] == 2
    assert study["id"] in [s["id"] for s in client.studies(limit=1, all_pages=True)]
    fetched = wiredem.open_study(client.fetch_study(study["id"], tmp_path / "study"))
    served = client.study_results(study["id"])
    for s in (served, fetched):
        frame = s.tests()
        assert len(frame) == 4 and sorted(frame["seed"].unique()) == [1, 2]
        assert sorted(frame["confining_pressure_pa"].unique()) == [10000, 20000]
        for _, row in frame.iterrows():  # every figure as the point's own summary.json has it
            summary = s.point_summaries[row["point"]]
            t = next(t for t in summary["tests"] if t["confining_pressure_pa"] == row["confining_pressure_pa"])
            assert row["yield_stress_ratio"] == t["yield"]["stress_ratio"]
            assert row["max_q_deviatoric_stress_pa"] == t["peak_deviatoric_stress_pa"]
            assert row["friction_angle_deg"] == summary["mohr_coulomb"]["friction_angle_deg"]
        spread = s.spread()
        assert len(spread) == 1 and spread.loc[0, "friction_angle_deg_n"] == 2 and spread.loc[0, "succeeded"] == 2
        phis = frame.drop_duplicates("point")["friction_angle_deg"]
        assert spread.loc[0, "friction_angle_deg_mean"] == pytest.approx(phis.mean(), rel=1e-12)
        assert list(s.points()["state"]) == ["succeeded", "succeeded"]
    assert fetched.tests().equals(served.tests())
    point = fetched.result(1)
    assert point.job_spec["seed"] == 2 and point.mohr_coulomb.friction_angle_deg == \
        fetched.point_summaries[1]["mohr_coulomb"]["friction_angle_deg"]
    # An ended study is removed with its jobs; then it is gone.
    job_ids = [p["job_id"] for p in client.study_summary(study["id"])["points"]]
    assert len(job_ids) == 2
    client.remove_study(study["id"])
    for gone in [lambda: client.study(study["id"])] + [lambda j=j: client.job(j) for j in job_ids]:
        with pytest.raises(wiredem.ApiError) as e:
            gone()
        assert (e.value.status, e.value.code) == (404, "not_found")


def test_a_server_with_a_token_answers_the_client_that_sends_it(runner_bin: Path, tmp_path: Path) -> None:
    server_bin = os.environ.get("WIREDEM_SERVER_BIN") or str(ROOT / "build" / "release" / "bin" / "wiredem-server")
    token = tmp_path / "token"
    token.write_text("s3cret-token\n")
    token.chmod(0o600)
    port_file = tmp_path / "port"
    process = subprocess.Popen([server_bin, "--listen", "127.0.0.1:0", "--port-file", str(port_file), "--data-dir",
                                str(tmp_path / "data"), "--runner", str(runner_bin), "--token-file", str(token),
                                "--web-dir", "none", "--log-level", "error"])
    try:
        deadline = time.monotonic() + 30
        while not (port_file.is_file() and port_file.read_text().strip()):
            assert process.poll() is None and time.monotonic() < deadline, "the server did not start"
            time.sleep(0.05)
        url = f"http://127.0.0.1:{port_file.read_text().strip()}"
        with pytest.raises(wiredem.ApiError) as e:
            wiredem.Client(url).health()
        assert (e.value.status, e.value.code) == (401, "unauthorized")
        with pytest.raises(wiredem.ApiError) as e:
            wiredem.Client(url, token="wrong").jobs()
        assert e.value.status == 401
        assert wiredem.Client(url, token_file=token).health()["status"] == "ok"
        assert wiredem.Client(url, token="s3cret-token").jobs() == []
    finally:
        process.send_signal(signal.SIGTERM)
        process.wait(timeout=15)
