#!/usr/bin/env python3
"""The study's columns standing on their own (docs/study.md, "The free-standing
column"): reads the free-standing test of each job directory given
(`wiredem prepare JOB -o DIR` then `wiredem test DIR --free-standing`, the jobs
in docs/study/free-standing/), writes one JSON record per directory into OUT (DIRNAME-result.json)
(what the summary's free_standing block holds, from tests/free_standing.h5),
prints the markdown table of docs/study.md (with the verdict of docs/model.md,
"What stands": the grains' bulk height and the grains lost; a run written
before it had them is re-read from its specimen and the compression's first
snapshot) and plots OUT/../figures/free_standing.png:
sigma_1 against the axial strain of the unconfined compression, and the
column's radius against height before the formwork was removed and after the
column settled.

The unconfined strength predicted by a Mohr-Coulomb envelope (phi, c) is
2 c cos(phi) / (1 - sin(phi)) (none when c <= 0): the envelope is taken from
the study's summary of the same pattern and seed (docs/study/PATTERN-seedK.json,
its mohr_coulomb), a check of the whole chain, not a tuning target.

    python3 scripts/free_standing_study.py DIR... [--out docs/study/free-standing] [--figure NAME.png]
"""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
LABELS = {"none": "no wire", "helix": "helix", "spiral_helix": "spiral helix", "radial_helix": "radially reinforced helix"}


def predicted_ucs_pa(phi_deg: float, c_pa: float) -> float | None:
    """The unconfined strength on the envelope: the circle through (0, 0) tangent to it."""
    if c_pa <= 0:
        return None
    phi = math.radians(phi_deg)
    return 2 * c_pa * math.cos(phi) / (1 - math.sin(phi))


def attribute(g: h5py.Group, name: str, default=None):
    v = g.attrs.get(name, default)
    if isinstance(v, bytes):
        return v.decode()
    return v.item() if hasattr(v, "item") else v


def profile(g: h5py.Group, name: str) -> dict | None:
    if name not in g:
        return None
    p = g[name]
    return {k: [float(x) for x in p[k][:]] for k in ("height_m", "radius_m", "grains")}


def given_in(sparse, full) -> bool:
    """Whether every field of `sparse` (a job as written by hand) has its value in
    `full` (the job as wiredem wrote it, every default filled in)."""
    if isinstance(sparse, dict):
        return isinstance(full, dict) and all(k in full and given_in(v, full[k]) for k, v in sparse.items())
    return sparse == full


def bulk_height_m(x, radius, bottom_m: float, escape_m: float, q: float) -> float:
    """The grains' bulk height z_q / q of engine::bulk_height_m (docs/model.md,
    "What stands"): z_q the height above the plate below which the share q of
    the standing grains' volume lies, each grain its sphere cut by the plane (a
    cap); spheres only (the study's grains)."""
    import numpy as np

    x, r = np.asarray(x), np.asarray(radius).reshape(-1)
    keep = np.hypot(x[:, 0], x[:, 1]) <= escape_m
    base, r = x[keep, 2] - r[keep], r[keep]
    if not len(r):
        return 0.0

    def below(z):
        h = np.clip(z - base, 0.0, 2 * r)
        return float(np.sum(math.pi * h * h * (3 * r - h) / 3))

    lo, hi = float(base.min()), float((base + 2 * r).max())
    target = q * below(hi)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if not lo < mid < hi:
            break
        lo, hi = (mid, hi) if below(mid) < target else (lo, mid)
    return (hi - bottom_m) / q


