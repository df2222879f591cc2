"""A study folder read into frames (the layout of `wiredem study run`), on files written here."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

import wiredem


def _point_summary(phi: float, etas: list) -> dict:
    return {"tests": [{"confining_pressure_pa": 1e4 * (i + 1), "peak_deviatoric_stress_pa": 5e3 * (i + 1),
                       "peak_axial_strain": 0.05, "max_q_shape": "rising", "residual_stress_ratio": eta - 0.01,
                       "quasi_static": False, "yield": {"stress_ratio": eta, "axial_strain": 0.04, "shape": "peak",
                                                        "sigma1_pa": 1.0, "sigma3_effective_pa": 0.5,
                                                        "deviatoric_stress_pa": 0.5}}
                      for i, eta in enumerate(etas)],
            "mohr_coulomb": {"friction_angle_deg": phi, "cohesion_pa": 100.0, "r_squared": 1.0},
            "mohr_coulomb_max_q": {"friction_angle_deg": phi + 1, "cohesion_pa": 0.0, "r_squared": 0.9}}


@pytest.fixture()
def study_dir(tmp_path: Path) -> Path:
    """Two points varying the pattern (the seed is the base's, 7); the second failed."""
    summary = {"name": "patterns", "paths": ["specimen.wire.pattern"],
               "points": [{"index": 0, "label": "specimen.wire.pattern=\"none\"", "values": {"specimen.wire.pattern": "none"},
                           "job_id": "", "state": "succeeded", "error": "", "friction_angle_deg": 20.0,
                           "cohesion_pa": 100.0, "r_squared": 1.0, "confining_pressures_pa": [1e4, 2e4]},
                          {"index": 1, "label": "specimen.wire.pattern=\"helix\"", "values": {"specimen.wire.pattern": "helix"},
                           "job_id": "", "state": "failed", "error": "it broke", "friction_angle_deg": None,
                           "cohesion_pa": None, "r_squared": None, "confining_pressures_pa": []}],
               "groups": [{"values": {"specimen.wire.pattern": "none"}, "points": 1, "succeeded": 1,
                           "friction_angle_deg": {"n": 1, "mean": 20.0, "sd": None},
                           "cohesion_pa": {"n": 1, "mean": 100.0, "sd": None}},
                          {"values": {"specimen.wire.pattern": "helix"}, "points": 1, "succeeded": 0,
                           "friction_angle_deg": {"n": 0, "mean": None, "sd": None},
                           "cohesion_pa": {"n": 0, "mean": None, "sd": None}}]}
    (tmp_path / "summary.json").write_text(json.dumps(summary))
    for k in (0, 1):
        (tmp_path / "points" / str(k)).mkdir(parents=True)
        (tmp_path / "points" / str(k) / "job.json").write_text(json.dumps({"seed": 7}))
    (tmp_path / "points" / "0" / "summary.json").write_text(json.dumps(_point_summary(20.0, [0.3, 0.35])))
    return tmp_path


def test_the_tidy_frame_has_a_row_per_test_of_the_succeeded_points(study_dir: Path) -> None:
    s = wiredem.open_study(study_dir)
    frame = s.tests()
    assert len(frame) == 2 and set(frame["point"]) == {0}
    assert list(frame["specimen.wire.pattern"]) == ["none", "none"]
    assert list(frame["seed"]) == [7, 7]  # not varied: the job's own
    assert list(frame["confining_pressure_pa"]) == [1e4, 2e4]
    assert list(frame["yield_stress_ratio"]) == [0.3, 0.35]
    assert list(frame["max_q_deviatoric_stress_pa"]) == [5e3, 1e4]
    assert list(frame["friction_angle_deg"]) == [20.0, 20.0]
    assert list(frame["max_q_friction_angle_deg"]) == [21.0, 21.0]


def test_points_and_spread_are_the_summarys(study_dir: Path) -> None:
    s = wiredem.open_study(study_dir)
    points = s.points()
    assert list(points["state"]) == ["succeeded", "failed"] and points.loc[1, "error"] == "it broke"
    assert list(points["seed"]) == [7, 7]
    spread = s.spread()
    assert list(spread["specimen.wire.pattern"]) == ["none", "helix"]
    assert spread.loc[0, "friction_angle_deg_mean"] == 20.0 and spread.loc[1, "succeeded"] == 0
    with pytest.raises(wiredem.ResultError, match="no result.h5"):
        s.result(0)


def test_a_folder_without_a_study_summary_is_refused(tmp_path: Path) -> None:
    with pytest.raises(wiredem.ResultError, match="no readable study summary"):
        wiredem.open_study(tmp_path)
    (tmp_path / "summary.json").write_text(json.dumps({"tests": []}))
    with pytest.raises(wiredem.ResultError, match="not a study summary"):
        wiredem.open_study(tmp_path)
