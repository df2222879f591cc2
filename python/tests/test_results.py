"""Reading result.h5 and summary.json (docs/results.md) of a real job."""
from __future__ import annotations

import json
import math
import shutil
import subprocess
from pathlib import Path
from typing import Any, Dict

import h5py
import numpy as np
import pytest

import wiredem
from conftest import TINY, Server


def test_a_folder_and_its_result_file_open_alike(tiny_dir: Path) -> None:
    a, b = wiredem.open(tiny_dir), wiredem.open(str(tiny_dir / "result.h5"))
    assert a.format == "wiredem-result-1" and a.name == "tiny"
    assert [t.name for t in a.tests] == [t.name for t in b.tests] == ["sigma3_10000", "sigma3_20000"]
    assert a.summary == b.summary == json.loads((tiny_dir / "summary.json").read_text())
    assert a.job_spec["triaxial"]["confining_pressures_pa"] == [10000, 20000]


def test_the_runners_own_job_folder_opens(server: Server, tiny_job: Dict[str, Any]) -> None:
    r = wiredem.open(server.data_dir / "jobs" / tiny_job["id"])
    assert r.summary is not None and len(r.tests) == 2


def test_a_local_run_folder_opens_with_the_figures_of_the_served_job(runner_bin: Path, tiny_dir: Path,
                                                                    tmp_path: Path) -> None:
    out = tmp_path / "run"
    subprocess.run([str(runner_bin), "run", str(TINY), "-o", str(out), "--threads", "1"], check=True,
                   capture_output=True, timeout=300)
    local, served = wiredem.open(out), wiredem.open(tiny_dir)
    # the engine is deterministic for any thread count: the same states, fits and curves
    assert local.mohr_coulomb == served.mohr_coulomb
    for a, b in zip(local.tests, served.tests):
        assert a.yield_state == b.yield_state
        assert a.series.equals(b.series)


def test_each_series_holds_every_dataset_of_its_group_with_its_units(tiny_dir: Path) -> None:
    r = wiredem.open(tiny_dir)
    with h5py.File(tiny_dir / "result.h5", "r") as f:
        for t in r.tests:
            g = f["tests"][t.name]
            datasets = {k for k in g if isinstance(g[k], h5py.Dataset)}
            s = t.series
            assert set(s.columns) == datasets
            assert len(s) == g["time_s"].shape[0]
            for k in datasets:
                np.testing.assert_array_equal(s[k].to_numpy(), g[k][()])
                units = g[k].attrs["units"]
                assert s.attrs["units"][k] == (units.decode() if isinstance(units, bytes) else units)
    s = r.tests[0].series
    assert s.attrs["units"]["sigma1_pa"] == "Pa" and s.attrs["units"]["stress_ratio"] == "1"
    assert s.attrs["units"]["time_s"] == "s"


def test_the_loading_rows_are_phase_two_and_follow_the_hold(tiny_dir: Path) -> None:
    for t in wiredem.open(tiny_dir).tests:
        s, loading = t.series, t.loading
        assert len(loading) > 10 and (loading["phase"] == wiredem.LOADING).all()
        assert set(s["phase"].unique()) == {0, 1, 2}
        assert loading.index[0] > s.index[s["phase"] == 1][-1]
        assert loading.attrs["units"] == s.attrs["units"]
        c = t.curve()
        assert list(c.columns) == ["axial_strain", "stress_ratio"] and c.attrs["units"]["stress_ratio"] == "1"


def test_states_and_fits_are_the_summarys(tiny_dir: Path) -> None:
    r = wiredem.open(tiny_dir)
    summary = json.loads((tiny_dir / "summary.json").read_text())
    for t, st in zip(r.tests, summary["tests"]):
        assert t.confining_pressure_pa == st["confining_pressure_pa"]
        assert t.yield_state == st["yield"]
        assert t.max_q_state["deviatoric_stress_pa"] == st["peak_deviatoric_stress_pa"]
        assert t.max_q_state["axial_strain"] == st["peak_axial_strain"]
        assert t.residual_stress_ratio == st["residual_stress_ratio"]
        assert t.quasi_static == st["quasi_static"]
    for fit, key in ((r.mohr_coulomb, "mohr_coulomb"), (r.mohr_coulomb_max_q, "mohr_coulomb_max_q")):
        assert fit.friction_angle_deg == summary[key]["friction_angle_deg"]
        assert fit.cohesion_pa == summary[key]["cohesion_pa"]
        assert fit.r_squared == summary[key]["r_squared"]
        assert fit.raw == summary[key]
    frame = r.tests_frame()
    assert list(frame.index) == ["sigma3_10000", "sigma3_20000"]
    assert list(frame["yield_stress_ratio"]) == [st["yield"]["stress_ratio"] for st in summary["tests"]]
    assert r.warnings == summary["warnings"]
    curves = r.stress_ratio_curves()
    assert list(curves) == [10000.0, 20000.0]
    for p, c in curves.items():
        assert c.equals(r.test(p).curve("stress_ratio"))
        assert c.attrs["units"] == {"axial_strain": "1", "stress_ratio": "1"}


