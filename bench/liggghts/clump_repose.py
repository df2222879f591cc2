#!/usr/bin/env python3
"""The packing fraction of a settled column of clumps and the angle of the
cone it leaves when its tube is lifted, the same way for every code (issue 40
§5; bench/liggghts/clump_repose.sh; docs/validation.md, "Across codes: clumps").

Each run gives two files of the poured clumps' spheres only (a data file of
wiredem-bench, or a dump `id radius x y z` of LIGGGHTS): SETTLED, the column
at rest in its tube before the lift, and LIFTED, the cone at the end.

* The packing fraction of the column's core: the share of points, drawn
  uniformly (a fixed seed) in a cylinder about the tube's axis, that lie in a
  sphere of a clump (so the overlap of a clump's own spheres counts once).
  The core keeps two volume-equivalent diameters d off the tube's wall
  (radius --tube-radius - 2 d) and off the rough base's tops (--base-top) and
  the column's top (the highest sphere top within the core's radius); its
  standard error is the binomial one of the points. The same points give the
  fraction per slice of one d, for the figure.
* The cone: heap_physics.measure (the surface and profile readings,
  H, r95, atan(H/r95)) on the spheres of LIFTED, centred on the heap's axis.

    clump_repose.py --tube-radius R --base-top Z --d-eq D LABEL=SETTLED,LIFTED ...
                    [--energy LABEL=J ...] [--csv OUT.csv] [--png OUT.png]

Labels name the runs code/sSEED; with several seeds of a code the table adds
their mean and standard deviation.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from heap_physics import BOX_HALF_WIDTH_M, measure, print_table  # noqa: E402
from packing_physics import read_atoms  # noqa: E402

POINTS = 400_000


def inside_any(points: np.ndarray, x: np.ndarray, r: np.ndarray) -> np.ndarray:
    """Whether each point lies in at least one of the spheres (x, r)."""
    hit = np.zeros(len(points), bool)
    for lo in range(0, len(points), 2000):
        p = points[lo:lo + 2000]
        d2 = ((p[:, None, :] - x[None, :, :]) ** 2).sum(axis=2)
        hit[lo:lo + 2000] = (d2 <= (r * r)[None, :]).any(axis=1)
    return hit


def core_fraction(x: np.ndarray, r: np.ndarray, tube_radius: float, base_top: float, d_eq: float) -> dict:
    """The packing fraction of the settled column's core (the module's text)."""
    rho = np.hypot(x[:, 0], x[:, 1])
    core_r = tube_radius - 2.0 * d_eq
    top = float((x[:, 2] + r)[rho <= core_r].max())
    z_lo, z_hi = base_top + 2.0 * d_eq, top - 2.0 * d_eq
    rng = np.random.default_rng(12345)
    # Uniform in the disc (sqrt of a uniform radius) and in z.
    a = 2.0 * math.pi * rng.random(POINTS)
    s = core_r * np.sqrt(rng.random(POINTS))
    pts = np.column_stack([s * np.cos(a), s * np.sin(a), z_lo + (z_hi - z_lo) * rng.random(POINTS)])
    near = (rho <= core_r + r) & (x[:, 2] + r >= z_lo) & (x[:, 2] - r <= z_hi)
    hit = inside_any(pts, x[near], r[near])
    phi = float(hit.mean())
    edges = np.arange(z_lo, z_hi + 1e-12, d_eq)
    mids, fractions = [], []
    for lo, hi in zip(edges[:-1], edges[1:]):
        s_ = (pts[:, 2] >= lo) & (pts[:, 2] < hi)
        if s_.sum() > 1000:
            mids.append(0.5 * (lo + hi))
            fractions.append(float(hit[s_].mean()))
    return {"phi": phi, "phi_se": math.sqrt(phi * (1.0 - phi) / POINTS), "column_top_mm": 1e3 * top,
            "core_mm": f"r {1e3 * core_r:.2f}, z {1e3 * z_lo:.2f}-{1e3 * z_hi:.2f}",
            "slice_z": np.array(mids), "slice_phi": np.array(fractions)}


FIGURES = [("phi", "phi core", "{:.4f}"), ("phi_se", "+-", "{:.4f}"), ("column_top_mm", "top [mm]", "{:.1f}"),
           ("surface", "surface", "{:.1f}"), ("surface_se", "+-", "{:.1f}"), ("profile", "profile", "{:.1f}"),
           ("profile_se", "+-", "{:.1f}"), ("height_mm", "H [mm]", "{:.1f}"), ("r95_mm", "r95 [mm]", "{:.1f}"),
           ("cone", "atan(H/r95)", "{:.1f}")]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=SETTLED,LIFTED")
    ap.add_argument("--tube-radius", type=float, required=True, help="the tube's inner radius [m]")
    ap.add_argument("--base-top", type=float, required=True, help="height of the rough base's tops [m]")
    ap.add_argument("--d-eq", type=float, required=True, help="a clump's volume-equivalent diameter [m]")
    ap.add_argument("--energy", action="append", default=[], help="LABEL=J: kinetic energy at the end")
    ap.add_argument("--csv", type=Path)
    ap.add_argument("--png", type=Path)
    args = ap.parse_args()
    energy = {e.partition("=")[0]: e.partition("=")[2] for e in args.energy}
    res = {}
    for spec in args.runs:
        label, _, paths = spec.partition("=")
        settled, lifted = paths.split(",")
        _, xs, rs = read_atoms(Path(settled))
        m = core_fraction(xs, rs, args.tube_radius, args.base_top, args.d_eq)
        _, x, r = read_atoms(Path(lifted))
        keep = np.all(np.abs(x[:, :2]) <= BOX_HALF_WIDTH_M, axis=1)
        m.update(measure(x[keep], r[keep]))
        m["spheres"] = int(keep.sum())
        m["energy"] = energy.get(label, "")
        res[label] = m
    print("angles in degrees; the core:", next(iter(res.values()))["core_mm"], "mm (seed 1's)")
    # NaN-aware means: the profile reading gives none for a cone of too few slices.
    print_table(res, FIGURES, "spheres", width=22, mean=np.nanmean, sd=np.nanstd)
    print("kinetic energy of the clumps at the end [J]: "
          + ", ".join(f"{label} {m['energy']}" for label, m in res.items()))
    if args.csv:
        with open(args.csv, "w") as out:
            out.write("run,spheres," + ",".join(k for k, _, _ in FIGURES) + ",kinetic_energy_end_j\n")
            for label, m in res.items():
                out.write(f"{label},{m['spheres']}," + ",".join(f"{m[k]:.6g}" for k, _, _ in FIGURES)
                          + f",{m['energy']}\n")
    if args.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(9, 4))
        colours = {"wiredem": "C0", "LIGGGHTS": "C1"}
        for i, (label, m) in enumerate(res.items()):
            c = colours.get(label.split("/")[0], f"C{2 + i % 7}")
            style = ["o-", "s--", "^:", "d-."][i % 4]
            ax0.plot(m["slice_phi"], 1e3 * m["slice_z"], style, color=c, ms=3, label=f"{label}: {m['phi']:.3f}")
            ax1.plot(1e3 * m["rr"], 1e3 * m["h"], style, color=c, ms=3, alpha=0.8,
                     label=f"{label}: {m['cone']:.1f}° / {m['surface']:.1f}°")
        ax0.set_xlabel("packing fraction of the slice (core)")
        ax0.set_ylabel("height [mm]")
        ax0.set_title("settled column, before the lift")
        ax0.legend(fontsize=7)
        ax1.set_xlabel("equivalent radius of the slice [mm]")
        ax1.set_ylabel("height of the slice [mm]")
        ax1.set_title("cone: radius profile (atan(H/r95) / surface)")
        ax1.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(args.png, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
