#!/usr/bin/python3
"""The calibration of the "gravel" grain preset (docs/model.md, "A calibrated
gravel"; issue 40 part 4): the angle of repose of a heap left by a column
without wire whose formwork is opened slowly (the free-standing test as a
lifting-cylinder test), read from the heap's final radius profile, and the
friction angle of a small triaxial campaign.

    /usr/bin/python3 scripts/gravel_calibration.py self-test
        the angle reading on synthetic heaps of known angle (no simulation)
    /usr/bin/python3 scripts/gravel_calibration.py jobs
        writes the calibration's job files into docs/calibration/gravel/
        (the preset's grading, clump and mu read from api/grain_presets.hpp)
    /usr/bin/python3 scripts/gravel_calibration.py report DIR...
        reads the job directories `wiredem run JOB --output DIR` wrote, prints
        each run's angle of repose (profile and surface readings) or friction
        angle, writes docs/calibration/gravel/calibration.json and
        docs/calibration/gravel/calibration.png

The angle of repose, two readings of one heap (its grains at rest after the
formwork was removed, tests/free_standing.h5):
  * profile: the free-standing test's radius profile after settling
    (/free_standing/profile_settled: per horizontal slice of one mean sphere
    diameter, the equivalent radius sqrt(2 <rho^2>) + <r> of the spheres in
    it, which is the radius of a disc the slice fills uniformly). A cone of
    slope theta has r(h) = r_0 - h / tan(theta): the slope dr/dh of a
    least-squares line through the flank's slices gives theta =
    atan(-1 / slope). The flank is the slices above the lowest (which holds
    the grains that ran out on the plate) and below the highest (the apex,
    a few grains).
  * surface: the heap's top surface from the grains at rest
    (/free_standing/snapshots/snapshot_0, the first snapshot of the
    compression, before the plate touches): the highest sphere top in rings
    of one mean sphere diameter about the axis, fitted by a line between
    1/4 and 3/4 of the radius that holds 95 % of the spheres; theta =
    atan(-slope).
Both are tried on synthetic heaps of known angle (self-test).
"""
from __future__ import annotations

import argparse
import json
import math
import re
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "docs" / "calibration" / "gravel"
# Published targets (docs/model.md, "A calibrated gravel", with what could and
# could not be checked of each).
TARGET_REPOSE_DEG = (38.0, 42.0)    # crushed (angular) rock dumped in heaps
TARGET_PEAK_PHI_DEG = (45.0, 55.0)  # crushed-rock ballast in large triaxial tests at low confinement


# ------------------------------------------------------------------ readings

def line_fit(x: np.ndarray, y: np.ndarray) -> tuple[float, float]:
    """Least-squares slope of y against x and its standard error."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    a = np.vstack([x, np.ones_like(x)]).T
    coef, res, *_ = np.linalg.lstsq(a, y, rcond=None)
    n = len(x)
    if n < 3:
        return float(coef[0]), float("nan")
    resid = y - a @ coef
    s2 = float(resid @ resid) / (n - 2)
    se = math.sqrt(s2 / float(((x - x.mean()) ** 2).sum()))
    return float(coef[0]), se


def profile_angle_deg(height_m, radius_m) -> tuple[float, float, int]:
    """The flank's angle from a radius profile (see the module's text):
    (angle, its standard error from the fit, slices used)."""
    h, r = np.asarray(height_m, float), np.asarray(radius_m, float)
    keep = (np.arange(len(h)) >= 1) & (np.arange(len(h)) < len(h) - 1)
    if keep.sum() < 3:
        return float("nan"), float("nan"), int(keep.sum())
    slope, se = line_fit(h[keep], r[keep])
    angle = math.degrees(math.atan(-1.0 / slope))
    # d(theta)/d(slope) = 1 / (1 + slope^2) for theta = atan(-1/slope)
    return angle, math.degrees(se / (1.0 + slope * slope)), int(keep.sum())


def surface_angle_deg(position_m, radius_m) -> tuple[float, float, int]:
    """The heap's top surface against the distance from the axis (see the
    module's text): (angle, its standard error, rings used)."""
    p, r = np.asarray(position_m, float), np.asarray(radius_m, float)
    rho = np.hypot(p[:, 0], p[:, 1])
    top = p[:, 2] - (p[:, 2] - r).min() + r   # above the bottom plate
    d = 2.0 * r.mean()
    edge = np.sort(rho + r)[int(math.ceil(0.95 * len(r))) - 1]
    rings = np.arange(0.0, edge + d, d)
    x, y = [], []
    for lo in rings:
        inside = (rho >= lo) & (rho < lo + d)
        if inside.any():
            x.append(lo + 0.5 * d)
            y.append(top[inside].max())
    x, y = np.array(x), np.array(y)
    keep = (x >= 0.25 * edge) & (x <= 0.75 * edge)
    if keep.sum() < 3:
        return float("nan"), float("nan"), int(keep.sum())
    slope, se = line_fit(x[keep], y[keep])
    return math.degrees(math.atan(-slope)), math.degrees(se / (1.0 + slope * slope)), int(keep.sum())