def test_the_envelope_passes_the_fitted_cohesion_at_zero_stress(tiny_dir: Path) -> None:
    fit = wiredem.open(tiny_dir).mohr_coulomb
    assert fit.shear_stress_pa(0.0) == pytest.approx(fit.cohesion_pa)
    # τ rises by tan φ per unit of σ
    assert fit.shear_stress_pa(1e5) - fit.shear_stress_pa(0.0) == \
        pytest.approx(1e5 * math.tan(math.radians(fit.friction_angle_deg)), rel=1e-12)


def test_a_bare_result_file_reads_the_states_from_its_attributes(tiny_dir: Path, bare_h5: Path) -> None:
    with_summary, bare = wiredem.open(tiny_dir), wiredem.open(bare_h5)
    assert bare.summary is None
    for a, b in zip(with_summary.tests, bare.tests):
        # the same numbers the runner wrote into both files
        assert b.yield_state["stress_ratio"] == a.yield_state["stress_ratio"]
        assert b.yield_state["axial_strain"] == a.yield_state["axial_strain"]
        assert b.yield_state["sigma1_pa"] == a.yield_state["sigma1_pa"]
        assert b.yield_state["shape"] == a.yield_state["shape"]
        assert b.residual_stress_ratio == a.residual_stress_ratio
    with pytest.raises(wiredem.ResultError, match="summary.json"):
        bare.mohr_coulomb


def test_the_specimen_arrays_match_the_summary(tiny_dir: Path) -> None:
    r = wiredem.open(tiny_dir)
    sp, summary = r.specimen, r.summary["specimen"]
    assert sp.grain_position_m.shape == (summary["grains"], 3)
    assert sp.grain_radius_m.shape == (summary["grains"],) and (sp.grain_radius_m > 0).all()
    assert sp.wire_node_position_m.shape == (0, 3)  # tiny has no wire
    assert sp.membrane_node_position_m.shape[1] == 3
    assert sp.units("grain_position_m") == "m"
    assert sp.attributes["grains"] == summary["grains"]
    radius = r.job_spec["specimen"]["membrane_radius_m"]
    assert (np.hypot(sp.grain_position_m[:, 0], sp.grain_position_m[:, 1]) < radius).all()
    g = sp.grains()
    assert list(g.columns) == ["x_m", "y_m", "z_m", "radius_m"] and len(g) == summary["grains"]


def test_snapshots_and_the_force_network(tiny_dir: Path) -> None:
    r = wiredem.open(tiny_dir)
    grains = r.summary["specimen"]["grains"]
    for t in r.tests:
        assert [s.requested_axial_strain for s in t.snapshots] == [0, 0.04, 0.08]
        strains = [s.axial_strain for s in t.snapshots]
        assert strains == sorted(strains)
        last = t.snapshots[-1]
        assert t.snapshot_near(0.079) is last
        net = last.force_network()
        assert len(net) == last.array("contact_bodies").shape[0] > 0
        assert set(net["kind_a"]).union(net["kind_b"]) <= {0, 1, 2}
        assert (net.loc[net["kind_a"] == 0, "index_a"] < grains).all()
        assert (net["normal_force_n"] >= 0).all()  # the normal force never attracts
        assert net.attrs["units"]["normal_force_n"] == "N"
        walls = last.wall_contacts()
        assert len(walls) > 0 and set(walls["kind"]) <= {0, 1, 2}
        assert last.body_positions_m()[0].shape == (grains, 3)


def test_what_is_not_a_result_is_refused_with_the_reason(tmp_path: Path) -> None:
    with pytest.raises(wiredem.ResultError, match="no such file"):
        wiredem.open(tmp_path / "nothing")
    with pytest.raises(wiredem.ResultError, match="no result.h5"):
        wiredem.open(tmp_path)
    (tmp_path / "tests").mkdir()
    with pytest.raises(wiredem.ResultError, match="wiredem analyse"):
        wiredem.open(tmp_path)
    other = tmp_path / "other.h5"
    with h5py.File(other, "w") as f:
        f["x"] = np.zeros(3)
    with pytest.raises(wiredem.ResultError, match="not a wiredem result"):
        wiredem.open(other)
    text = tmp_path / "text.h5"
    text.write_text("not hdf5")
    with pytest.raises(wiredem.ResultError, match="not an HDF5 file"):
        wiredem.open(text)


