#!/usr/bin/env python3
"""Figures and figures-of-merit of docs/validation.md, remade from the engine.

Runs wiredem-chung-ooi (tests/validation/chung_ooi_sweep.cpp: Chung & Ooi's
oblique-impact benchmarks through the engine, with the rigid-body lines beside
them), plots docs/validation/chung_ooi_*.png and prints, per benchmark, the
largest deviation from the rigid-body answer where the contact slides
throughout (the regime where that answer is exact for any tangential law).
Then runs wiredem-thornton-fcc (tests/validation/thornton_fcc_sweep.cpp:
Thornton's face-centred cubic array in the rigid-wall cuboid cell at
mu = 0 ... 0.5), plots docs/validation/thornton_fcc.png (sigma1/sigma3
against the axial strain, and the peaks against 2(1 + mu)/(1 - mu)) and
prints the peaks.

    python3 scripts/validation_figures.py [--bin build/release/tests/validation/wiredem-chung-ooi]
        [--fcc-bin build/release/tests/validation/wiredem-thornton-fcc] [--out docs/validation]
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


def load(binary: Path) -> list[dict[str, float | str]]:
    text = subprocess.run([str(binary)], check=True, capture_output=True, text=True).stdout
    rows = []
    for r in csv.DictReader(io.StringIO(text)):
        rows.append({k: (v if k in ("test", "material") else float(v)) for k, v in r.items()})
    return rows


def contact_angle_deg(vx: float, vz: float, spin: float, radius: float) -> float:
    """Angle of the contact point's velocity from the normal [deg] (the
    benchmark's 'rebound angle at the contact patch'; incident when vz < 0)."""
    return math.degrees(math.atan2(vx - spin * radius, abs(vz)))


def sliding_deviation(rows) -> float:
    """Largest |Δv_x| of the engine against the rigid-body line, relative to the
    line's change of v_x (μ J_n / m), where the contact slides throughout."""
    worst = 0.0
    for r in rows:
        if r["rigid_slides"] != 1.0:
            continue
        change = abs(r["rigid_vx_m_per_s"] - r["vx0_m_per_s"])
        if change > 0:
            worst = max(worst, abs(r["vx_m_per_s"] - r["rigid_vx_m_per_s"]) / change)
    return worst


def test4(rows, out: Path) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    for material, colour in (("aluminium_oxide", "C0"), ("aluminium_alloy", "C1")):
        rs = [r for r in rows if r["test"] == "4" and r["material"] == material]
        th = [r["x"] for r in rs]
        et = [r["vx_m_per_s"] / r["vx0_m_per_s"] for r in rs]
        et_rb = [r["rigid_vx_m_per_s"] / r["vx0_m_per_s"] for r in rs]
        label = material.replace("_", " ")
        axes[0].plot(th, et, "o", ms=3, color=colour, label=f"wiredem, {label}")
        axes[0].plot(th, et_rb, "-", lw=1, color=colour, label=f"rigid body, {label}")
        axes[1].plot(th, [r["spin_rad_per_s"] for r in rs], "o", ms=3, color=colour)
        axes[1].plot(th, [r["rigid_spin_rad_per_s"] for r in rs], "-", lw=1, color=colour)
        axes[2].plot(th, [contact_angle_deg(r["vx_m_per_s"], r["vz_m_per_s"], r["spin_rad_per_s"], r["radius_m"]) for r in rs],
                     "o", ms=3, color=colour)
        axes[2].plot(th, [contact_angle_deg(r["rigid_vx_m_per_s"], r["rigid_vz_m_per_s"], r["rigid_spin_rad_per_s"],
                                            r["radius_m"]) for r in rs], "-", lw=1, color=colour)
    onset = math.degrees(math.atan(3.5 * 0.092 * 2.0))
    for ax in axes:
        ax.axvline(onset, color="grey", lw=0.8, ls=":")
        ax.set_xlabel("incident angle from the normal [deg]")
    axes[0].set_ylabel("tangential restitution $v_x'/v_x$")
    axes[1].set_ylabel("spin after impact $\\omega'$ [rad/s]")
    axes[2].set_ylabel("contact-point rebound angle [deg]")
    axes[0].legend(fontsize=7)
    fig.suptitle("Chung & Ooi test 4: 3.9 m/s onto a plate, $\\mu$ = 0.092 (dotted: sliding throughout above "
                 f"{onset:.1f}°)", fontsize=10)
    fig.tight_layout()
    fig.savefig(out / "chung_ooi_test4.png", dpi=110)
    plt.close(fig)


