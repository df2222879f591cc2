#!/usr/bin/python3
"""The grain volume fraction of a cuboid-cell specimen inside its walls and in
its core, a grain diameter (or more) in from all six walls: the measure the
membrane cell reports as `core_grain_volume_fraction` (a grain diameter from
the membrane and both plates; engine/specimen/packing.hpp). The cuboid cell's
summary reports its core so too since 2026-12-07 (a diameter of the largest
grain in, on a grid); this script reads a specimen of any date, at several
margins. For comparing the two cells at one density (docs/validation.md, "The rigid-wall cell against
the membrane").

    /usr/bin/python3 scripts/box_core_fraction.py JOB_DIR [JOB_DIR ...]

JOB_DIR: a directory `wiredem run` wrote for a job with triaxial.cell =
"cuboid" (its specimen.h5). Each grain counts with the share of its volume
inside the region (4000 fixed points in the unit ball,
bench/liggghts/packing_physics.py: 0.2 % per cut grain).
"""
import sys
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "bench" / "liggghts"))
from packing_physics import ball_points  # noqa: E402


def fraction(x: np.ndarray, r: np.ndarray, lo: np.ndarray, hi: np.ndarray, points: np.ndarray) -> float:
    volume = 0.0
    for c, rad in zip(x, r):
        inside = np.all((c + rad * points >= lo) & (c + rad * points <= hi), axis=1).mean()
        volume += inside * 4.0 / 3.0 * np.pi * rad ** 3
    return volume / float(np.prod(hi - lo))


def main() -> int:
    if len(sys.argv) < 2:
        print(__doc__)
        return 2
    points = ball_points()
    for d in sys.argv[1:]:
        with h5py.File(Path(d) / "specimen.h5", "r") as f:
            x = f["bodies/grain/x0"][:]
            r = f["bodies/grain/radius_m"][:, 0]
            lo, hi = np.full(3, -np.inf), np.full(3, np.inf)
            for k in range(len(f["walls"])):
                p, n = f[f"walls/{k}/point_m"][0], f[f"walls/{k}/normal"][0]
                a = int(np.argmax(np.abs(n)))
                if n[a] > 0:
                    lo[a] = p[a]
                else:
                    hi[a] = p[a]
        if not (np.isfinite(lo).all() and np.isfinite(hi).all()):
            print(f"{d}: not a cuboid cell's specimen (six plane walls)", file=sys.stderr)
            return 1
        diameter = 2.0 * r.mean()
        cells = " ".join(f"{k} d in: {fraction(x, r, lo + k * diameter, hi - k * diameter, points):.4f}" for k in (0, 1, 2))
        print(f"{d}: box {np.round((hi - lo) * 1e3, 2)} mm; grain volume fraction {cells}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
