#!/usr/bin/env python3
"""Thornton's FCC array as an elastic structure: where the runs part from the closed form.

The closed form 2(1 + mu)/(1 - mu) (docs/validation.md) is the array of rigid
spheres with every inclined contact sliding. This script computes the
**elastic** array of the run instead (tests/validation/fcc.hpp: 2 x 2 x 2
cells, r = 1.23 mm, E = 1 GPa, nu = 0.3, frictionless walls of the same
material, sigma3 = 20 kPa, the paper's tangential law T = k_t N delta_t up to
mu N) under a uniform (affine) strain of its interior:

* every contact of a kind carries the same force: the xy-plane contacts N_h
  (Hertz, from the lateral strain), the inclined ones N (Hertz, from both
  strains) and T = min(k_t delta_t, mu) N with delta_t = s (eps_z - eps_x)/sqrt(2)
  the tangential displacement (s the interior's layer spacing);
* the walls see the bonds that cross a plane of the array: 2 (2n + 1) 2n of
  them (40 for n = 2 cells), shared by the ((2n + 1)^2 + 1)/2 spheres of a face
  (13), each pressed onto its wall by Hertz with R* = r: the walls' overlaps
  are part of the measured strain (about a third of it here);
* the lateral stress is held at sigma3 (the servo), the axial strain imposed.

It runs wiredem-thornton-fcc (or reads its CSV), and prints, per mu: where
the first contact slides or the first burst of kinetic energy comes in the
run, the model's ratio and mobilisation T/(mu N) there, the largest
deviation of the run from the model before it, the model's first slip
(T = mu N) and its largest ratio, and the run's peak. Plots
docs/validation/thornton_fcc_model.png (runs solid, model dashed).

    python3 scripts/fcc_elastic_model.py [--fcc-bin BIN] [--args 'dt=0.25'] [--csv FILE] [--out DIR]
"""
from __future__ import annotations

import argparse
import csv
import io
import math
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# tests/validation/fcc.hpp and engine/scene.hpp (FccArraySpec)
E, NU, R = 1e9, 0.3, 1.23e-3
SIGMA3 = 20e3
KT = 1e5  # the tangential law's default k_t [1/m]


class ElasticArray:
    def __init__(self, mu: float, kt: float = KT, cells: int = 2):
        e_star = E / (2 * (1 - NU * NU))  # sphere-sphere and sphere-wall alike (same material)
        self.k = 4 / 3 * e_star * math.sqrt(R / 2)   # sphere-sphere, R* = r/2
        self.kw = 4 / 3 * e_star * math.sqrt(R)      # sphere-wall, R* = r
        self.bonds = 2 * (2 * cells + 1) * 2 * cells
        self.face = ((2 * cells + 1) ** 2 + 1) // 2
        self.layers = 2 * cells
        self.mu, self.kt = mu, kt
        # the isotropic state at sigma3: N0 on every contact, width w0
        n0 = 0.06
        for _ in range(60):
            xi0 = (n0 / self.k) ** (2 / 3)
            s = (2 * R - xi0) / math.sqrt(2)
            xiw = (self.bonds * n0 / math.sqrt(2) / self.face / self.kw) ** (2 / 3)
            w = self.layers * s + 2 * (R - xiw)
            n0 = SIGMA3 * w * w * math.sqrt(2) / self.bonds
        self.n0, self.s, self.w0 = n0, s, w

    def hertz(self, xi: float, k: float) -> float:
        return k * max(xi, 0.0) ** 1.5

    def state(self, ez: float, ex: float):
        """Forces and wall stresses for interior strains ez, ex (compression > 0)."""
        s = self.s
        ni = self.hertz(2 * R - s * math.hypot(1 - ex, 1 - ez), self.k)
        nh = self.hertz(2 * R - s * math.sqrt(2) * (1 - ex), self.k)
        t = min(self.kt * s * abs(ez - ex) / math.sqrt(2), self.mu) * ni
        fz = self.bonds * (ni + t) / math.sqrt(2)
        fx = self.bonds / 2 * (nh + ni - t) / math.sqrt(2)
        wz = self.layers * s * (1 - ez) + 2 * (R - (fz / self.face / self.kw) ** (2 / 3))
        wx = self.layers * s * (1 - ex) + 2 * (R - (fx / self.face / self.kw) ** (2 / 3))
        return ni, nh, t, fz / (wx * wx), fx / (wx * wz), wz

    def at(self, ez: float):
        """(measured axial strain, sigma1/sigma3, T/N, N_h/N0) at interior strain ez, sigma_x = sigma3."""
        lo, hi = -0.05, 0.05
        for _ in range(70):
            mid = 0.5 * (lo + hi)
            if self.state(ez, mid)[4] > SIGMA3:
                hi = mid
            else:
                lo = mid
        ni, nh, t, sz, sx, wz = self.state(ez, 0.5 * (lo + hi))
        return 1 - wz / self.w0, sz / sx, t / ni, nh / self.n0

    def curve(self, ez_max: float, n: int):
        return [self.at(ez_max * k / n) for k in range(n + 1)]