def reread_verdict(d: Path, g: h5py.Group, job: dict) -> dict | None:
    """For a run written before the verdict read the grains' bulk (2026-12-06):
    the bulk heights and the grains lost from the prepared specimen (before the
    removal) and the compression's first snapshot (the settled column, at
    rest or where the settling stopped), with the job's bounds; None without
    that snapshot."""
    import numpy as np

    snaps = g.get("snapshots")
    if snaps is None or "snapshot_0" not in snaps:
        return None
    fs = job.get("free_standing", {})
    escape = fs.get("escape_distance_m") or 1.5 * job["specimen"]["membrane_radius_m"]
    q = fs.get("bulk_fraction", 0.95)
    with h5py.File(d / "specimen.h5", "r") as sp:
        bottom = float(sp["walls"]["0"]["point_m"][:].reshape(-1)[2])
        x0, r0 = sp["bodies"]["grain"]["x0"][:], sp["bodies"]["grain"]["radius_m"][:].reshape(-1)
    s = snaps["snapshot_0"]
    x1, r1 = s["grain_position_m"][:], s["grain_radius_m"][:].reshape(-1)
    before, after = bulk_height_m(x0, r0, bottom, escape, q), bulk_height_m(x1, r1, bottom, escape, q)
    gone = np.hypot(x1[:, 0], x1[:, 1]) > escape
    lost = float(np.sum(r1[gone] ** 3) / np.sum(r1 ** 3))
    loss = (before - after) / before
    return {"bulk_height_before_m": before, "bulk_height_m": after, "bulk_height_loss": loss, "lost_fraction": lost,
            "stands": bool(attribute(g, "at_rest", 0)) and loss <= fs.get("max_height_loss", 0.1)
            and lost <= fs.get("max_lost_fraction", 0.1), "reread": True}


def read_run(d: Path) -> dict:
    job = json.loads((d / "job.json").read_text())
    pattern = job["specimen"].get("wire", {}).get("pattern", "helix")
    with h5py.File(d / "tests" / "free_standing.h5", "r") as f:
        g = f["free_standing"]
        rec = {
            "dir": str(d),
            "pattern": pattern,
            "seed": job.get("seed", 1),
            "rolling_friction_coeff": job.get("contact", {}).get("rolling_friction_coeff", 0),
            "wire_cuts": len(job["specimen"].get("wire", {}).get("cuts_at_m", [])),
            "cut_every_loops": job["specimen"].get("wire", {}).get("cut_every_loops", 0),
            "stands": bool(attribute(g, "stands", 0)),
            "at_rest": bool(attribute(g, "at_rest", 0)),
            "time_to_rest_s": attribute(g, "time_to_rest_s"),
            "height_before_m": attribute(g, "height_before_m"),
            "height_m": attribute(g, "height_m"),
            "height_loss": attribute(g, "height_loss"),
            "radius_before_m": attribute(g, "radius_before_m"),
            "radius_m": attribute(g, "radius_m"),
            "escaped_grains": attribute(g, "escaped_grains"),
            "weight_n": attribute(g, "weight_n"),
            "base_force_n": attribute(g, "base_force_n"),
            "max_removal_kinetic_energy_j": attribute(g, "max_removal_kinetic_energy_j"),
            "steps": attribute(g, "steps"),
            "time_step_s": attribute(g, "time_step_s"),
            "wall_time_s": attribute(g, "wall_time_s"),
            "threads": attribute(g, "threads"),
            "quasi_static": bool(attribute(g, "quasi_static", 0)),
            "max_inertial_number": attribute(g, "max_inertial_number"),
            "warnings": json.loads(attribute(g, "warnings", "[]") or "[]"),
            "profile_before": profile(g, "profile_before"),
            "profile_settled": profile(g, "profile_settled"),
        }
        if "bulk_height_m" in g.attrs:
            for k in ("bulk_height_before_m", "bulk_height_m", "bulk_height_loss", "grains", "lost_fraction"):
                rec[k] = attribute(g, k)
        elif (v := reread_verdict(d, g, job)) is not None:
            rec["verdict_as_recorded"] = rec["stands"]
            rec.update(v)
        if "strength_smoothed_maximum" in g.attrs:
            rec["compression"] = {
                "unconfined_strength_pa": attribute(g, "strength_smoothed_maximum"),
                "shape": attribute(g, "strength_shape"),
                "strength_axial_strain": attribute(g, "strength_axial_strain"),
                "max_sigma1_pa": attribute(g, "max_sigma1_pa"),
                "failed": bool(attribute(g, "failed", 0)),
            }
            if "failure_mode" in g.attrs:  # how it failed (docs/model.md, "How it failed"): runs since 2026-12-06
                for k in ("failure_mode", "spilled_fraction", "bulge_m"):
                    rec["compression"][k] = attribute(g, k)
        phase = g["phase"][:]
        loading = phase == 3
        rec["curve"] = {
            "axial_strain": [float(x) for x in g["axial_strain"][:][loading]],
            "sigma1_pa": [float(x) for x in g["sigma1_pa"][:][loading]],
        }
    # The envelope of the study's campaign of the same column: only when the
    # job prepares the study's specimen (examples/paper-*.json) with that seed.
    study = ROOT / "docs" / "study" / f"{pattern}-seed{rec['seed']}.json"
    paper = ROOT / "examples" / f"paper-{pattern.replace('_', '-')}.json"
    same_column = False
    if paper.exists():
        ref = json.loads(paper.read_text())
        # The same specimen and the same contact law (the study's has no rolling resistance).
        contact = dict({"rolling_friction_coeff": 0}, **ref.get("contact", {}))
        # (A cut wire is another column: the study's wire is whole.)
        same_column = (given_in(ref["specimen"], job["specimen"]) and given_in(contact, job.get("contact", {}))
                       and not rec["wire_cuts"] and not rec["cut_every_loops"])
    if study.exists() and same_column:
        mc = json.loads(study.read_text())["mohr_coulomb"]
        rec["envelope"] = {"source": str(study.relative_to(ROOT)), "friction_angle_deg": mc["friction_angle_deg"],
                           "cohesion_pa": mc["cohesion_pa"],
                           "predicted_unconfined_strength_pa": predicted_ucs_pa(mc["friction_angle_deg"], mc["cohesion_pa"])}
    return rec