def test_with_fields_sets_dotted_paths_on_a_copy() -> None:
    base = {"name": "a", "triaxial": {"confining_pressures_pa": [1]}}
    spec = wiredem.with_fields(base, {"triaxial.confining_pressures_pa": [20000], "specimen.wire.pattern": "helix"},
                               seed=3)
    assert spec == {"name": "a", "triaxial": {"confining_pressures_pa": [20000]},
                    "specimen": {"wire": {"pattern": "helix"}}, "seed": 3}
    assert base["triaxial"]["confining_pressures_pa"] == [1]


def test_a_files_wire_autocorrelation_is_the_servers(server: Server, tiny_job: Dict[str, Any], tiny_dir: Path,
                                                      runner_bin: Path) -> None:
    client = server.client()
    for t in wiredem.open(tiny_dir).tests:
        for s in t.snapshots:
            assert s.wire_autocorrelation(runner_bin) == client.wire_autocorrelation(tiny_job["id"], t.name, s.index)


def test_the_autocorrelation_of_a_sine_peaks_at_its_period(tiny_dir: Path, tmp_path: Path, runner_bin: Path) -> None:
    """x_t = sin(a t), a = 2π/P, N a multiple of P (mean 0, variance 1/2): with the engine's
    R(k) = Σ_{t<N−k} x_t x_{t+k} / ((N − k) s²) = cos(a k) − Σ_{t<N−k} cos(a (2t + k)) / (N − k),
    and |Σ_{t<M} cos(a (2t + k))| = |sin(a M) cos(a (M − 1 + k))| / |sin a| ≤ 1/|sin a|; so R(0) = 1,
    |R(k) − cos(a k)| ≤ 1/((N − k) |sin a|), and the first maximum after 0 is at k = P."""
    path = tmp_path / "result.h5"
    shutil.copyfile(tiny_dir / "result.h5", path)
    period, segments = 40, 400
    with h5py.File(path, "r+") as f:
        snap = f["tests/sigma3_20000/snapshots/snapshot_2"]
        del snap["wire_segment_strain"]
        snap["wire_segment_strain"] = 1e-3 * np.sin(2 * np.pi * np.arange(segments) / period)
    r = wiredem.open(path)
    seg = r.job_spec["specimen"]["wire"]["segment_length_m"]
    reply = r.test(20000).snapshots[-1].wire_autocorrelation(runner_bin)
    assert reply["error"] is None and reply["segments"] == segments
    assert reply["coefficients"][0] == pytest.approx(1.0, abs=1e-12)
    a, k = 2 * np.pi / period, np.arange(segments // 2)
    bound = 1 / ((segments - k) * abs(np.sin(a))) + 1e-12
    assert (np.abs(np.array(reply["coefficients"][: segments // 2]) - np.cos(a * k)) <= bound).all()
    assert reply["first_maximum_lag_m"] == pytest.approx(period * seg, rel=1e-12)
    assert reply["prominent_maximum_lag_m"] == pytest.approx(period * seg, rel=1e-12)
    with pytest.raises(wiredem.ResultError, match="no wiredem binary"):
        r.test(20000).snapshots[-1].wire_autocorrelation(tmp_path / "no-such-binary")


def test_the_autocorrelation_command_names_what_the_file_does_not_hold(tiny_dir: Path, runner_bin: Path) -> None:
    h5 = str(tiny_dir / "result.h5")
    for args, code, message in ((["--snapshot", "99"], 9, "has no snapshot 99"), (["--test", "sigma3_1"], 9, "has no test"),
                                (["--snapshot", "-1"], 2, "0 or more")):
        run = subprocess.run([str(runner_bin), "autocorrelation", h5, *args], capture_output=True, text=True)
        assert run.returncode == code and message in run.stderr, (args, run.returncode, run.stderr)
    default = subprocess.run([str(runner_bin), "autocorrelation", h5], capture_output=True, text=True, check=True)
    last = wiredem.open(tiny_dir).tests[-1].snapshots[-1]
    assert json.loads(default.stdout) == last.wire_autocorrelation(runner_bin)  # the highest pressure's last
