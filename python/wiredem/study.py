"""A parameter study's results as tidy pandas DataFrames (docs/studies.md).

A study's summary (``GET /v1/studies/{id}/summary``, or ``DIR/summary.json``
of ``wiredem study run`` / ``wiredem study fetch``) holds one row per point
and one per group of replicates (the points equal but for ``seed``), with φ and
c over the seeds as the study code computed them (``api::study_summary``).
With each point's own ``summary.json``, :meth:`Study.tests` is one row per
test: the point's varied values, its seed, σ₃, the yield and max-q states,
and the point's φ, c and R².
"""
from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, Dict, List, Optional, Union

import pandas as pd

from .errors import ResultError
from .results import Result, open_result

PathLike = Union[str, "os.PathLike[str]"]

# summary.json's per-test keys that become columns of Study.tests(), by their column name.
_TEST_KEYS = (("max_q_deviatoric_stress_pa", ("peak_deviatoric_stress_pa",)),
              ("max_q_axial_strain", ("peak_axial_strain",)),
              ("max_q_shape", ("max_q_shape",)),
              ("yield_stress_ratio", ("yield", "stress_ratio")),
              ("yield_axial_strain", ("yield", "axial_strain")),
              ("yield_sigma1_pa", ("yield", "sigma1_pa")),
              ("yield_sigma3_effective_pa", ("yield", "sigma3_effective_pa")),
              ("yield_deviatoric_stress_pa", ("yield", "deviatoric_stress_pa")),
              ("yield_shape", ("yield", "shape")),
              ("residual_stress_ratio", ("residual_stress_ratio",)),
              ("quasi_static", ("quasi_static",)),
              ("max_inertial_number", ("max_inertial_number",)),
              ("hold_time_s", ("hold_time_s",)))
# The point's fit, from its summary.json.
_FIT_KEYS = (("friction_angle_deg", ("mohr_coulomb", "friction_angle_deg")),
             ("cohesion_pa", ("mohr_coulomb", "cohesion_pa")),
             ("r_squared", ("mohr_coulomb", "r_squared")),
             ("max_q_friction_angle_deg", ("mohr_coulomb_max_q", "friction_angle_deg")),
             ("max_q_cohesion_pa", ("mohr_coulomb_max_q", "cohesion_pa")))


def _find(obj: Any, keys: tuple) -> Any:
    for k in keys:
        if not isinstance(obj, dict):
            return None
        obj = obj.get(k)
    return obj


