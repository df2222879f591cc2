#!/usr/bin/env python3
"""The physics of a settled packing, the same way for every code (issue 43 §4).

Reads settled grain positions written by wiredem-bench (`--liggghts-data`:
a LAMMPS data file) or by LIGGGHTS / LAMMPS (`dump custom id radius x y z`,
bench/liggghts/in.settle*), and measures each packing the same way:

* the packing fraction phi of the bulk: the cylinder r < R - 2d, d <= z <=
  z_top - 3d (z_top: the 95th percentile of the grains' centre heights;
  d the diameter), every grain's volume inside the region counted (a fixed
  set of 4000 points in the unit ball: 0.2 % per cut grain);
* the coordination number Z of the grains whose centre lies in that region
  (grain-grain contacts with an overlap xi > 0, grain-wall contacts left
  out), the fraction of those grains without a contact (rattlers), and Z of
  the grains with at least two contacts;
* the normal contact forces of the grain-grain contacts in the region, from
  the overlaps by Hertz's law F = (4/3) E* sqrt(R*) xi^(3/2). Every code
  compared uses that elastic law (only the damping and the tangential law
  differ, bench/liggghts/in.bench); in a packing at rest the damping's share
  is nil, so the overlaps carry the forces. Each force is scaled by the mean
  of the forces in its horizontal slab (2d thick): the forces grow with
  depth, f/<f>_slab removes the gradient. Figures of the distribution:
  <f^2>/<f>^2, P(f < 0.5 <f>), P(f > 2 <f>), and the Kolmogorov-Smirnov
  distance between each pair of codes;
* the floor's load over the grains' weight (the Janssen effect: the rest is
  carried by friction on the cylinder), from the grain-floor overlaps.

    packing_physics.py LABEL=FILE [LABEL=FILE ...] [--csv OUT.csv] [--png OUT.png]

Labels name the runs (e.g. wiredem/s1, LIGGGHTS/s1): the part before the
first '/' is the code; with several runs of a code (several seeds), the
table adds, per code, the mean and the seed-to-seed standard deviation.
"""
from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

# The bench's material (bench/bench_main.cpp, ContainerSpec): grains E = 10 GPa,
# nu = 0.3, rho = 7800; floor and cylinder E = 1 GPa, nu = 0.3; R = 20 mm; g = 10.
E_GRAIN, NU_GRAIN, RHO = 10e9, 0.3, 7800.0
E_WALL, NU_WALL = 1e9, 0.3
R_CYL, G = 0.02, 10.0


def e_star(e1: float, n1: float, e2: float, n2: float) -> float:
    return 1.0 / ((1 - n1 * n1) / e1 + (1 - n2 * n2) / e2)


