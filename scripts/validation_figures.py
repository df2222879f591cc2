#!/usr/bin/env python3
"""Figures and figures-of-merit of docs/validation.md, remade from the engine.

Runs wiredem-chung-ooi (tests/validation/chung_ooi_sweep.cpp: Chung & Ooi's
oblique-impact benchmarks through the engine, with the rigid-body lines beside
them), plots docs/validation/chung_ooi_*.png and prints, per benchmark, the
largest deviation from the rigid-body answer where the contact slides
throughout (the regime where that answer is exact for any tangential law).

    python3 scripts/validation_figures.py [--bin build/release/tests/validation/wiredem-chung-ooi] [--out docs/validation]
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


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", type=Path, default=ROOT / "build/release/tests/validation/wiredem-chung-ooi")
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


if __name__ == "__main__":
    main()