class Study:
    """A study's summary and the summaries of its succeeded points.

    Args:
        summary: the study summary (``points``, ``groups``, ``paths``).
        points: {point index: that point's summary.json} of the succeeded points.
        directory: the study folder when read from one (for :meth:`result`).
    """

    def __init__(self, summary: Dict[str, Any], points: Dict[int, Dict[str, Any]],
                 directory: Optional[Path] = None, seeds: Optional[Dict[int, Any]] = None) -> None:
        self.summary = summary  #: the study summary as written
        self.point_summaries = points  #: {index: summary.json}
        self.directory = directory
        self._seeds = seeds or {}

    @property
    def name(self) -> str:
        """The study's name."""
        return str(self.summary.get("name", ""))

    @property
    def paths(self) -> List[str]:
        """The varied fields (dotted job-spec paths), in document order."""
        return list(self.summary.get("paths", []))

    def _seed(self, point: Dict[str, Any]) -> Any:
        values = point.get("values") or {}
        return values["seed"] if "seed" in values else self._seeds.get(int(point["index"]))

    def points(self) -> pd.DataFrame:
        """One row per point, indexed by its index: ``label``, ``job_id``, ``state``, ``error``, a
        column per varied path, ``seed``, and the summary's figures (φ, c, R², volume fractions, lags)."""
        rows = []
        for p in self.summary.get("points", []):
            row: Dict[str, Any] = {"point": p["index"], "label": p.get("label"), "job_id": p.get("job_id") or None,
                                   "state": p.get("state"), "error": p.get("error") or None}
            row.update({path: (p.get("values") or {}).get(path) for path in self.paths if path != "seed"})
            row["seed"] = self._seed(p)
            for k, v in p.items():
                if k not in ("index", "label", "values", "job_id", "state", "error") and not isinstance(v, list):
                    row[k] = v
            rows.append(row)
        return pd.DataFrame(rows).set_index("point")

    def tests(self) -> pd.DataFrame:
        """The tidy frame: one row per test of every succeeded point.

        Columns: ``point``, ``label``, a column per varied path (but seed),
        ``seed``, ``confining_pressure_pa``, the yield state (``yield_stress_ratio``
        η, ``yield_deviatoric_stress_pa`` q, ``yield_axial_strain``, ``yield_shape``,
        …), the max-q state (``max_q_*``), ``residual_stress_ratio``,
        ``quasi_static``, and the point's fit (``friction_angle_deg`` φ,
        ``cohesion_pa`` c, ``r_squared``): every figure as the runner wrote it.
        """
        rows = []
        by_index = {int(p["index"]): p for p in self.summary.get("points", [])}
        for index in sorted(self.point_summaries):
            s = self.point_summaries[index]
            p = by_index.get(index, {"index": index, "values": {}})
            base: Dict[str, Any] = {"point": index, "label": p.get("label")}
            base.update({path: (p.get("values") or {}).get(path) for path in self.paths if path != "seed"})
            base["seed"] = self._seed(p)
            fit = {col: _find(s, keys) for col, keys in _FIT_KEYS}
            for t in s.get("tests", []):
                row = dict(base)
                row["confining_pressure_pa"] = t.get("confining_pressure_pa")
                row.update({col: _find(t, keys) for col, keys in _TEST_KEYS})
                row.update(fit)
                rows.append(row)
        columns = ["point", "label"] + [p for p in self.paths if p != "seed"] + ["seed", "confining_pressure_pa"] \
            + [c for c, _ in _TEST_KEYS] + [c for c, _ in _FIT_KEYS]
        return pd.DataFrame(rows, columns=columns)

    def spread(self) -> pd.DataFrame:
        """φ and c over the seeds, one row per group of replicates (the points equal but for seed),
        as the study code computed them: a column per varied path, ``points``, ``succeeded``,
        ``friction_angle_deg_mean``, ``_sd`` (n − 1; None below 2), ``_n``, and the same of ``cohesion_pa``."""
        rows = []
        for g in self.summary.get("groups", []):
            row: Dict[str, Any] = {path: (g.get("values") or {}).get(path) for path in self.paths if path != "seed"}
            row["points"], row["succeeded"] = g.get("points"), g.get("succeeded")
            for q in ("friction_angle_deg", "cohesion_pa"):
                for stat in ("mean", "sd", "n"):
                    row[f"{q}_{stat}"] = (g.get(q) or {}).get(stat)
            rows.append(row)
        return pd.DataFrame(rows)

    def result(self, index: int) -> Result:
        """Point ``index``'s result (its folder ``points/K`` must hold result.h5)."""
        if self.directory is None:
            raise ResultError("this study was read without its folder: fetch it (Client.fetch_study) to open results")
        return open_result(self.directory / "points" / str(index))


def _seed_of_point(folder: Path) -> Any:
    """The seed of a point folder's job: its job.json (`wiredem study run`), else the job
    spec in its result.h5 (`wiredem study fetch`); None when it has neither."""
    job = folder / "job.json"
    try:
        if job.is_file():
            return json.loads(job.read_text()).get("seed")
        if (folder / "result.h5").is_file():
            return open_result(folder / "result.h5").job_spec.get("seed")
    except (ValueError, ResultError):
        return None
    return None


def open_study(path: PathLike) -> Study:
    """Opens a study folder: ``DIR/summary.json`` and each ``DIR/points/K/summary.json``
    (what ``wiredem study run -o DIR``, ``wiredem study fetch ID -o DIR`` and
    :meth:`Client.fetch_study` write)."""
    folder = Path(os.fspath(path))
    try:
        summary = json.loads((folder / "summary.json").read_text())
    except (OSError, ValueError) as e:
        raise ResultError(f"{folder}: no readable study summary.json ({e})") from e
    if not isinstance(summary, dict) or "points" not in summary:
        raise ResultError(f"{folder}/summary.json is not a study summary (no points)")
    points, seeds = {}, {}
    for p in summary["points"]:
        k = int(p["index"])
        sj = folder / "points" / str(k) / "summary.json"
        if "seed" not in (p.get("values") or {}):
            seeds[k] = _seed_of_point(folder / "points" / str(k))
        if p.get("state") == "succeeded" and sj.is_file():
            points[k] = json.loads(sj.read_text())
    return Study(summary, points, folder, seeds)
