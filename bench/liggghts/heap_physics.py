#!/usr/bin/env python3
"""The angle of repose of a poured heap, the same way for every code (issue 43 §4).

Reads the heap's grain positions written by wiredem-bench --heap
(`--liggghts-data`: a LAMMPS data file) or by LIGGGHTS / LAMMPS (`dump custom
id radius x y z`, bench/liggghts/in.heap*), centres them on the heap's axis
(the median of x and y), and reads the angle twice, with the readings of the
gravel calibration (scripts/gravel_calibration.py, one place; their accuracy
on synthetic cones of known angle is in docs/model.md, "Measuring the angle
of repose"):

* surface: the highest sphere top in rings of one diameter about the axis,
  a line fitted between 1/4 and 3/4 of the radius r95 that holds 95 % of the
  grains; theta = atan(-slope);
* profile: per horizontal slice of one diameter, the equivalent radius
  sqrt(2 <rho^2>) + r; a line through the slices but the lowest and the
  highest, theta = atan(-1 / (dr/dh)).

Also printed: the heap's height H (the highest sphere top within r95/4 of the
axis), r95, and atan(H / r95), the angle of a cone of that height and base.

    heap_physics.py [--poured N] LABEL=FILE [LABEL=FILE ...] [--csv OUT.csv] [--png OUT.png] [--title T]

--poured N: only the grains with ids up to N are the heap's; the rest is
the fixed rough base (wiredem-bench --rough-base). Grains beyond the peers'
box (|x| or |y| > 0.1 m) are left out for every code: a peer loses them.

Labels name the runs as heap_physics.sh does (code/rMU_R/sSEED); with several
seeds of a code and mu_r, the table adds their mean and standard deviation.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parent.parent / "scripts"))
from gravel_calibration import equivalent_radius_profile, profile_angle_deg, surface_angle_deg  # noqa: E402
from packing_physics import read_atoms  # noqa: E402

# The peers' box (wiredem-bench --heap writes it 0.2 m wide): a grain that
# rolls beyond it is lost to them, so it is left out for every code.
BOX_HALF_WIDTH_M = 0.1


def measure(x: np.ndarray, r: np.ndarray) -> dict:
    x = x.copy()
    x[:, 0] -= np.median(x[:, 0])
    x[:, 1] -= np.median(x[:, 1])
    surf, surf_se, rings = surface_angle_deg(x, r)
    h, rr = equivalent_radius_profile(x, r)
    prof, prof_se, slices = profile_angle_deg(h, rr)
    rho = np.hypot(x[:, 0], x[:, 1])
    r95 = float(np.sort(rho + r)[int(math.ceil(0.95 * len(r))) - 1])
    top = x[:, 2] + r - (x[:, 2] - r).min()
    height = float(top[rho <= 0.25 * r95].max())
    return {"grains": len(r), "surface": surf, "surface_se": surf_se, "rings": rings, "profile": prof,
            "profile_se": prof_se, "slices": slices, "height_mm": 1e3 * height, "r95_mm": 1e3 * r95,
            "cone": math.degrees(math.atan(height / r95)), "h": h, "rr": rr}


FIGURES = [("surface", "surface", "{:.1f}"), ("surface_se", "+-", "{:.1f}"), ("profile", "profile", "{:.1f}"),
           ("profile_se", "+-", "{:.1f}"), ("height_mm", "H [mm]", "{:.1f}"), ("r95_mm", "r95 [mm]", "{:.1f}"),
           ("cone", "atan(H/r95)", "{:.1f}")]


def print_table(res: dict, figures: list, count: str, width: int = 28, mean=np.mean, sd=np.std) -> None:
    """One row per run (LABEL: its figures, `count` first), then the mean and
    standard deviation of each group of runs that differ in their last label
    part only (the seeds)."""
    print(f"{'run':<{width}} {'N':>6} " + " ".join(f"{h:>11}" for _, h, _ in figures))
    for label, m in res.items():
        print(f"{label:<{width}} {m[count]:>6} " + " ".join(f"{fmt.format(m[k]):>11}" for k, _, fmt in figures))
    groups: dict[str, list[str]] = {}
    for label in res:
        groups.setdefault(label.rsplit("/", 1)[0], []).append(label)
    for group, labels in groups.items():
        if len(labels) < 2:
            continue
        means = " ".join(f"{fmt.format(mean([res[l][k] for l in labels])):>11}" for k, _, fmt in figures)
        sds = " ".join(f"{fmt.format(sd([res[l][k] for l in labels], ddof=1)):>11}" for k, _, fmt in figures)
        print(f"{group + ' mean':<{width}} {'':>6} {means}")
        print(f"{group + ' s.d.':<{width}} {'':>6} {sds}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=FILE")
    ap.add_argument("--csv", type=Path)
    ap.add_argument("--png", type=Path)
    ap.add_argument("--poured", type=int, help="the heap's grains: the first N by id (the rest: the base)")
    ap.add_argument("--title", default="poured heaps: radius profile (surface / profile angle)",
                    help="the figure's title (repose_physics.sh: the lifted tube's)")
    args = ap.parse_args()
    res = {}
    for spec in args.runs:
        label, _, path = spec.partition("=")
        ids, x, r = read_atoms(Path(path))
        keep = np.all(np.abs(x[:, :2]) <= BOX_HALF_WIDTH_M, axis=1)
        if args.poured:
            keep &= ids <= args.poured
        res[label] = measure(x[keep], r[keep])
    print("angles in degrees")
    print_table(res, FIGURES, "grains")
    if args.csv:
        with open(args.csv, "w") as out:
            out.write("run,grains," + ",".join(k for k, _, _ in FIGURES) + "\n")
            for label, m in res.items():
                out.write(f"{label},{m['grains']}," + ",".join(f"{m[k]:.6g}" for k, _, _ in FIGURES) + "\n")
    if args.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(figsize=(6.5, 4))
        colours = {"wiredem": "C0", "LIGGGHTS": "C1", "LAMMPS": "C2"}
        cases = sorted({label.split("/")[1] if label.count("/") >= 1 else "" for label in res})
        styles = ["o-", "s--", "^:", "d-."]  # one per mu_r (the label's second part)
        for i, (label, m) in enumerate(res.items()):
            code = label.split("/")[0]
            case = label.split("/")[1] if label.count("/") >= 1 else ""
            ax.plot(1e3 * m["rr"], 1e3 * m["h"], styles[cases.index(case) % len(styles)],
                    color=colours.get(code, f"C{3 + i % 6}"), ms=3, alpha=0.8,
                    label=f"{label}: {m['surface']:.1f}° / {m['profile']:.1f}°")
        ax.set_xlabel("equivalent radius of the slice [mm]")
        ax.set_ylabel("height of the slice [mm]")
        ax.set_title(args.title)
        ax.legend(fontsize=6)
        fig.tight_layout()
        fig.savefig(args.png, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
