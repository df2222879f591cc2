"""Reading a free-standing test (``/free_standing`` of result.h5 and summary.json's
``free_standing``; docs/results.md) of real runs: the web test's job (tests/web/job.json:
150 grains, a helix, formwork removal, settling, a dead load and an unconfined
compression) and the same column with its wire pulled out instead of the compression.
Each runs once per module, locally with the runner (`wiredem run`), its triaxial test
cut to one pressure and 1 % strain (the free-standing test needs the campaign's one)."""
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
from conftest import ROOT

WEB_JOB = ROOT / "tests" / "web" / "job.json"


def _run(runner_bin: Path, job: Dict[str, Any], folder: Path) -> Path:
    job["triaxial"].update({"confining_pressures_pa": [10000], "target_axial_strain": 0.01,
                            "snapshot_strains": [0, 0.01]})
    (folder / "job.json").write_text(json.dumps(job))
    out = folder / "out"
    subprocess.run([str(runner_bin), "run", str(folder / "job.json"), "-o", str(out), "--threads", "1"], check=True,
                   capture_output=True, timeout=600)
    return out


@pytest.fixture(scope="module")
def compressed(runner_bin: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The web test's job with a dead load held before the compression."""
    job = json.loads(WEB_JOB.read_text())
    job["free_standing"].update({"dead_load_n": 0.05, "dead_load_hold_time_s": 0.01})
    return _run(runner_bin, job, tmp_path_factory.mktemp("compressed"))


@pytest.fixture(scope="module")
def pulled(runner_bin: Path, tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The same column, its wire's top end pulled up by 5 mm instead of the compression."""
    job = json.loads(WEB_JOB.read_text())
    job["free_standing"] = {"enabled": True, "removal_time_s": 0.01, "removal_distance_m": 0.002,
                            "max_settling_time_s": 0.05, "pull_out_speed_m_per_s": 0.05,
                            "pull_out_ramp_time_s": 0.005, "pull_out_length_m": 0.005, "pull_out_max_time_s": 0.5,
                            "sample_interval_s": 0.0005}
    return _run(runner_bin, job, tmp_path_factory.mktemp("pulled"))


def test_a_job_without_the_test_has_none(tiny_dir: Path) -> None:
    assert wiredem.open(tiny_dir).free_standing is None


def test_the_series_holds_every_row_dataset_with_its_units_and_the_files_phase_names(compressed: Path) -> None:
    fs = wiredem.open(compressed).free_standing
    assert fs is not None
    s = fs.series
    with h5py.File(compressed / "result.h5", "r") as f:
        g = f["free_standing"]
        rows = g["time_s"].shape[0]
        declared = g["phase"].attrs["units"]
        declared = declared.decode() if isinstance(declared, bytes) else str(declared)
        for name in g:
            d = g[name]
            if isinstance(d, h5py.Dataset) and d.ndim == 1 and d.shape[0] == rows:
                assert np.array_equal(s[name].to_numpy(), d[()], equal_nan=True), name
                units = d.attrs["units"]
                assert s.attrs["units"][name] == (units.decode() if isinstance(units, bytes) else units)
    assert len(s) == rows > 10
    # the names are the file's: "0 removal, 1 settling, 2 dead_load, 3 loading"
    assert fs.phases == {0: "removal", 1: "settling", 2: "dead_load", 3: "loading"}, declared
    assert list(dict.fromkeys(s["phase_name"])) == ["removal", "settling", "dead_load", "loading"]
    assert (np.diff(s["phase"].to_numpy()) >= 0).all()  # the phases follow each other once
    assert (np.diff(s["time_s"].to_numpy()) > 0).all()
    with pytest.raises(wiredem.ResultError, match="no phase 'pull_out' .*removal, settling, dead_load, loading"):
        fs.phase("pull_out")


def test_the_compression_starts_where_the_file_says_and_peaks_at_its_peak_snapshot(compressed: Path) -> None:
    fs = wiredem.open(compressed).free_standing
    assert fs is not None
    c, a = fs.compression, fs.attributes
    assert c.index[0] == a["loading_start_sample"] and c.index[-1] == len(fs.series) - 1
    assert (c["phase_name"] == "loading").all()
    peak = int(a["max_sigma1_sample"])
    assert c["sigma1_pa"].max() == c.loc[peak, "sigma1_pa"] == a["max_sigma1_pa"]
    assert fs.peak_snapshot is not None and fs.peak_snapshot.index is None
    assert fs.peak_snapshot.axial_strain == c.loc[peak, "axial_strain"]
    assert fs.peak_snapshot.test_name == "free_standing"
    assert [sn.index for sn in fs.snapshots] == list(range(len(fs.snapshots))) and fs.snapshots
    with pytest.raises(wiredem.ResultError, match="triaxial test's snapshots only"):
        fs.peak_snapshot.wire_autocorrelation()


def test_the_figures_are_the_summarys_and_a_bare_file_reads_the_same_settling(compressed: Path,
                                                                               tmp_path: Path) -> None:
    r = wiredem.open(compressed)
    fs = r.free_standing
    assert fs is not None and r.summary is not None
    block = r.summary["free_standing"]
    assert fs.stands is block["settling"]["stands"]
    assert fs.unconfined_compression == block["compression"]
    assert fs.dead_load == block["dead_load"] and fs.dead_load is not None
    assert fs.dead_load["force_n"] == 0.05
    assert fs.pull_out_figures is None and fs.pull_out is None
    bare = tmp_path / "result.h5"
    shutil.copyfile(compressed / "result.h5", bare)
    alone = wiredem.open(bare).free_standing
    assert alone is not None and alone.summary is None and alone.unconfined_compression is None
    assert alone.stands is fs.stands
    for k, v in alone.settling.items():  # every attribute the summary also has, the same number
        assert block["settling"][k] == v, k
    assert set(alone.settling) == set(block["settling"])


def test_the_profiles_count_the_standing_grains_once(compressed: Path) -> None:
    r = wiredem.open(compressed)
    fs = r.free_standing
    assert fs is not None
    grains = fs.settling["grains"]
    for which in ("before", "settled", "at_peak", "at_end"):
        p = fs.profile(which)
        assert list(p.columns) == ["grains", "height_m", "radius_m"]
        assert p.attrs["units"] == {"grains": "1", "height_m": "m", "radius_m": "m"}
        assert (np.diff(p["height_m"].to_numpy()) > 0).all()
        # each grain in one slice; the settled column's, standing grains only
        assert p["grains"].sum() <= r.job_spec["specimen"]["grain_count"]
        if which == "settled":
            assert p["grains"].sum() == grains
    with pytest.raises(wiredem.ResultError, match="no profile 'top' .*before, settled"):
        fs.profile("top")


def test_the_wires_tension_at_the_peak_is_its_axial_stiffness_times_its_strain(compressed: Path) -> None:
    r = wiredem.open(compressed)
    fs = r.free_standing
    assert fs is not None
    w = fs.wire_at_peak()
    assert w.attrs["units"] == {"strain": "1", "tension_n": "N"}
    assert len(w) == len(r.specimen.wire_node_position_m) - 1  # one row per segment
    wire = r.job_spec["specimen"]["wire"]
    ea = wire["youngs_modulus_pa"] * math.pi * wire["radius_m"] ** 2  # T = E_w π r_w² ε, stretched or pressed
    assert (w["strain"] > 0).any() and (w["strain"] < 0).any()
    assert np.allclose(w["tension_n"], ea * w["strain"], rtol=1e-12, atol=0)


def test_a_pull_out_has_its_own_rows_and_no_compression(pulled: Path) -> None:
    r = wiredem.open(pulled)
    fs = r.free_standing
    assert fs is not None and r.summary is not None
    assert fs.phases[4] == "pull_out"
    p = fs.pull_out
    assert p is not None
    assert p.attrs["units"]["pull_force_n"] == "N" and p.attrs["units"]["pulled_length_m"] == "m"
    assert len(p) == len(fs.phase("pull_out")) > 0
    assert np.array_equal(p["time_s"].to_numpy(), fs.phase("pull_out")["time_s"].to_numpy())
    figures = fs.pull_out_figures
    assert figures is not None and figures["end"] == "length"
    assert p["pull_force_n"].max() == figures["peak_pull_force_n"]
    assert p["pulled_length_m"].iloc[-1] == figures["pulled_length_m"] >= 0.005
    assert fs.compression.empty
    assert fs.unconfined_compression is not None and fs.unconfined_compression["unconfined_strength_pa"] is None
    with pytest.raises(wiredem.ResultError, match="no wire at its peak"):
        fs.wire_at_peak()


def test_the_figure_marks_the_engines_strength_and_says_whether_the_column_stands(compressed: Path, pulled: Path,
                                                                                 tmp_path: Path) -> None:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from wiredem import plots

    r = wiredem.open(compressed)
    fs = r.free_standing
    assert fs is not None and fs.unconfined_compression is not None
    fig = plots.plot_free_standing(r)
    ax = fig.axes[0]
    circle = next(line for line in ax.get_lines() if line.get_marker() == "o")
    assert circle.get_xdata()[0] == pytest.approx(100 * fs.unconfined_compression["strain_at_failure"], abs=1e-12)
    assert circle.get_ydata()[0] == pytest.approx(1e-3 * fs.unconfined_compression["unconfined_strength_pa"],
                                                  rel=1e-12)
    triangle = next(line for line in ax.get_lines() if line.get_marker() == "^")
    assert triangle.get_ydata()[0] == pytest.approx(1e-3 * fs.attributes["max_sigma1_pa"], rel=1e-12)
    assert ("the column stands" if fs.stands else "the column does not stand") in fig._suptitle.get_text()
    fig.savefig(tmp_path / "compressed.png")
    plt.close(fig)
    fig = plots.plot_free_standing(wiredem.open(pulled))  # the pull's force instead of the compression
    assert fig.axes[0].get_xlabel() == "pulled length [mm]"
    fig.savefig(tmp_path / "pulled.png")
    plt.close(fig)
