#!/usr/bin/env python3
"""The collapse of columns without wire against the scaling laws of
axisymmetric granular collapse (docs/validation.md, "Collapse of a column
without wire").

Runs wiredem-collapse (tests/validation/collapse_sweep.cpp: lattice columns
of one radius and several heights, their formwork removed quickly and
slowly, with and without rolling resistance), keeps its CSV in
docs/validation/collapse.csv and plots docs/validation/collapse.png (--name
changes the files' name: collapse-paper for the paper's 20 mm column): the
runout (r_inf - R_i)/R_i and the final height H_inf/R_i against the aspect
ratio a = H_i/R_i, with Lube et al.'s laws (J. Fluid Mech. 508, 2004) beside
them and a band of one grain diameter over R_i around them (the resolution
of a column a few grains wide).

    python3 scripts/collapse_figure.py [--bin build/release/tests/validation/wiredem-collapse]
        [--radius 0.008] [--layers 3,5,9,13] [--speeds 5,0.05] [--rolling 0,0.1,0.2,0.3]
        [--name collapse] [--csv FILE (plot it, run nothing)]
"""
from __future__ import annotations

import argparse
import csv
import io
import math
import subprocess
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
GRAIN_DIAMETER_M = 2 * 1.23e-3


def lube_runout(a: float) -> float:
    return 1.24 * a if a < 1.7 else 1.6 * math.sqrt(a)


def lube_height(a: float) -> float:
    return a if a < 0.74 else 0.88 * a ** (1 / 6)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--bin", default=str(ROOT / "build/release/tests/validation/wiredem-collapse"))
    ap.add_argument("--radius", default="0.008")
    ap.add_argument("--layers", default="3,5,9,13")
    ap.add_argument("--speeds", default="5,0.05")
    ap.add_argument("--rolling", default="0,0.1,0.2,0.3")
    ap.add_argument("--csv", help="plot this CSV instead of running the sweep")
    ap.add_argument("--out", default=str(ROOT / "docs/validation"))
    ap.add_argument("--name", default="collapse", help="the files' name: OUT/NAME.csv and OUT/NAME.png")
    args = ap.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    if args.csv:
        text = Path(args.csv).read_text()
    else:
        text = subprocess.run([args.bin, args.radius, args.layers, args.speeds, args.rolling], check=True,
                              capture_output=True, text=True).stdout
        (out / f"{args.name}.csv").write_text(text)
    rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(io.StringIO(text))]

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 5.2))
    a_max = max(r["aspect_ratio"] for r in rows) * 1.15
    grid = [a_max * k / 200 for k in range(1, 201)]
    band = GRAIN_DIAMETER_M / (sum(r["initial_radius_m"] for r in rows) / len(rows))
    for ax, law, key, ylabel in ((ax1, lube_runout, "runout", "runout $(r_\\infty - R_i)/R_i$"),
                                 (ax2, lube_height, "final_height", "final height $H_\\infty/R_i$")):
        ax.plot(grid, [law(a) for a in grid], color="#1d2330", label="Lube et al. (2004)")
        ax.fill_between(grid, [law(a) - band for a in grid], [law(a) + band for a in grid], color="#1d2330", alpha=0.12,
                        label=f"± one grain diameter ($d/R_i$ = {band:.2f})")
        colours = ["#57606a", "#1f6feb", "#1a7f37", "#d1242f", "#9a6700", "#8250df"]  # one per mu_r
        for i, mu_r in enumerate(sorted({r["rolling_friction_coeff"] for r in rows})):
            for speed in sorted({r["release_speed_ratio"] for r in rows}, reverse=True):
                pts = [r for r in rows if r["rolling_friction_coeff"] == mu_r and r["release_speed_ratio"] == speed]
                if not pts:
                    continue
                fast = speed >= 1
                colour = colours[i % len(colours)]
                ax.plot([r["aspect_ratio"] for r in pts], [r[key] for r in pts], "o" if fast else "s", color=colour,
                        linestyle="-" if fast else ":", label=f"$\\mu_r$ = {mu_r:g}, release {speed:g} $\\sqrt{{g H_i}}$")
                moving = [r for r in pts if not r["at_rest"]]
                ax.plot([r["aspect_ratio"] for r in moving], [r[key] for r in moving], "o" if fast else "s",
                        color=colour, mfc="white", linestyle="none")
        ax.set_xlabel("aspect ratio $a = H_i/R_i$")
        ax.set_ylabel(ylabel)
        ax.set_xlim(0, a_max)
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
    ax1.set_yscale("log")
    ax1.set_ylim(0.3, None)
    handles, labels = ax2.get_legend_handles_labels()
    fig.legend(handles, labels, fontsize=7, loc="lower center", ncol=4, frameon=False)
    r0 = rows[0]["membrane_radius_m"]
    fig.suptitle(f"Collapse of a column without wire: formwork radius {r0 * 1000:g} mm "
                 f"({r0 / GRAIN_DIAMETER_M:.1f} grain diameters), mu = 0.3; r_inf holds 95 % of the grains; open markers: not at rest at 0.4 s", fontsize=10)
    fig.tight_layout(rect=(0, 0.16, 1, 1))
    fig.savefig(out / f"{args.name}.png", dpi=120)
    for r in rows:
        print(f"mu_r = {r['rolling_friction_coeff']:g}, a = {r['aspect_ratio']:.2f} (release {r['release_speed_ratio']:g}): runout {r['runout']:.2f} "
              f"(law {r['lube_runout']:.2f}), height {r['final_height']:.2f} (law {r['lube_final_height']:.2f}), "
              f"at rest {int(r['at_rest'])}")


if __name__ == "__main__":
    main()