def column_label(r: dict) -> str:
    """The column a run is a sample of: its pattern, its wire's cuts and its contact law (seeds pooled)."""
    mu_r, cuts, every = r["rolling_friction_coeff"], r.get("wire_cuts", 0), r.get("cut_every_loops", 0)
    return (LABELS.get(r["pattern"], r["pattern"]) + (f", wire cut at {cuts} places" if cuts else "")
            + (f", wire cut every {every} loops" if every else "") + (f", μ_r = {mu_r}" if mu_r else ""))


def by_column(runs: list[dict]) -> dict[str, list[dict]]:
    """The runs grouped by column_label, in the order first given, each group by seed."""
    groups: dict[str, list[dict]] = {}
    for r in runs:
        groups.setdefault(column_label(r), []).append(r)
    return {k: sorted(v, key=lambda r: r["seed"]) for k, v in groups.items()}


def mean_sd(values: list[float], scale: float = 1.0, digits: int = 1) -> str:
    """mean ± sample standard deviation (n − 1), scaled; the value alone for one; "—" for none."""
    xs = [scale * v for v in values if v is not None]
    if not xs:
        return "—"
    m = sum(xs) / len(xs)
    if len(xs) == 1:
        return f"{m:.{digits}f}"
    sd = math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1))
    return f"{m:.{digits}f} ± {sd:.{digits}f}"