def equivalent_radius_profile(position_m, radius_m):
    """The engine's radius profile (engine/triaxial/free_standing.cpp,
    radius_profile and equivalent_radius_m), for the synthetic heaps: slices
    of one mean diameter from the bottom plate up, sqrt(2 <rho^2>) + <r>."""
    p, r = np.asarray(position_m, float), np.asarray(radius_m, float)
    z = p[:, 2] - (p[:, 2] - r).min()
    d = 2.0 * r.mean()
    h, rr = [], []
    for k in range(int(z.max() // d) + 1):
        s = (z >= k * d) & (z < (k + 1) * d)
        if s.any():
            rho2 = (p[s, 0] ** 2 + p[s, 1] ** 2).mean()
            h.append((k + 0.5) * d)
            rr.append(math.sqrt(2.0 * rho2) + r[s].mean())
    return np.array(h), np.array(rr)


# ------------------------------------------------------------- synthetic heaps

def synthetic_heap(angle_deg: float, base_radius_m: float, radius_m: float, seed: int, fringe: bool):
    """A cone of the given slope filled at random with sphere centres that
    keep one radius inside its surface (about 0.55 of its volume; overlaps do
    not matter to either reading), on a plate at z = 0; with `fringe`, a layer
    of grains that ran out on the plate to 1.3 times the base radius."""
    rng = np.random.default_rng(seed)
    t = math.tan(math.radians(angle_deg))
    height = base_radius_m * t
    n = int(0.55 * (math.pi / 3) * base_radius_m ** 2 * height / ((4 / 3) * math.pi * radius_m ** 3))
    pts = []
    while len(pts) < n:
        q = rng.uniform([-base_radius_m, -base_radius_m, radius_m], [base_radius_m, base_radius_m, height], size=(4 * n, 3))
        rho = np.hypot(q[:, 0], q[:, 1])
        inside = rho <= (height - q[:, 2]) / t - radius_m / math.sin(math.atan(t))
        pts.extend(q[inside][: n - len(pts)])
    pts = np.array(pts)
    if fringe:
        k = n // 10
        a = rng.uniform(0, 2 * math.pi, k)
        rho = rng.uniform(0.8 * base_radius_m, 1.3 * base_radius_m, k)
        pts = np.vstack([pts, np.c_[rho * np.cos(a), rho * np.sin(a), np.full(k, radius_m)]])
    return pts, np.full(len(pts), radius_m)


def self_test() -> int:
    """Both readings on synthetic heaps of 30, 40 and 50 degrees, five seeds
    each, a heap eight and twenty grain diameters in base radius, with and
    without a run-out fringe. Prints the mean and spread of each reading."""
    rows = []
    worst = 0.0
    for base_in_d in (8, 20):
        for fringe in (False, True):
            for angle in (30.0, 40.0, 50.0):
                prof, surf = [], []
                for seed in range(5):
                    pos, rad = synthetic_heap(angle, base_in_d * 2e-3, 1e-3, seed, fringe)
                    h, r = equivalent_radius_profile(pos, rad)
                    prof.append(profile_angle_deg(h, r)[0])
                    surf.append(surface_angle_deg(pos, rad)[0])
                rows.append((base_in_d, fringe, angle, np.mean(prof), np.std(prof), np.mean(surf), np.std(surf)))
                if base_in_d == 8:
                    worst = max(worst, abs(np.mean(prof) - angle))
    print("base/d fringe  true   profile (mean, sd)   surface (mean, sd)")
    for b, f, a, pm, ps, sm, ss in rows:
        print(f"{b:6d} {str(f):6s} {a:5.1f}   {pm:6.2f} {ps:5.2f}        {sm:6.2f} {ss:5.2f}")
    print(f"largest bias of the profile reading, heaps 8 diameters in radius: {worst:.2f} deg")
    return 0


# ---------------------------------------------------------------------- jobs

def preset_values() -> dict:
    """The gravel preset's grading, clump and friction, read from
    api/grain_presets.hpp (where they are defined once)."""
    text = (ROOT / "api" / "grain_presets.hpp").read_text()
    block = text[text.index("gravel_preset{"):]
    block = block[: block.index("};")]
    arrays = re.findall(r"\{([^{}]*)\}", block[len("gravel_preset{"):])
    sieve = [float(x) for x in arrays[0].split(",")]
    passing = [float(x) for x in arrays[1].split(",")]
    tail = block[block.rindex("}") + 1:]
    numbers = [float(x) for x in re.findall(r"[-+]?\d*\.\d+|\d+", tail)]
    template = re.findall(r'"([a-z]+)"', block)[1]
    return {"sieve_mm": sieve, "passing": passing, "template": template, "mu": numbers[0], "mu_r": numbers[1],
            "eta_r": numbers[2]}


def d50_mm(sieve, passing) -> float:
    for k in range(len(passing) - 1):
        if passing[k] <= 0.5 <= passing[k + 1]:
            t = (0.5 - passing[k]) / (passing[k + 1] - passing[k])
            return sieve[k] * (sieve[k + 1] / sieve[k]) ** t
    raise ValueError("no D50")


GRAIN_RADIUS_M = 1.2e-3      # D50 = 2.4 mm: the column 5.2 D50 in radius, the narrowest the clumps allow
COLUMN = {"membrane_radius_m": 0.0125, "membrane_height_m": 0.06, "grain_count": 800,
          "grain": {"youngs_modulus_pa": 1e6, "density_kg_per_m3": 2650},
          "membrane": {"youngs_modulus_pa": 1e6}, "wire": {"pattern": "none"},
          "pouring": {"max_preparation_time_s": 0.8, "settle_kinetic_energy_per_grain_j": 1e-8}}
# The one triaxial test the campaign needs before its free-standing test: a
# token (0.2 % strain); the heap is what is measured.
TOKEN_TRIAXIAL = {"confining_pressures_pa": [10000], "target_axial_strain": 0.002, "plate_speed_m_per_s": 0.05,
                  "pressure_ramp_time_s": 0.002, "hold_time_s": 0.002, "sample_interval_s": 0.001,
                  "snapshot_strains": [0.002]}
# The formwork opened by 4 mm over 0.1 s (0.04 m/s, a tenth of sqrt(g H) for
# the 19 mm column: the slow release of a lifting-cylinder test), then 0.4 s to
# come to rest; every grain counts (escape distance 0.1 m).
SLOW_RELEASE = {"enabled": True, "removal_time_s": 0.1, "removal_distance_m": 0.004, "escape_distance_m": 0.1,
                "max_settling_time_s": 0.4, "settle_kinetic_energy_per_grain_j": 1e-9, "plate_speed_m_per_s": 0.05,
                "target_axial_strain": 0.005,
                "sample_interval_s": 0.002}


def repose_job(mu_r: float | None, seed: int = 1) -> dict:
    """A heap of the preset's grains with rolling resistance mu_r (the
    preset itself when None), poured from `seed`."""
    p = preset_values()
    spec = dict(COLUMN)
    contact = {}
    if mu_r is None:
        spec.update({"grain_radius_m": GRAIN_RADIUS_M, "grain_preset": "gravel"})
        name = "gravel preset: angle of repose"
    else:
        scale = 2 * GRAIN_RADIUS_M / (d50_mm(p["sieve_mm"], p["passing"]) * 1e-3)
        spec["grain_sizes"] = {"basis": "mass", "diameters_m": [round(d * 1e-3 * scale, 9) for d in p["sieve_mm"]],
                               "fraction_passing": p["passing"]}
        spec["grain_shape"] = {"template": p["template"]}
        contact = {"friction_coeff": p["mu"], "rolling_friction_coeff": mu_r, "rolling_damping_ratio": p["eta_r"]}
        name = f"gravel calibration: angle of repose, mu_r = {mu_r}"
    return {"name": name,
            "comment": "scripts/gravel_calibration.py jobs (docs/model.md, 'A calibrated gravel'): 800 clumps of the gravel preset's grading and shape in a 12.5 mm formwork (19 mm high), soft grains (E = 1 MPa: under a heap's own weight the overlaps stay below 1 % of a radius), the formwork opened slowly by the free-standing test; the heap's angle is read from its settled radius profile",
            "seed": seed, "specimen": spec, "contact": contact, "triaxial": TOKEN_TRIAXIAL,
            "free_standing": SLOW_RELEASE, "engine": {"threads": 1}}


def triaxial_job(mu_r: float | None, quick: bool = False) -> dict:
    """The preset's grains in a small membrane campaign at two pressures: its
    Mohr-Coulomb friction angle; rolling resistance mu_r (the preset itself
    when None). `quick`: the first check, 400 clumps, a plate twice as fast and
    a shorter hold."""
    p = preset_values()
    spec = dict(COLUMN)
    spec.update({"grain_radius_m": GRAIN_RADIUS_M, "grain_count": 400 if quick else 600,
                 "grain": {"youngs_modulus_pa": 1e8, "density_kg_per_m3": 2650},
                 "membrane": {"youngs_modulus_pa": 1e7}, "membrane_height_m": 0.04 if quick else 0.05,
                 "pouring": {"max_preparation_time_s": 0.8, "settle_kinetic_energy_per_grain_j": 1e-8}})
    contact = {}
    if mu_r is None:
        spec["grain_preset"] = "gravel"
        name = "gravel preset: triaxial friction angle"
    else:
        scale = 2 * GRAIN_RADIUS_M / (d50_mm(p["sieve_mm"], p["passing"]) * 1e-3)
        spec["grain_sizes"] = {"basis": "mass", "diameters_m": [round(d * 1e-3 * scale, 9) for d in p["sieve_mm"]],
                               "fraction_passing": p["passing"]}
        spec["grain_shape"] = {"template": p["template"]}
        del spec["grain_radius_m"]  # the curve sets every size
        contact = {"friction_coeff": p["mu"], "rolling_friction_coeff": mu_r, "rolling_damping_ratio": p["eta_r"]}
        name = f"gravel calibration: triaxial friction angle, mu_r = {mu_r}" + (", quick" if quick else "")
    return {"name": name,
            "comment": f"scripts/gravel_calibration.py jobs (docs/model.md, 'A calibrated gravel'): {spec['grain_count']} clumps of the gravel preset's grading and shape in a 12.5 mm membrane, two confining pressures, mass scaling 100 and a fast plate: a check of phi, not a quasi-static laboratory test",
            "seed": 1, "specimen": spec, "contact": contact,
            "triaxial": {"confining_pressures_pa": [10000, 20000], "target_axial_strain": 0.08,
                         "plate_speed_m_per_s": 0.02 if quick else 0.01, "pressure_ramp_time_s": 0.005,
                         "hold_time_s": 0.01 if quick else 0.03, "sample_interval_s": 0.0005, "snapshot_strains": [0.08]},
            "engine": {"density_scale": 100, "threads": 1}}


def write_jobs() -> int:
    OUT.mkdir(parents=True, exist_ok=True)
    for mu_r in (0.1, 0.3, 0.35, 0.4):
        (OUT / f"repose-mu_r-{mu_r}.json").write_text(json.dumps(repose_job(mu_r), indent=1) + "\n")
    (OUT / "repose-mu_r-0.35-seed2.json").write_text(json.dumps(repose_job(0.35, seed=2), indent=1) + "\n")
    (OUT / "repose-preset.json").write_text(json.dumps(repose_job(None), indent=1) + "\n")
    # The first check ran the preset while its mu_r was 0.1 (before the calibration): written out.
    (OUT / "triaxial-quick-mu_r-0.1.json").write_text(json.dumps(triaxial_job(0.1, quick=True), indent=1) + "\n")
    for mu_r in (0.3, 0.4):
        (OUT / f"triaxial-mu_r-{mu_r}.json").write_text(json.dumps(triaxial_job(mu_r), indent=1) + "\n")
    print(f"wrote the jobs into {OUT.relative_to(ROOT)}")
    return 0


# -------------------------------------------------------------------- report

def read_run(d: Path) -> dict:
    import h5py
    job = json.loads((d / "job.json").read_text())
    summary = json.loads((d / "summary.json").read_text())
    c = job.get("contact", {})
    sp = job["specimen"]
    rec = {"dir": d.name, "name": job["name"], "grains": sp["grain_count"], "preset": sp.get("grain_preset"),
           "mu": c.get("friction_coeff"), "mu_r": c.get("rolling_friction_coeff")}
    if rec["preset"]:
        p = preset_values()
        rec["mu"], rec["mu_r"] = p["mu"], p["mu_r"]
    fs = d / "tests" / "free_standing.h5"
    if fs.exists():
        with h5py.File(fs) as f:
            g = f["free_standing"]
            prof = g["profile_settled"]
            before = g["profile_before"]
            a, se, n = profile_angle_deg(prof["height_m"][:], prof["radius_m"][:])
            snap = g["snapshots"][sorted(g["snapshots"].keys())[0]]
            sa, sse, sn = surface_angle_deg(snap["grain_position_m"][:], snap["grain_radius_m"][:])
            rec.update({"repose_profile_deg": a, "repose_profile_se_deg": se, "profile_slices": n,
                        "repose_surface_deg": sa, "repose_surface_se_deg": sse, "surface_rings": sn,
                        "profile_settled": {"height_m": prof["height_m"][:].tolist(), "radius_m": prof["radius_m"][:].tolist()},
                        "profile_before": {"height_m": before["height_m"][:].tolist(), "radius_m": before["radius_m"][:].tolist()}})
        st = summary["free_standing"]["settling"]
        rec.update({"at_rest": st["at_rest"], "time_to_rest_s": st["time_to_rest_s"],
                    "height_before_m": st["height_before_m"], "height_m": st["height_m"],
                    "radius_before_m": st["radius_before_m"]})
    mc = summary.get("mohr_coulomb")
    if mc and not fs.exists():
        rec.update({"phi_deg": mc.get("friction_angle_deg"), "cohesion_pa": mc.get("cohesion_pa"),
                    "phi_c0_deg": (mc.get("cohesionless") or {}).get("friction_angle_deg"),
                    "grain_volume_fraction": summary["specimen"]["grain_volume_fraction"],
                    "pile_height_m": summary["specimen"]["pile_height_m"]})
        rec["tests"] = [{"sigma3_pa": t.get("confining_pressure_pa"),
                         "sigma3_effective_pa": (t.get("yield") or {}).get("sigma3_effective_pa"),
                         "sigma1_pa": (t.get("yield") or {}).get("sigma1_pa"),
                         "yield_shape": (t.get("yield") or {}).get("shape")} for t in summary.get("tests", [])]
    return rec


def report(dirs: list[str]) -> int:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    recs = [read_run(Path(d)) for d in dirs]
    OUT.mkdir(parents=True, exist_ok=True)
    (OUT / "calibration.json").write_text(json.dumps(recs, indent=1) + "\n")
    fig, (ax1, ax2, ax3) = plt.subplots(1, 3, figsize=(14, 4))
    ax1.axhspan(*TARGET_REPOSE_DEG, color="0.85", label="target (crushed rock)")
    ax3.axhspan(*TARGET_PEAK_PHI_DEG, color="0.85", label="target (ballast, low sigma3)")
    for r in recs:
        if "repose_profile_deg" not in r:
            print(f"{r['dir']}: mu_r = {r['mu_r']}: phi = {r.get('phi_deg'):.1f} deg, c = {r.get('cohesion_pa'):.0f} Pa, "
                  f"phi(c = 0) = {r.get('phi_c0_deg'):.1f} deg; grain volume fraction {r['grain_volume_fraction']:.3f}, "
                  f"pile {1e3 * r['pile_height_m']:.1f} mm; yields " + ", ".join(
                      f"({t['sigma1_pa']:.0f}, {t['sigma3_effective_pa']:.0f}) Pa {t['yield_shape']}" for t in r["tests"]))
            mk = "^" if r["grains"] < 600 else ("s" if r["preset"] else "o")
            tag = " (400 grains, fast)" if r["grains"] < 600 else (" (preset)" if r["preset"] else "")
            ax3.plot(r["mu_r"], r["phi_c0_deg"], mk, color="C2", label="phi, c = 0" + tag)
            ax3.plot(r["mu_r"], r["phi_deg"], mk, color="C3", mfc="none", label="phi with c" + tag)
            continue
        print(f"{r['dir']}: mu = {r['mu']}, mu_r = {r['mu_r']}: repose {r['repose_profile_deg']:.1f} +- "
              f"{r['repose_profile_se_deg']:.1f} deg (profile, {r['profile_slices']} slices), "
              f"{r['repose_surface_deg']:.1f} +- {r['repose_surface_se_deg']:.1f} deg (surface, {r['surface_rings']} rings); "
              f"height {1e3 * r['height_before_m']:.1f} -> {1e3 * r['height_m']:.1f} mm, at rest {r['at_rest']}")
        mk = "s" if r["preset"] else "o"
        ax1.errorbar(r["mu_r"], r["repose_profile_deg"], yerr=r["repose_profile_se_deg"], fmt=mk, color="C0",
                     label="profile" + (" (preset)" if r["preset"] else ""))
        ax1.errorbar(r["mu_r"], r["repose_surface_deg"], yerr=r["repose_surface_se_deg"], fmt=mk, color="C1", mfc="none",
                     label="surface" + (" (preset)" if r["preset"] else ""))
        ax2.plot(np.array(r["profile_settled"]["radius_m"]) * 1e3, np.array(r["profile_settled"]["height_m"]) * 1e3,
                 "-o", ms=3, label=f"mu_r = {r['mu_r']}" + (" (preset)" if r["preset"] else ""))
    before = next((r for r in recs if "profile_before" in r), None)
    if before:
        ax2.plot(np.array(before["profile_before"]["radius_m"]) * 1e3, np.array(before["profile_before"]["height_m"]) * 1e3,
                 "k:", label="column before")
    h, l = ax1.get_legend_handles_labels()
    uniq = dict(zip(l, h))
    ax1.legend(uniq.values(), uniq.keys(), fontsize=8)
    ax1.set_xlim(-0.02, 0.42)
    ax3.set_xlim(-0.02, 0.42)
    ax1.set_xlabel("rolling friction mu_r (mu = 0.6)")
    ax1.set_ylabel("angle of repose [deg]")
    ax1.set_title("heap after a slow formwork release, 800 clumps")
    ax2.set_xlabel("equivalent radius [mm]")
    ax2.set_ylabel("height [mm]")
    ax2.set_title("settled radius profiles")
    ax2.legend(fontsize=8)
    h, l = ax3.get_legend_handles_labels()
    uniq = dict(zip(l, h))
    ax3.legend(uniq.values(), uniq.keys(), fontsize=8)
    ax3.set_xlabel("rolling friction mu_r (mu = 0.6)")
    ax3.set_ylabel("Mohr-Coulomb friction angle [deg]")
    ax3.set_title("membrane triaxial, 10 and 20 kPa")
    fig.tight_layout()
    fig.savefig(OUT / "calibration.png", dpi=110)
    print(f"wrote {(OUT / 'calibration.png').relative_to(ROOT)} and calibration.json")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=["self-test", "jobs", "report"])
    ap.add_argument("dirs", nargs="*")
    a = ap.parse_args()
    if a.what == "self-test":
        return self_test()
    if a.what == "jobs":
        return write_jobs()
    return report(a.dirs)


if __name__ == "__main__":
    sys.exit(main())