def read_atoms(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(id (N,), x (N, 3), radius (N,)) from a data file or the last snapshot
    of a dump, in ascending id (a dump lacks the atoms its code lost)."""
    lines = path.read_text().splitlines()
    if lines and lines[0].startswith("ITEM:"):
        starts = [i for i, l in enumerate(lines) if l.startswith("ITEM: NUMBER OF ATOMS")]
        i = starts[-1]
        n = int(lines[i + 1])
        j = next(k for k in range(i, len(lines)) if lines[k].startswith("ITEM: ATOMS"))
        cols = lines[j].split()[2:]
        rows = np.array([[float(v) for v in l.split()] for l in lines[j + 1:j + 1 + n]])
        rows = rows[np.argsort(rows[:, cols.index("id")])]
        x = rows[:, [cols.index("x"), cols.index("y"), cols.index("z")]]
        return rows[:, cols.index("id")].astype(int), x, rows[:, cols.index("radius")]
    j = lines.index("Atoms")
    rows = np.array([[float(v) for v in l.split()] for l in lines[j + 1:] if l.strip()])
    rows = rows[np.argsort(rows[:, 0])]
    return rows[:, 0].astype(int), rows[:, 4:7], 0.5 * rows[:, 2]


def read_positions(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(x (N, 3), radius (N,)) from a data file or the last snapshot of a dump."""
    _, x, r = read_atoms(path)
    return x, r


def pairs_in_contact(x: np.ndarray, r: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(i, j, xi) of every grain pair with i < j and an overlap xi > 0."""
    order = np.argsort(x[:, 2])
    xs, rs = x[order], r[order]
    reach = 2.0 * r.max()
    ii, jj, xx = [], [], []
    for a in range(len(xs)):
        hi = np.searchsorted(xs[:, 2], xs[a, 2] + reach, side="right")
        if hi <= a + 1:
            continue
        d = np.linalg.norm(xs[a + 1:hi] - xs[a], axis=1)
        xi = rs[a] + rs[a + 1:hi] - d
        k = np.nonzero(xi > 0.0)[0]
        ii.append(np.full(len(k), order[a]))
        jj.append(order[a + 1 + k])
        xx.append(xi[k])
    return np.concatenate(ii), np.concatenate(jj), np.concatenate(xx)


def ball_points(n: int = 4000) -> np.ndarray:
    """A fixed, evenly spread set of points in the unit ball (a scaled
    Fibonacci lattice in radius^3 and the sphere's angles)."""
    k = np.arange(n) + 0.5
    rad = (k / n) ** (1.0 / 3.0)
    golden = math.pi * (3.0 - math.sqrt(5.0))
    theta = golden * np.arange(n)
    # the radial order and the angular spiral are decorrelated by a second index
    u = ((np.arange(n) * 0.6180339887498949) % 1.0) * 2.0 - 1.0
    s = np.sqrt(1.0 - u * u)
    return rad[:, None] * np.stack([s * np.cos(theta), s * np.sin(theta), u], axis=1)


def measure(x: np.ndarray, r: np.ndarray) -> dict:
    d = 2.0 * float(np.mean(r))
    z_top = float(np.percentile(x[:, 2], 95))
    z_lo, z_hi, r_in = d, z_top - 3.0 * d, R_CYL - 2.0 * d
    rc = np.hypot(x[:, 0], x[:, 1])
    if z_hi - z_lo < 2.0 * d:
        raise SystemExit(f"the packing is {z_top / d:.1f} diameters high: too low for a bulk region "
                         "(d <= z <= z_95 - 3d, at least 2d high); settle more grains (2000 in the 20 mm cylinder)")

    # packing fraction: each grain's share of the region
    pts = ball_points()
    vol = 0.0
    near = (x[:, 2] + r > z_lo) & (x[:, 2] - r < z_hi) & (rc - r < r_in)
    for c, a in zip(x[near], r[near]):
        p = c + a * pts
        inside = (p[:, 2] >= z_lo) & (p[:, 2] <= z_hi) & (np.hypot(p[:, 0], p[:, 1]) <= r_in)
        vol += (4.0 / 3.0) * math.pi * a ** 3 * inside.mean()
    phi = vol / (math.pi * r_in ** 2 * (z_hi - z_lo))

    i, j, xi = pairs_in_contact(x, r)
    bulk = (x[:, 2] >= z_lo) & (x[:, 2] <= z_hi) & (rc <= r_in)
    z_of = np.bincount(i, minlength=len(r)) + np.bincount(j, minlength=len(r))
    zb = z_of[bulk]
    rstar = r[i] * r[j] / (r[i] + r[j])
    f = (4.0 / 3.0) * e_star(E_GRAIN, NU_GRAIN, E_GRAIN, NU_GRAIN) * np.sqrt(rstar) * xi ** 1.5
    mid = 0.5 * (x[i] + x[j])
    in_region = (mid[:, 2] >= z_lo) & (mid[:, 2] <= z_hi) & (np.hypot(mid[:, 0], mid[:, 1]) <= r_in)
    f, zc = f[in_region], mid[in_region, 2]
    if len(f) == 0:
        raise SystemExit("no grain-grain contact in the bulk region: the packing has not settled")
    slab = np.floor((zc - z_lo) / (2.0 * d)).astype(int)
    mean_of_slab = np.bincount(slab, weights=f) / np.maximum(np.bincount(slab), 1)
    fn = f / mean_of_slab[slab]

    floor_xi = r - x[:, 2]
    floor_f = (4.0 / 3.0) * e_star(E_GRAIN, NU_GRAIN, E_WALL, NU_WALL) * np.sqrt(r) * np.clip(floor_xi, 0, None) ** 1.5
    weight = float(np.sum(RHO * (4.0 / 3.0) * math.pi * r ** 3) * G)
    return {
        "grains": len(r),
        "z_top_d": z_top / d,
        "phi": phi,
        "Z": float(zb.mean()),
        "rattlers": float(np.mean(zb == 0)),
        "Z_2": float(zb[zb >= 2].mean()),
        "contacts": int(len(fn)),
        "f2": float(np.mean(fn ** 2)),
        "p_lt_half": float(np.mean(fn < 0.5)),
        "p_gt_2": float(np.mean(fn > 2.0)),
        "floor_over_weight": float(floor_f.sum() / weight),
        "fn": fn,
    }


def ks(a: np.ndarray, b: np.ndarray) -> float:
    grid = np.sort(np.concatenate([a, b]))
    ca = np.searchsorted(np.sort(a), grid, side="right") / len(a)
    cb = np.searchsorted(np.sort(b), grid, side="right") / len(b)
    return float(np.max(np.abs(ca - cb)))


FIGURES = [("phi", "phi", "{:.4f}"), ("Z", "Z", "{:.3f}"), ("rattlers", "x0", "{:.3f}"), ("Z_2", "Z(>=2)", "{:.3f}"),
           ("f2", "<f2>/<f>2", "{:.3f}"), ("p_lt_half", "P(f<.5)", "{:.3f}"), ("p_gt_2", "P(f>2)", "{:.4f}"),
           ("floor_over_weight", "floor/W", "{:.3f}")]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", nargs="+", help="LABEL=FILE")
    ap.add_argument("--csv", type=Path)
    ap.add_argument("--png", type=Path)
    args = ap.parse_args()
    res = {}
    for spec in args.runs:
        label, _, path = spec.partition("=")
        res[label] = measure(*read_positions(Path(path)))
    head = f"{'run':<16} {'N':>6} {'contacts':>8} " + " ".join(f"{h:>10}" for _, h, _ in FIGURES)
    print(head)
    for label, m in res.items():
        print(f"{label:<16} {m['grains']:>6} {m['contacts']:>8} " + " ".join(f"{fmt.format(m[k]):>10}" for k, _, fmt in FIGURES))
    codes: dict[str, list[str]] = {}
    for label in res:
        codes.setdefault(label.split("/")[0], []).append(label)
    print()
    for code, labels in codes.items():
        if len(labels) < 2:
            continue
        mean = " ".join(f"{fmt.format(np.mean([res[l][k] for l in labels])):>10}" for k, _, fmt in FIGURES)
        sd = " ".join(f"{fmt.format(np.std([res[l][k] for l in labels], ddof=1)):>10}" for k, _, fmt in FIGURES)
        print(f"{code + ' mean':<16} {'':>6} {'':>8} {mean}")
        print(f"{code + ' s.d.':<16} {'':>6} {'':>8} {sd}")
    print()
    labels = list(res)
    for a in range(len(labels)):
        for b in range(a + 1, len(labels)):
            print(f"KS distance of f/<f>: {labels[a]} vs {labels[b]}: {ks(res[labels[a]]['fn'], res[labels[b]]['fn']):.3f}"
                  f" (5 % critical value {1.358 * math.sqrt(1 / len(res[labels[a]]['fn']) + 1 / len(res[labels[b]]['fn'])):.3f})")
    if args.csv:
        with open(args.csv, "w") as out:
            out.write("run,grains,contacts," + ",".join(k for k, _, _ in FIGURES) + "\n")
            for label, m in res.items():
                out.write(f"{label},{m['grains']},{m['contacts']}," + ",".join(f"{m[k]:.6g}" for k, _, _ in FIGURES) + "\n")
    if args.png:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(1, 2, figsize=(10, 4))
        bins = np.linspace(0, 4, 41)
        centres = 0.5 * (bins[1:] + bins[:-1])
        styles = {"wiredem": "C0", "LIGGGHTS": "C1", "LAMMPS": "C2"}
        for label, m in res.items():
            h, _ = np.histogram(m["fn"], bins=bins, density=True)
            c = styles.get(label.split("/")[0], "C3")
            for a in ax:
                a.plot(centres, h, "-", color=c, alpha=0.8, label=label)
        ax[1].set_yscale("log")
        for a in ax:
            a.set_xlabel("f / <f> (slab of 2d)")
            a.set_ylabel("P(f/<f>)")
        ax[0].legend(fontsize=7)
        ax[0].set_title("normal contact forces, bulk")
        ax[1].set_title("the same, log scale")
        fig.tight_layout()
        fig.savefig(args.png, dpi=110)
    return 0


if __name__ == "__main__":
    sys.exit(main())
