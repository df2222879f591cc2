"""A campaign's results as numpy arrays and pandas DataFrames.

Reads what ``wiredem run``, ``wiredem analyse`` and ``wiredem fetch`` write
(docs/results.md): ``result.h5`` (format ``wiredem-result-1``, a ``units``
attribute on every numeric dataset) and, beside it, ``summary.json``. Every
figure the engine computed — the yield and max-q states, the residual stress
ratio, the Mohr–Coulomb fits, the volume fractions, the wire's autocorrelation
lags — is read from these files as the runner wrote it, never recomputed here.

Units travel with the data: a DataFrame carries ``frame.attrs["units"]``
(column → unit string, ``"1"`` for dimensionless values and counts), an array
:meth:`Specimen.units` / :meth:`Snapshot.units`; names end in their unit
(``_m``, ``_pa``, ``_s``) as everywhere in wiredem.

Files are opened for each read and closed again: a :class:`Result` holds no
HDF5 handle, and series are cached once read.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import subprocess
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Dict, Iterable, List, Optional, Tuple, Union

import h5py
import numpy as np
import pandas as pd

from .errors import ResultError

PathLike = Union[str, "os.PathLike[str]"]

#: ``phase`` of a series row: 0 pressure ramp, 1 hold, 2 loading (docs/results.md).
RAMP, HOLD, LOADING = 0, 1, 2

#: Body kinds of ``contact_bodies`` (docs/results.md).
BODY_KINDS = {0: "grain", 1: "wire", 2: "membrane"}

#: The columns of a test's time series in the order the runner writes them: the list
#: of ``engine/triaxial/series_columns.hpp`` (the writer's one list;
#: ``SeriesColumns.ThePythonPackagesColumnListIsTheTable`` checks that this is it, in
#: its order). Time first, the phase last.
SERIES_COLUMNS: Tuple[str, ...] = (
    "time_s", "axial_strain", "height_m", "top_plate_force_n", "bottom_plate_force_n",
    "column_radius_m", "confining_pressure_pa", "sigma1_pa", "sigma3_effective_pa",
    "deviatoric_stress_pa", "stress_ratio", "volumetric_strain", "kinetic_energy_j",
    "elastic_energy_j", "contacts", "sliding_contacts", "membrane_contacts",
    "wire_strain_mean", "wire_strain_max", "inertial_number", "phase",
)
_TIME, _PHASE = SERIES_COLUMNS[0], SERIES_COLUMNS[-1]


def _series_order(columns: Iterable[str]) -> List[str]:
    """A series frame's columns: time and phase first (as docs/results.md lists them),
    then the others in the writer's order (:data:`SERIES_COLUMNS`), then any the package
    does not know (a newer file's) in the file's order."""
    have = list(columns)
    known = [_TIME, _PHASE] + [k for k in SERIES_COLUMNS if k not in (_TIME, _PHASE)]
    return [k for k in known if k in have] + [k for k in have if k not in SERIES_COLUMNS]


def find_wiredem(given: Optional[PathLike] = None) -> str:
    """The ``wiredem`` binary: ``given``, else ``$WIREDEM_BIN``, else ``wiredem`` on the PATH."""
    name = os.fspath(given) if given is not None else os.environ.get("WIREDEM_BIN") or shutil.which("wiredem")
    if not name or not (os.path.isfile(name) and os.access(name, os.X_OK)):
        raise ResultError(f"no wiredem binary ({name or 'none on the PATH'}): give its path or set $WIREDEM_BIN")
    return name


def _text(value: Any) -> str:
    return value.decode("utf-8") if isinstance(value, bytes) else str(value)


def _attr(value: Any) -> Any:
    """An HDF5 attribute as a plain Python value."""
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.ndarray):
        return value.tolist() if value.shape else value.item()
    if isinstance(value, np.generic):
        return value.item()
    return value


def _attributes(obj: Any) -> Dict[str, Any]:
    return {k: _attr(v) for k, v in obj.attrs.items()}


def _units(ds: Any) -> Optional[str]:
    u = ds.attrs.get("units")
    return None if u is None else _text(u)


# ---------------------------------------------------------------------------


@dataclass(frozen=True)
class MohrCoulomb:
    """A Mohr–Coulomb envelope τ = c + σ tan φ as the engine fitted it (summary.json).

    ``mohr_coulomb`` goes through the yield states, ``mohr_coulomb_max_q``
    through the states at the maximum of q (docs/results.md). Values are None
    when the fit was impossible; ``error`` then says why.
    """

    friction_angle_deg: Optional[float]     #: φ [°]
    cohesion_pa: Optional[float]            #: c [Pa]
    r_squared: Optional[float]              #: of the fit through the circle tops; None with one test
    paper_top_line_angle_deg: Optional[float]  #: α, the slope of the line through the tops (the paper's figure)
    cohesion_fixed_at_zero: Optional[bool]  #: True with a single test (c = 0 imposed)
    states: Optional[str]                   #: which states it went through
    error: Optional[str]                    #: why there is no fit, if there is none
    raw: Dict[str, Any] = field(repr=False, compare=False, default_factory=dict)  #: the JSON object as written

    @staticmethod
    def from_json(obj: Optional[Dict[str, Any]]) -> "MohrCoulomb":
        obj = obj or {}
        return MohrCoulomb(obj.get("friction_angle_deg"), obj.get("cohesion_pa"), obj.get("r_squared"),
                           obj.get("paper_top_line_angle_deg"), obj.get("cohesion_fixed_at_zero"),
                           obj.get("states"), obj.get("error"), dict(obj))

    def shear_stress_pa(self, normal_stress_pa: Any) -> Any:
        """The envelope's τ [Pa] at normal stresses σ [Pa] (a number or an array), for drawing it."""
        if self.friction_angle_deg is None or self.cohesion_pa is None:
            raise ResultError(f"no Mohr-Coulomb fit: {self.error or 'no friction angle'}")
        return self.cohesion_pa + np.asarray(normal_stress_pa) * math.tan(math.radians(self.friction_angle_deg))


class _Arrays:
    """A group of arrays in a file (the specimen, a snapshot), read one by one on demand."""

    def __init__(self, path: Path, group: str, attributes: Dict[str, Any], units: Dict[str, Optional[str]]) -> None:
        self._path, self._group = path, group
        #: the group's attributes as the runner wrote them
        self.attributes = attributes
        self._units = units

    @property
    def arrays(self) -> List[str]:
        """The names of its datasets."""
        return list(self._units)

    def units(self, name: str) -> Optional[str]:
        """The units of array ``name`` (None in a file written without them)."""
        return self._units[name]

    def array(self, name: str) -> np.ndarray:
        """One dataset as a numpy array (e.g. ``grain_position_m``, N×3)."""
        if name not in self._units:
            raise ResultError(f"{self._path}: {self._group} has no {name} (it has {', '.join(self._units)})")
        with h5py.File(self._path, "r") as f:
            return f[self._group][name][()]


def _dataset_units(g: Any) -> Dict[str, Optional[str]]:
    """{dataset name: units} of a group's datasets."""
    return {k: _units(g[k]) for k in g if isinstance(g[k], h5py.Dataset)}


class Specimen(_Arrays):
    """The prepared specimen (``/specimen``): grains, wire and membrane as arrays [m, rad].

    ``attributes``: grains, wire_length_m, volume fractions, settled, … (docs/results.md).
    """

    def __init__(self, path: Path) -> None:
        with h5py.File(path, "r") as f:
            if "specimen" not in f:
                raise ResultError(f"{path}: no /specimen")
            g = f["specimen"]
            super().__init__(path, g.name, _attributes(g), _dataset_units(g))

    @property
    def grain_position_m(self) -> np.ndarray:
        """Grain centres, N×3 [m]."""
        return self.array("grain_position_m")

    @property
    def grain_radius_m(self) -> np.ndarray:
        """Grain radii, N [m]."""
        return self.array("grain_radius_m")

    @property
    def wire_node_position_m(self) -> np.ndarray:
        """Wire nodes in the order laid, W×3 [m] (0×3 without wire)."""
        return self.array("wire_node_position_m").reshape(-1, 3)

    @property
    def wire_rest_angle_rad(self) -> np.ndarray:
        """The rest angle ζ₀ of each wire node's plastic joint, W [rad]."""
        return self.array("wire_rest_angle_rad")

    @property
    def membrane_node_position_m(self) -> np.ndarray:
        """Membrane nodes, M×3 [m]."""
        return self.array("membrane_node_position_m")

    def grains(self) -> pd.DataFrame:
        """One row per grain: ``x_m``, ``y_m``, ``z_m``, ``radius_m`` (units in ``attrs["units"]``)."""
        p = self.grain_position_m
        frame = pd.DataFrame({"x_m": p[:, 0], "y_m": p[:, 1], "z_m": p[:, 2], "radius_m": self.grain_radius_m})
        frame.index.name = "grain"
        frame.attrs["units"] = {"x_m": "m", "y_m": "m", "z_m": "m", "radius_m": "m"}
        return frame


class Snapshot(_Arrays):
    """One snapshot of a test (``…/snapshots/snapshot_<k>``): the column at a strain.

    ``attributes``: requested_axial_strain, axial_strain, time_s.
    """

    def __init__(self, path: Path, group: str, attributes: Dict[str, Any], units: Dict[str, Optional[str]]) -> None:
        super().__init__(path, group, attributes, units)
        last = group.rsplit("/", 1)[1]
        #: k of snapshot_<k>; None for the free-standing test's ``peak_snapshot``
        self.index: Optional[int] = int(last.rsplit("_", 1)[1]) if last.startswith("snapshot_") else None

    def __repr__(self) -> str:
        name = self.index if self.index is not None else "at the peak"
        return f"<Snapshot {name} at axial strain {self.axial_strain:.4g}>"

    @property
    def axial_strain(self) -> float:
        """The measured axial strain at the snapshot."""
        return float(self.attributes["axial_strain"])

    @property
    def requested_axial_strain(self) -> float:
        """The strain asked for (``triaxial.snapshot_strains``)."""
        return float(self.attributes.get("requested_axial_strain", math.nan))

    @property
    def time_s(self) -> float:
        """Simulated time of the snapshot [s]."""
        return float(self.attributes.get("time_s", math.nan))

    @property
    def wire_segment_strain(self) -> np.ndarray:
        """The strain of each wire segment (stretch > 0), W − 1, in the order laid."""
        return self.array("wire_segment_strain")

    @property
    def test_name(self) -> str:
        """The name of the test it belongs to (``sigma3_20000``, or ``free_standing``)."""
        parts = self._group.strip("/").split("/")
        return parts[1] if parts[0] == "tests" else parts[0]

    def wire_autocorrelation(self, wiredem: Optional[PathLike] = None) -> Dict[str, Any]:
        """The engine's autocorrelation of :attr:`wire_segment_strain`, with its maxima.

        ``segment_length_m``, ``segments``, ``lag_m``, ``coefficients`` R(lag),
        ``first_maximum_lag_m`` (the first local maximum after lag 0),
        ``prominent_maximum_lag_m`` (the first above the white-noise band) and
        ``error`` (why there is none): the reply of the server's
        ``…/snapshots/{k}/wire_autocorrelation``, computed by the ``wiredem``
        binary (``wiredem autocorrelation``) from this file, so that R has one
        implementation, the one summary.json's lags come from. ``wiredem`` is the
        binary's path; default ``$WIREDEM_BIN``, else ``wiredem`` on the PATH.
        """
        if self.index is None or not self._group.startswith("/tests/"):
            raise ResultError(f"{self._group}: the wire's autocorrelation is computed for a triaxial test's "
                              "snapshots only (wiredem autocorrelation --test NAME --snapshot K)")
        binary = find_wiredem(wiredem)
        run = subprocess.run([binary, "autocorrelation", str(self._path), "--test", self.test_name,
                              "--snapshot", str(self.index)], capture_output=True, text=True)
        if run.returncode != 0:
            raise ResultError(run.stderr.strip() or f"{binary} autocorrelation exited {run.returncode}")
        reply: Dict[str, Any] = json.loads(run.stdout)
        return reply

    def force_network(self) -> pd.DataFrame:
        """The contacts between bodies, one row each.

        Columns: ``kind_a``, ``index_a``, ``kind_b``, ``index_b`` (kinds 0 grain,
        1 wire, 2 membrane: :data:`BODY_KINDS`), ``force_x_n``, ``force_y_n``,
        ``force_z_n`` (the force on the first body) and ``normal_force_n``.
        """
        bodies = self.array("contact_bodies").reshape(-1, 4)
        force = self.array("contact_force_n").reshape(-1, 3)
        frame = pd.DataFrame({"kind_a": bodies[:, 0], "index_a": bodies[:, 1], "kind_b": bodies[:, 2],
                              "index_b": bodies[:, 3], "force_x_n": force[:, 0], "force_y_n": force[:, 1],
                              "force_z_n": force[:, 2], "normal_force_n": self.array("contact_normal_force_n")})
        frame.index.name = "contact"
        frame.attrs["units"] = {"kind_a": "1", "index_a": "1", "kind_b": "1", "index_b": "1", "force_x_n": "N",
                                "force_y_n": "N", "force_z_n": "N", "normal_force_n": "N"}
        return frame

    def wall_contacts(self) -> pd.DataFrame:
        """The contacts with the plates and walls: ``wall``, ``kind``, ``index``, the force on the body."""
        bodies = self.array("wall_contact_bodies").reshape(-1, 3)
        force = self.array("wall_contact_force_n").reshape(-1, 3)
        frame = pd.DataFrame({"wall": bodies[:, 0], "kind": bodies[:, 1], "index": bodies[:, 2],
                              "force_x_n": force[:, 0], "force_y_n": force[:, 1], "force_z_n": force[:, 2]})
        frame.index.name = "contact"
        frame.attrs["units"] = {"wall": "1", "kind": "1", "index": "1", "force_x_n": "N", "force_y_n": "N",
                                "force_z_n": "N"}
        return frame

    def body_positions_m(self) -> Dict[int, np.ndarray]:
        """{body kind: positions N×3 [m]} (grains, wire nodes, membrane nodes), for placing contacts."""
        names = {0: "grain_position_m", 1: "wire_node_position_m", 2: "membrane_node_position_m"}
        return {k: self.array(n).reshape(-1, 3) for k, n in names.items() if n in self._units}


class Test:
    """One triaxial test (``/tests/sigma3_<σ₃>``): its time series, states and snapshots."""

    def __init__(self, path: Path, group: str, summary: Optional[Dict[str, Any]]) -> None:
        self._path, self._group = path, group
        self.name = group.rsplit("/", 1)[1]  #: ``sigma3_20000``
        #: summary.json's ``tests[]`` entry of this test (None without summary.json)
        self.summary = summary
        with h5py.File(path, "r") as f:
            g = f[group]
            #: the group's attributes as the runner wrote them (docs/results.md)
            self.attributes: Dict[str, Any] = _attributes(g)
            self._columns = _dataset_units(g)
            snaps = []
            if "snapshots" in g and isinstance(g["snapshots"], h5py.Group):
                for k in g["snapshots"]:
                    s = g["snapshots"][k]
                    snaps.append(Snapshot(path, s.name, _attributes(s), _dataset_units(s)))
        #: the snapshots, by ascending measured axial strain
        self.snapshots: List[Snapshot] = sorted(snaps, key=lambda s: (s.axial_strain, s.index))
        self._series: Optional[pd.DataFrame] = None

    def __repr__(self) -> str:
        return f"<Test {self.name}: {len(self.snapshots)} snapshots>"

    @property
    def confining_pressure_pa(self) -> float:
        """The applied σ₃ [Pa]."""
        return float(self.attributes["confining_pressure_pa"])

    @property
    def units(self) -> Dict[str, Optional[str]]:
        """{column: units} of the time series."""
        return dict(self._columns)

    @property
    def series(self) -> pd.DataFrame:
        """The whole time series (ramp, hold, loading), one row per sample.

        Columns as docs/results.md lists them (``time_s``, ``phase``,
        ``axial_strain``, ``sigma1_pa``, ``stress_ratio``, …), units in
        ``frame.attrs["units"]``; the index is the sample number (``yield_sample``
        and ``peak_sample`` point into it).
        """
        if self._series is None:
            with h5py.File(self._path, "r") as f:
                g = f[self._group]
                data = {k: g[k][()] for k in self._columns}
            frame = pd.DataFrame({k: data[k] for k in _series_order(data)})
            frame.index.name = "sample"
            frame.attrs["units"] = {k: self._columns[k] for k in frame.columns}
            frame.attrs["test"] = self.name
            self._series = frame
        return self._series.copy()

    @property
    def loading(self) -> pd.DataFrame:
        """The rows of the loading phase (``phase == 2``): the curves against axial strain."""
        s = self.series
        out = s[s[_PHASE] == LOADING] if _PHASE in s else s
        out.attrs = dict(s.attrs)
        return out

    def curve(self, column: str = "stress_ratio", loading_only: bool = True) -> pd.DataFrame:
        """``axial_strain`` and one column (default the stress ratio η) as a two-column DataFrame."""
        s = self.loading if loading_only else self.series
        if column not in s:
            raise ResultError(f"{self.name}: no column {column} (it has {', '.join(s.columns)})")
        out = s[["axial_strain", column]]
        out.attrs = {"units": {k: s.attrs["units"].get(k) for k in ("axial_strain", column)}, "test": self.name}
        return out

    @property
    def yield_state(self) -> Optional[Dict[str, Any]]:
        """The state at the maximum of the smoothed stress ratio (docs/model.md, "How yield is read").

        summary.json's ``tests[].yield`` (``shape``, ``stress_ratio``,
        ``axial_strain``, ``sigma1_pa``, ``sigma3_effective_pa``,
        ``deviatoric_stress_pa``) when there is a summary; else the group's
        ``yield_*`` attributes (without q, which only the summary holds) and
        ``sample``. None when the curves could not be read.
        """
        if self.summary is not None:
            return self.summary.get("yield")
        a = self.attributes
        if "yield_stress_ratio" not in a:
            return None
        out = {"shape": a.get("yield_shape"), "stress_ratio": a["yield_stress_ratio"],
               "axial_strain": a.get("yield_axial_strain"), "sigma1_pa": a.get("yield_sigma1_pa"),
               "sigma3_effective_pa": a.get("yield_sigma3_effective_pa")}
        if "yield_sample" in a:
            out["sample"] = a["yield_sample"]
        return out

    @property
    def max_q_state(self) -> Dict[str, Any]:
        """The state at the raw maximum of q: ``deviatoric_stress_pa``, ``axial_strain``,
        ``sigma1_pa``, ``sigma3_effective_pa``, ``shape`` (peak, plateau, rising: of the
        smoothed q curve) and ``sample`` (its row in :attr:`series`).

        summary.json's ``tests[].peak_*`` when there is a summary, else the group's ``peak_*``
        attributes (the same numbers: the runner writes both).
        """
        a, s = self.attributes, self.summary
        state = {"deviatoric_stress_pa": a.get("peak_deviatoric_stress_pa"), "axial_strain": a.get("peak_axial_strain"),
                 "sigma1_pa": a.get("peak_sigma1_pa"), "sigma3_effective_pa": a.get("peak_sigma3_effective_pa"),
                 "shape": a.get("max_q_shape"), "sample": a.get("peak_sample")}
        if s is not None:
            state.update({"deviatoric_stress_pa": s.get("peak_deviatoric_stress_pa"),
                          "axial_strain": s.get("peak_axial_strain"), "sigma1_pa": s.get("sigma1_pa"),
                          "sigma3_effective_pa": s.get("sigma3_effective_pa"), "shape": s.get("max_q_shape")})
        return state

    @property
    def residual_stress_ratio(self) -> Optional[float]:
        """The mean raw stress ratio over the last end window of strain (None when unread)."""
        if self.summary is not None:
            return self.summary.get("residual_stress_ratio")
        return self.attributes.get("residual_stress_ratio")

    @property
    def quasi_static(self) -> bool:
        """The engine's verdict: I ≤ 10⁻³ and mean kinetic/elastic ≤ 10⁻² during loading."""
        return bool(self.attributes.get("quasi_static"))

    @property
    def warnings(self) -> List[str]:
        """The test's own warnings (not quasi-static, not consolidated, …)."""
        w = self.attributes.get("warnings")
        return list(json.loads(w)) if isinstance(w, str) and w else []

    def snapshot_near(self, axial_strain: float) -> Snapshot:
        """The snapshot whose measured axial strain is nearest the one given."""
        if not self.snapshots:
            raise ResultError(f"{self.name}: no snapshots")
        return min(self.snapshots, key=lambda s: abs(s.axial_strain - axial_strain))


def _phase_names(units: Optional[str]) -> Dict[int, str]:
    """{code: name} of a ``phase`` dataset whose units attribute lists them
    (``"0 removal, 1 settling, 2 dead_load, 3 loading, 4 pull_out"``): the file says
    what its codes mean, so a reader never keeps its own copy of the list."""
    names: Dict[int, str] = {}
    for part in (units or "").split(","):
        code, _, name = part.strip().partition(" ")
        if code.isdigit() and name:
            names[int(code)] = name.strip()
    return names


def _read_frame(path: Path, group: str, names: List[str], units: Dict[str, Optional[str]]) -> pd.DataFrame:
    with h5py.File(path, "r") as f:
        g = f[group]
        frame = pd.DataFrame({k: g[k][()] for k in names})
    frame.attrs["units"] = {k: units.get(k) for k in names}
    return frame


#: The free-standing group's per-segment datasets at the peak, and their names in :meth:`FreeStanding.wire_at_peak`.
_WIRE_AT_PEAK = {"wire_strain_at_peak": "strain", "wire_tension_at_peak_n": "tension_n"}


class FreeStanding:
    """The free-standing test (``/free_standing``; docs/model.md, "The free-standing test"):
    the formwork taken away, the column settling under its own weight, an optional dead
    load, then an unconfined compression or a pull-out of the wire.

    ``attributes`` are the group's attributes as the runner wrote them and ``summary``
    summary.json's ``free_standing`` block (None without summary.json); every figure is
    read from them, never recomputed. :attr:`series` is the time series of every phase,
    :attr:`compression` its loading rows, :meth:`profile` the column's radius against
    height, :attr:`pull_out` the pull's own rows.
    """

    def __init__(self, path: Path, summary: Optional[Dict[str, Any]]) -> None:
        self._path = path
        #: summary.json's ``free_standing`` block (None without summary.json)
        self.summary = summary
        with h5py.File(path, "r") as f:
            g = f["free_standing"]
            #: the group's attributes as the runner wrote them (docs/results.md)
            self.attributes: Dict[str, Any] = _attributes(g)
            units = _dataset_units(g)
            rows = g[_TIME].shape[0] if _TIME in g else 0
            # The series: the datasets with one entry per row (not the per-segment
            # ones at the peak, nor the volumetric strain a free column leaves empty).
            self._columns = {k: u for k, u in units.items() if g[k].ndim == 1 and g[k].shape[0] == rows and rows}
            self._per_segment = {k: u for k, u in units.items() if k in _WIRE_AT_PEAK}
            self._groups = {k: _dataset_units(g[k]) for k in g if isinstance(g[k], h5py.Group)
                            and k not in ("snapshots", "peak_snapshot")}
            #: {phase code: name}, as the file's ``phase`` dataset declares them
            self.phases: Dict[int, str] = _phase_names(units.get(_PHASE))
            snaps = []
            if "snapshots" in g and isinstance(g["snapshots"], h5py.Group):
                for k in g["snapshots"]:
                    snaps.append(Snapshot(path, g["snapshots"][k].name, _attributes(g["snapshots"][k]),
                                          _dataset_units(g["snapshots"][k])))
            #: the compression's snapshots (at 0, half and all of its target strain), by ascending strain
            self.snapshots: List[Snapshot] = sorted(snaps, key=lambda sn: (sn.axial_strain, sn.index or 0))
            #: the column at the largest σ₁ of the compression (None without one)
            self.peak_snapshot: Optional[Snapshot] = None
            if "peak_snapshot" in g and isinstance(g["peak_snapshot"], h5py.Group):
                p = g["peak_snapshot"]
                self.peak_snapshot = Snapshot(path, p.name, _attributes(p), _dataset_units(p))
        self._series: Optional[pd.DataFrame] = None

    def __repr__(self) -> str:
        verdict = "stands" if self.stands else "does not stand"
        return f"<FreeStanding: {verdict}, {len(self.series)} rows>"

    @property
    def stands(self) -> bool:
        """The engine's verdict (docs/model.md, "What stands"): at rest, with at most
        ``free_standing.max_height_loss`` of the grains' bulk height and at most
        ``free_standing.max_lost_fraction`` of their volume lost."""
        if self.summary is not None:
            return bool(self.summary["settling"]["stands"])
        return bool(self.attributes.get("stands"))

    @property
    def settling(self) -> Dict[str, Any]:
        """How the column settled once the formwork was gone: summary.json's
        ``free_standing.settling`` (``stands``, ``at_rest``, ``bulk_height_loss``,
        ``lost_fraction``, ``weight_n``, ``base_force_n``, …), else the same names
        from the group's attributes."""
        if self.summary is not None:
            return dict(self.summary["settling"])
        keys = ("stands", "at_rest", "time_to_rest_s", "height_before_m", "height_m", "height_loss",
                "radius_before_m", "radius_m", "bulk_height_before_m", "bulk_height_m", "bulk_height_loss", "grains",
                "escaped_grains", "lost_fraction", "weight_n", "base_force_n", "base_force_tolerance_n",
                "max_removal_kinetic_energy_j")
        out = {k: self.attributes[k] for k in keys if k in self.attributes}
        for k in ("stands", "at_rest"):
            if k in out:
                out[k] = bool(out[k])
        return out

    @property
    def dead_load(self) -> Optional[Dict[str, Any]]:
        """summary.json's ``free_standing.dead_load`` (``force_n``, ``stress_pa``, ``holds``,
        ``strain_at_load``, ``creep_strain``); None without a dead load or a summary."""
        return None if self.summary is None else self.summary.get("dead_load")

    @property
    def unconfined_compression(self) -> Optional[Dict[str, Any]]:
        """summary.json's ``free_standing.compression``: ``unconfined_strength_pa`` with its
        ``shape`` (peak, plateau or rising) and ``strain_at_failure``, ``max_sigma1_pa``,
        ``failed``, the envelope's ``predicted_unconfined_strength_pa``, ``quasi_static``, …;
        None without a summary."""
        return None if self.summary is None else self.summary.get("compression")

    @property
    def pull_out_figures(self) -> Optional[Dict[str, Any]]:
        """summary.json's ``free_standing.pull_out`` (``peak_pull_force_n``, ``pulled_length_m``,
        ``end``, …); None without a pull-out or a summary."""
        return None if self.summary is None else self.summary.get("pull_out")

    @property
    def warnings(self) -> List[str]:
        """The test's own warnings (not at rest, not quasi-static, …)."""
        w = self.attributes.get("warnings")
        return list(json.loads(w)) if isinstance(w, str) and w else []

    @property
    def units(self) -> Dict[str, Optional[str]]:
        """{column: units} of the time series."""
        return dict(self._columns)

    @property
    def series(self) -> pd.DataFrame:
        """The time series of every phase, one row per sample: ``time_s``, ``phase`` and
        ``phase_name`` (:attr:`phases`), ``axial_strain``, ``sigma1_pa`` (F_top/(π r₀²), r₀
        the settled column's equivalent radius), ``column_radius_m``, ``height_m``, the plate
        forces, energies and wire strains (docs/results.md); units in ``frame.attrs["units"]``."""
        if self._series is None:
            frame = _read_frame(self._path, "/free_standing", _series_order(self._columns), self._columns)
            units = frame.attrs["units"]
            if _PHASE in frame:
                frame.insert(2, "phase_name", frame[_PHASE].map(self.phases))
                units["phase_name"] = None
            frame.index.name = "sample"
            frame.attrs["units"] = units
            frame.attrs["test"] = "free_standing"
            self._series = frame
        out = self._series.copy()
        out.attrs = {"units": dict(self._series.attrs["units"]), "test": "free_standing"}
        return out

    def phase(self, name: str) -> pd.DataFrame:
        """The rows of one phase by its name (``removal``, ``settling``, ``dead_load``,
        ``loading``, ``pull_out``: :attr:`phases`)."""
        codes = [c for c, n in self.phases.items() if n == name]
        if not codes:
            raise ResultError(f"{self._path}: the free-standing test has no phase {name!r} "
                              f"(its phases: {', '.join(self.phases.values())})")
        s = self.series
        out = s[s[_PHASE] == codes[0]]
        out.attrs = dict(s.attrs)
        return out

    @property
    def compression(self) -> pd.DataFrame:
        """The unconfined compression's rows (phase ``loading``): σ₁ and the column against
        the axial strain. Empty when the job pulled the wire out instead."""
        return self.phase("loading")

    def profile(self, which: str = "settled") -> pd.DataFrame:
        """The column's radius against height: ``height_m``, ``radius_m`` (the equivalent radius
        of the slice's grains) and ``grains``, per slice of one grain diameter. ``which``:
        ``before`` (in the formwork), ``settled``, ``at_peak`` or ``at_end`` (of the compression)."""
        name = f"profile_{which}"
        if name not in self._groups:
            have = ", ".join(k[len("profile_"):] for k in self._groups if k.startswith("profile_"))
            raise ResultError(f"{self._path}: no profile {which!r} (it has {have})")
        frame = _read_frame(self._path, f"/free_standing/{name}", list(self._groups[name]), self._groups[name])
        frame.index.name = "slice"
        return frame

    @property
    def pull_out(self) -> Optional[pd.DataFrame]:
        """The pull-out's rows (``time_s``, ``pulled_length_m``, ``pull_force_n``,
        ``end_tension_n``, ``wire_in_column_m``, ``grains_in_column``); None without one."""
        if "pull_out" not in self._groups:
            return None
        frame = _read_frame(self._path, "/free_standing/pull_out", list(self._groups["pull_out"]),
                            self._groups["pull_out"])
        frame.index.name = "row"
        return frame

    def wire_at_peak(self) -> pd.DataFrame:
        """Per wire segment, in the order laid, at the compression's largest σ₁:
        ``strain`` and ``tension_n``."""
        names = _WIRE_AT_PEAK
        have = [k for k in names if k in self._per_segment]
        if not have:
            raise ResultError(f"{self._path}: the free-standing test holds no wire at its peak "
                              "(no wire, or no compression)")
        frame = _read_frame(self._path, "/free_standing", have, self._per_segment).rename(columns=names)
        frame.attrs["units"] = {names[k]: self._per_segment[k] for k in have}
        frame.index.name = "segment"
        return frame


class Result:
    """A campaign's results: ``result.h5`` and, when beside it, ``summary.json``.

    Open with :func:`wiredem.open`. ``tests`` are by ascending confining
    pressure; the Mohr–Coulomb fits and the summary's figures need
    ``summary.json`` (a bare ``result.h5`` has the series, states and snapshots).
    """

    def __init__(self, h5_path: Path, summary_path: Optional[Path]) -> None:
        self.path = h5_path  #: the result.h5
        #: summary.json as a dict, or None when there is none beside result.h5
        self.summary: Optional[Dict[str, Any]] = None
        if summary_path is not None:
            try:
                self.summary = json.loads(summary_path.read_text())
            except (OSError, ValueError) as e:
                raise ResultError(f"{summary_path}: not readable as JSON ({e})") from e
        try:
            f = h5py.File(h5_path, "r")
        except OSError as e:
            raise ResultError(f"{h5_path}: not an HDF5 file ({e})") from e
        with f:
            #: the root's ``format`` (``wiredem-result-1``), None in a file without it
            self.format: Optional[str] = _attr(f.attrs["format"]) if "format" in f.attrs else None
            if "job_spec" not in f or "tests" not in f:
                raise ResultError(f"{h5_path}: not a wiredem result (no /job_spec or /tests)")
            #: the job spec it ran with, every field (``api::to_json``)
            self.job_spec: Dict[str, Any] = json.loads(_text(f["job_spec"][()]))
            groups = [f["tests"][k].name for k in f["tests"]]
            has_free_standing = isinstance(f.get("free_standing"), h5py.Group)
        by_pressure = {}
        for t in (self.summary or {}).get("tests", []):
            by_pressure[float(t["confining_pressure_pa"])] = t
        tests = []
        for g in groups:
            probe = Test(h5_path, g, None)
            probe.summary = by_pressure.get(probe.confining_pressure_pa)
            tests.append(probe)
        #: the tests, by ascending confining pressure
        self.tests: List[Test] = sorted(tests, key=lambda t: t.confining_pressure_pa)
        self._specimen: Optional[Specimen] = None
        #: the free-standing test (None when the job ran none)
        self.free_standing: Optional[FreeStanding] = None
        if has_free_standing:
            self.free_standing = FreeStanding(h5_path, (self.summary or {}).get("free_standing"))

    def __repr__(self) -> str:
        return f"<Result {self.name!r}: {len(self.tests)} tests, {self.path}>"

    @property
    def name(self) -> str:
        """The job's name."""
        return str(self.job_spec.get("name", ""))

    @property
    def specimen(self) -> Specimen:
        """The prepared specimen."""
        if self._specimen is None:
            self._specimen = Specimen(self.path)
        return self._specimen

    def test(self, key: Union[str, float]) -> Test:
        """A test by its name (``sigma3_20000``) or its confining pressure [Pa]."""
        for t in self.tests:
            if (isinstance(key, str) and t.name == key) or (not isinstance(key, str)
                                                           and t.confining_pressure_pa == float(key)):
                return t
        raise ResultError(f"{self.path}: no test {key} (tests: {', '.join(t.name for t in self.tests)})")

    def _summary(self, what: str) -> Dict[str, Any]:
        if self.summary is None:
            raise ResultError(f"{self.path}: {what} is in summary.json, and there is none beside it")
        return self.summary

    @property
    def mohr_coulomb(self) -> MohrCoulomb:
        """The envelope through the yield states (summary ``mohr_coulomb``)."""
        return MohrCoulomb.from_json(self._summary("the Mohr-Coulomb fit").get("mohr_coulomb"))

    @property
    def mohr_coulomb_max_q(self) -> MohrCoulomb:
        """The envelope through the states at the maximum of q (summary ``mohr_coulomb_max_q``)."""
        return MohrCoulomb.from_json(self._summary("the Mohr-Coulomb fit").get("mohr_coulomb_max_q"))

    @property
    def warnings(self) -> List[str]:
        """summary.json's warnings (not settled, not quasi-static, fit or autocorrelation problems)."""
        return list(self._summary("the warnings").get("warnings", []))

    def stress_ratio_curves(self, loading_only: bool = True) -> Dict[float, pd.DataFrame]:
        """{σ₃ [Pa]: DataFrame of ``axial_strain`` and ``stress_ratio``} of every test."""
        return {t.confining_pressure_pa: t.curve("stress_ratio", loading_only) for t in self.tests}

    def tests_frame(self) -> pd.DataFrame:
        """One row per test: σ₃, the yield state (``yield_*``), the max-q state (``max_q_*``),
        the residual stress ratio and the quasi-static verdict, as the engine wrote them."""
        rows = []
        for t in self.tests:
            row: Dict[str, Any] = {"test": t.name, "confining_pressure_pa": t.confining_pressure_pa}
            y = t.yield_state or {}
            for k in ("stress_ratio", "axial_strain", "sigma1_pa", "sigma3_effective_pa", "deviatoric_stress_pa",
                      "shape"):
                row[f"yield_{k}"] = y.get(k)
            for k, v in t.max_q_state.items():
                if k != "sample":
                    row[f"max_q_{k}"] = v
            row["residual_stress_ratio"] = t.residual_stress_ratio
            row["quasi_static"] = t.quasi_static
            rows.append(row)
        return pd.DataFrame(rows).set_index("test")


def open_result(path: PathLike) -> Result:
    """Opens a result: a ``result.h5``, or a folder holding one (what ``wiredem run -o DIR``
    writes, ``wiredem fetch ID -o DIR`` downloads, or :meth:`Client.fetch` writes).

    ``summary.json`` beside the file is read too when it is there.
    """
    p = Path(os.fspath(path))
    if p.is_dir():
        h5 = p / "result.h5"
        if not h5.is_file():
            hint = " (a campaign that has not been analysed yet: run `wiredem analyse` on it)" \
                if (p / "tests").is_dir() or (p / "specimen.h5").is_file() else ""
            raise ResultError(f"{p}: no result.h5{hint}")
    elif p.is_file():
        h5 = p
    else:
        raise ResultError(f"{p}: no such file or folder")
    summary = h5.parent / "summary.json"
    return Result(h5, summary if summary.is_file() else None)

