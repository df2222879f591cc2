#!/usr/bin/python3
"""Submit examples/tiny.json to a wiredem server, wait, and plot the stress ratio of every test.

    PYTHONPATH=python python3 examples/python/stress_ratio.py [--server URL] [--out FIGURE.png]

The worked example of docs/python.md; the figure docs/python/stress_ratio.png is
its output (`--out docs/python/stress_ratio.png`), and CI runs it against a
server it starts (python/tests/test_example.py).
"""
import argparse
import sys
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402

import wiredem  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--server", help="http://HOST:PORT (default $WIREDEM_SERVER, else http://127.0.0.1:8080)")
    ap.add_argument("--job", default=str(ROOT / "examples" / "tiny.json"), help="the job spec to run")
    ap.add_argument("--out", default="stress_ratio.png", help="the figure to write")
    args = ap.parse_args()

    client = wiredem.Client(args.server)
    job = client.submit(args.job)
    print(f"submitted {job['id']}")

    def show(j):
        print(f"  {j['state']:<10} {j.get('stage') or '':<10} {100 * (j.get('progress') or 0):5.1f} %")

    client.wait(job["id"], interval_s=0.5, progress=show)
    with tempfile.TemporaryDirectory() as folder:
        result = client.result(job["id"], folder)  # summary.json and result.h5
        curves = result.stress_ratio_curves()      # {σ₃ [Pa]: axial_strain, stress_ratio}
        fit = result.mohr_coulomb

        fig, ax = plt.subplots(figsize=(7, 4.5))
        for sigma3_pa, curve in curves.items():
            line, = ax.plot(curve["axial_strain"] * 100, curve["stress_ratio"], label=f"σ₃ = {sigma3_pa / 1e3:g} kPa")
            y = result.test(sigma3_pa).yield_state  # the engine's reading, not re-read from the curve
            if y:
                ax.plot(y["axial_strain"] * 100, y["stress_ratio"], "o", color=line.get_color(), mec="k")
        ax.set_xlabel("axial strain ε_a [%]")
        ax.set_ylabel("stress ratio η = (σ₁ − σ₃,eff)/(σ₁ + σ₃,eff)")
        ax.set_title(f"{result.name}: loading, ○ yield; Mohr–Coulomb φ = {fit.friction_angle_deg:.1f}°, "
                     f"c = {fit.cohesion_pa / 1e3:.2f} kPa", fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend()
        fig.tight_layout()
        fig.savefig(args.out, dpi=110)
    for sigma3_pa, curve in curves.items():
        print(f"σ₃ = {sigma3_pa:g} Pa: {len(curve)} rows, η at yield "
              f"{result.test(sigma3_pa).yield_state['stress_ratio']:.3f}")
    print(f"φ = {fit.friction_angle_deg:.2f}°, c = {fit.cohesion_pa:.0f} Pa; wrote {args.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