def print_seed_table(groups: dict[str, list[dict]]) -> None:
    """Per column, over its seeds: how many stand, and the mean ± standard
    deviation of the bulk height's loss, the settled radius, the volume lost
    and the unconfined strength (the runs that recorded one, counted)."""
    print("| column | seeds | stand | at rest | bulk height loss [%] | radius after [mm] | volume lost [%] "
          "| unconfined strength [kPa] (runs with one) | steps | wall time [s] |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for label, group in groups.items():
        n = len(group)
        ucs = [r["compression"]["unconfined_strength_pa"] for r in group if r.get("compression")]
        print(f"| {label} | {', '.join(str(r['seed']) for r in group)} "
              f"| {sum(r['stands'] for r in group)} of {n} | {sum(r['at_rest'] for r in group)} of {n} "
              f"| {mean_sd([r.get('bulk_height_loss') for r in group], 100)} "
              f"| {mean_sd([r['radius_m'] for r in group], 1e3)} "
              f"| {mean_sd([r.get('lost_fraction') for r in group], 100, 0)} "
              f"| {mean_sd(ucs, 1e-3, 2)} ({len(ucs)} of {n}) "
              f"| {mean_sd([r['steps'] for r in group], 1, 0)} | {mean_sd([r['wall_time_s'] for r in group], 1, 0)} |")


def kpa(x: float | None) -> str:
    return "—" if x is None else f"{x / 1e3:.2f}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dirs", nargs="+", type=Path)
    ap.add_argument("--out", type=Path, default=ROOT / "docs/study/free-standing")
    ap.add_argument("--figure", default="free_standing.png",
                    help="the figure's file name under docs/study/figures (default free_standing.png)")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    runs = [read_run(d) for d in args.dirs]
    for r in runs:
        record = {k: v for k, v in r.items() if k not in ("curve", "dir")}
        (args.out / f"{Path(r['dir']).name}-result.json").write_text(json.dumps(record, indent=2) + "\n")

    print("| pattern | stands | grains' bulk height before → after [mm] (change) | top (grain or wire) change "
          "| radius before → after [mm] | grains escaped (share of the volume) | at rest after [s] "
          "| unconfined strength [kPa] (shape, ε₁) | predicted by the seed's envelope [kPa] | steps, wall time |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in runs:
        c = r.get("compression")
        ucs = f"{kpa(c['unconfined_strength_pa'])} ({c['shape']}, {c['strength_axial_strain']:.3f})" if c else "—"
        env = r.get("envelope")
        pred = "—"
        if env:
            p = env["predicted_unconfined_strength_pa"]
            pred = (f"{kpa(p)} (φ = {env['friction_angle_deg']:.1f}°, c = {env['cohesion_pa'] / 1e3:.1f} kPa)" if p
                    else f"none (c = {env['cohesion_pa'] / 1e3:.1f} kPa ≤ 0)")
        label = column_label(r) + f", seed {r['seed']}"
        stands = "yes" if r["stands"] else "no"
        if "verdict_as_recorded" in r:  # re-read: the run's own file has the top's verdict
            stands += f" (recorded: {'yes' if r['verdict_as_recorded'] else 'no'}, read from the top)"
        bulk = (f"{1e3 * r['bulk_height_before_m']:.1f} → {1e3 * r['bulk_height_m']:.1f} ({-100 * r['bulk_height_loss']:+.1f} %)"
                if "bulk_height_m" in r else "—")
        lost = f" ({100 * r['lost_fraction']:.0f} %)" if "lost_fraction" in r else ""
        print(f"| {label} | {stands} | {bulk} | {-100 * r['height_loss']:+.1f} % "
              f"| {1e3 * r['radius_before_m']:.1f} → {1e3 * r['radius_m']:.1f} | {r['escaped_grains']}{lost} "
              f"| {r['time_to_rest_s']:.3f}{'' if r['at_rest'] else ' (not at rest)'} | {ucs} | {pred} "
              f"| {r['steps']}, {r['wall_time_s']:.0f} s on {r['threads']} |")

    groups = by_column(runs)
    if any(len(g) > 1 for g in groups.values()):
        print()
        print_seed_table(groups)

    # One colour per column (pattern and law), one line style per seed; the
    # profile before the removal of each column's first run only.
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
    for i, (label, group) in enumerate(groups.items()):
        colour = f"C{i % 10}"
        for j, r in enumerate(group):
            style = ["-", "--", "-.", ":"][j % 4]
            name = f"{label}, seed {r['seed']}"
            if r["curve"]["axial_strain"]:
                ax1.plot(r["curve"]["axial_strain"], [s / 1e3 for s in r["curve"]["sigma1_pa"]], style, color=colour,
                         label=name)
            p = r["profile_settled"]
            if p:
                ax2.plot([1e3 * x for x in p["radius_m"]], [1e3 * z for z in p["height_m"]], style, color=colour,
                         label=f"{name}, settled")
            p = r["profile_before"]
            if p and j == 0:
                ax2.plot([1e3 * x for x in p["radius_m"]], [1e3 * z for z in p["height_m"]], ":", color=colour,
                         alpha=0.6, label=f"{label}, before removal")
    ax1.set_xlabel("axial strain ε₁")
    ax1.set_ylabel("σ₁ [kPa] (top plate)")
    ax1.set_title("unconfined compression")
    ax1.legend(fontsize=8)
    ax2.set_xlabel("radius [mm]")
    ax2.set_ylabel("height [mm]")
    ax2.set_title("the column's radius, before and after the formwork went")
    ax2.legend(fontsize=7)
    fig.tight_layout()
    figures = ROOT / "docs/study/figures"
    figures.mkdir(parents=True, exist_ok=True)
    fig.savefig(figures / args.figure, dpi=120)


if __name__ == "__main__":
    main()