def tests_6_7_node(rows, out: Path) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    rs = [r for r in rows if r["test"] == "6"]
    w0 = [r["spin0_rad_per_s"] for r in rs]
    axes[0].plot(w0, [r["spin_rad_per_s"] for r in rs], "o", ms=3, label="wiredem")
    axes[0].plot(w0, [r["rigid_spin_rad_per_s"] for r in rs], "-", lw=1, label="rigid body")
    axes[0].set_xlabel("spin before impact $\\omega_0$ [rad/s]")
    axes[0].set_ylabel("spin after $\\omega'$ [rad/s]")
    axes[0].set_title("test 6: head-on at 3.9 m/s with spin", fontsize=9)
    axes[0].legend(fontsize=7)
    for ax, test, title in ((axes[1], "7", "test 7: two equal spheres, 3.9 m/s"),
                            (axes[2], "membrane_node", "paper's grain on a free membrane node, 0.5 m/s, $\\mu$ = 0.3")):
        rs = [r for r in rows if r["test"] == test]
        th = [r["x"] for r in rs]
        ax.plot(th, [r["vx_m_per_s"] / r["vx0_m_per_s"] for r in rs], "o", ms=3, label="wiredem")
        ax.plot(th, [r["rigid_vx_m_per_s"] / r["vx0_m_per_s"] for r in rs], "-", lw=1, label="rigid body")
        ax.set_xlabel("incident angle from the normal [deg]")
        ax.set_ylabel("tangential restitution of the grain $v_x'/v_x$")
        ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(out / "chung_ooi_tests_6_7_node.png", dpi=110)
    plt.close(fig)


def load_fcc(binary: Path) -> list[dict[str, float]]:
    text = subprocess.run([str(binary)], check=True, capture_output=True, text=True).stdout
    return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(io.StringIO(text))]


WINDOW_ROWS = 11  # the bound test's window (tests/validation/test_thornton_fcc.cpp)


def fcc_curves(rows):
    """Per mu: loading strains, sigma1/sigma3 of each row, and the raw and windowed peaks."""
    curves = {}
    for mu in sorted({r["mu"] for r in rows}):
        rs = [r for r in rows if r["mu"] == mu and r["phase"] == 2.0]
        s1 = [r["sigma1_pa"] for r in rs]
        s3 = [0.5 * (r["sigma_x_pa"] + r["sigma_y_pa"]) for r in rs]
        windowed = max(sum(s1[i:i + WINDOW_ROWS]) / sum(s3[i:i + WINDOW_ROWS])
                       for i in range(len(rs) - WINDOW_ROWS + 1))
        curves[mu] = ([100 * r["axial_strain"] for r in rs], [a / b for a, b in zip(s1, s3)],
                      max(a / b for a, b in zip(s1, s3)), windowed)
    return curves


def thornton_fcc(rows, out: Path) -> dict:
    curves = fcc_curves(rows)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4))
    for k, (mu, (strain, ratio, _, _)) in enumerate(curves.items()):
        colour = f"C{k}"
        axes[0].plot(strain, ratio, color=colour, lw=0.8, label=f"μ = {mu:g}")
        axes[0].axhline(2 * (1 + mu) / (1 - mu), color=colour, ls="--", lw=0.8)
    axes[0].set_xlabel("axial strain ε_a [%]")
    axes[0].set_ylabel("σ₁/σ₃ (walls)")
    axes[0].set_title("Thornton's FCC array, cuboid cell (dashed: 2(1+μ)/(1−μ))", fontsize=9)
    axes[0].legend(fontsize=7)
    mus = list(curves)
    line = [m / 100 for m in range(0, 51)]
    axes[1].plot(line, [2 * (1 + m) / (1 - m) for m in line], "k-", lw=1, label="2(1+μ)/(1−μ) (Thornton 1979)")
    axes[1].plot(mus, [curves[m][3] for m in mus], "o", color="C0", label="wiredem, windowed peak")
    axes[1].plot(mus, [curves[m][2] for m in mus], "x", color="C3", label="wiredem, largest row")
    axes[1].set_xlabel("inter-particle friction μ")
    axes[1].set_ylabel("peak σ₁/σ₃")
    axes[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out / "thornton_fcc.png", dpi=110)
    plt.close(fig)
    return curves


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", type=Path, default=ROOT / "build/release/tests/validation/wiredem-chung-ooi")
    ap.add_argument("--fcc-bin", type=Path, default=ROOT / "build/release/tests/validation/wiredem-thornton-fcc")
    ap.add_argument("--out", type=Path, default=ROOT / "docs/validation")
    args = ap.parse_args()
    rows = load(args.bin)
    args.out.mkdir(parents=True, exist_ok=True)
    test4(rows, args.out)
    tests_6_7_node(rows, args.out)
    print("largest deviation from the rigid-body line where the contact slides throughout "
          "(|Δv_x| / rigid change of v_x):")
    for test in ("4", "6", "7", "membrane_node"):
        rs = [r for r in rows if r["test"] == test]
        n = sum(1 for r in rs if r["rigid_slides"] == 1.0)
        print(f"  test {test}: {sliding_deviation(rs):.2e} over {n} sliding cases of {len(rs)}")
    curves = thornton_fcc(load_fcc(args.fcc_bin), args.out)
    print("Thornton's FCC array: peak sigma1/sigma3 (largest row, window of "
          f"{WINDOW_ROWS} rows) against 2(1 + mu)/(1 - mu):")
    for mu, (_, _, raw, windowed) in curves.items():
        closed = 2 * (1 + mu) / (1 - mu)
        print(f"  mu = {mu:g}: {raw:.4f}, {windowed:.4f} against {closed:.4f} "
              f"({100 * (windowed / closed - 1):+.1f} %)")


if __name__ == "__main__":
    main()