def interpolate(curve, ea: float):
    for a, b in zip(curve, curve[1:]):
        if a[0] <= ea <= b[0]:
            f = (ea - a[0]) / (b[0] - a[0]) if b[0] > a[0] else 0.0
            return tuple(x + f * (y - x) for x, y in zip(a, b))
    return None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fcc-bin", type=Path, default=ROOT / "build/release/tests/validation/wiredem-thornton-fcc")
    ap.add_argument("--args", default="", help="extra arguments of the sweep after 'MU 2', e.g. 'dt=0.25'")
    ap.add_argument("--mu", default="0.1,0.2,0.3,0.4,0.5")
    ap.add_argument("--csv", type=Path, help="read this sweep CSV instead of running the binary")
    ap.add_argument("--out", type=Path, default=ROOT / "docs/validation")
    args = ap.parse_args()
    if args.csv:
        rows = [{k: float(v) for k, v in r.items()} for r in csv.DictReader(args.csv.open())]
    else:
        rows = []
        for mu in args.mu.split(","):
            text = subprocess.run([str(args.fcc_bin), mu, "2", *args.args.split()], check=True,
                                  capture_output=True, text=True).stdout
            rows += [{k: float(v) for k, v in r.items()} for r in csv.DictReader(io.StringIO(text))]
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(7, 4.5))
    print("mu   | run: first event (strain %, ratio, model there, T/(mu N) there) | max dev before | "
          "model: first slip (strain %, ratio), largest | run's peak (row)")
    for k, mu in enumerate(sorted({r["mu"] for r in rows})):
        rs = [r for r in rows if r["mu"] == mu and r["phase"] == 2.0]
        model = ElasticArray(mu)
        curve = model.curve(0.02, 2000)
        base_sliding, ke_ref = rs[0]["sliding_contacts"], rs[10]["kinetic_energy_j"]
        ratio = [r["sigma1_pa"] / (0.5 * (r["sigma_x_pa"] + r["sigma_y_pa"])) for r in rs]
        event, dev = None, 0.0
        for i, r in enumerate(rs):
            if r["sliding_contacts"] > base_sliding or r["kinetic_energy_j"] > 3 * ke_ref:
                event = i
                break
            m = interpolate(curve, r["axial_strain"])
            if i >= 5 and m:  # the first rows: the servo's answer to the start of loading
                dev = max(dev, abs(ratio[i] / m[1] - 1))
        first_slip = next(((c[0], c[1]) for c in curve if mu > 0 and c[2] >= mu - 1e-12), (float("nan"),) * 2)
        largest = max(c[1] for c in curve)
        m = interpolate(curve, rs[event]["axial_strain"]) if event is not None else None
        if m is not None:
            ev = (f"{100 * rs[event]['axial_strain']:.3f} %, {ratio[event]:.3f}, {m[1]:.3f}, "
                  f"{m[2] / mu if mu else 0:.2f}")
        else:
            ev = "none" if event is None else f"{100 * rs[event]['axial_strain']:.3f} %, {ratio[event]:.3f}, -, -"
        print(f"{mu:<4g} | {ev} | {100 * dev:.2f} % | {100 * first_slip[0]:.3f} %, {first_slip[1]:.3f}; {largest:.3f} | "
              f"{max(ratio):.3f} (closed form {2 * (1 + mu) / (1 - mu):.3f})")
        colour = f"C{k}"
        ax.plot([100 * r["axial_strain"] for r in rs], ratio, color=colour, lw=0.8, label=f"μ = {mu:g}")
        ax.plot([100 * c[0] for c in curve if c[0] <= 0.006], [c[1] for c in curve if c[0] <= 0.006],
                color=colour, ls="--", lw=1)
        if event is not None:
            ax.plot([100 * rs[event]["axial_strain"]], [ratio[event]], "o", color=colour, ms=4)
    ax.set_xlim(0, 0.6)
    ax.set_xlabel("axial strain ε_a [%]")
    ax.set_ylabel("σ₁/σ₃ (walls)")
    ax.set_title("FCC array: runs (solid), elastic array under uniform strain (dashed),\n"
                 "dots: the first contact slides or the first burst", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    args.out.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out / "thornton_fcc_model.png", dpi=110)


if __name__ == "__main__":
    main()
