"""Tests of scripts/free_standing_study.py's arithmetic: the unconfined
strength an envelope predicts, the columns its runs are samples of, and the
seed table's mean ± standard deviation.

    python3 -m unittest -v test_free_standing_study      (from tests/scripts)
"""
import contextlib
import io
import math
import os
import sys
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import free_standing_study as fs  # noqa: E402


def run(pattern, seed, mu_r=0.0, stands=False, ucs=None, **extra):
    r = {"pattern": pattern, "seed": seed, "rolling_friction_coeff": mu_r, "stands": stands, "at_rest": stands,
         "radius_m": 0.02 + 0.001 * seed, "bulk_height_loss": 0.01 * seed, "lost_fraction": 0.1 * seed,
         "steps": 1000 * seed, "wall_time_s": 10.0 * seed}
    if ucs is not None:
        r["compression"] = {"unconfined_strength_pa": ucs}
    r.update(extra)
    return r


class FreeStandingStudy(unittest.TestCase):
    def test_the_envelopes_unconfined_strength_is_the_circle_through_the_origin(self):
        # phi = 30 deg: 2 c cos(phi)/(1 - sin(phi)) = 2 sqrt(3) c, and the circle of diameter q_u
        # through the origin touches the line tau = c + sigma tan(phi).
        self.assertAlmostEqual(fs.predicted_ucs_pa(30.0, 1000.0), 2000.0 * math.sqrt(3.0), places=9)
        q, phi, c = fs.predicted_ucs_pa(17.1, 5500.0), math.radians(17.1), 5500.0
        centre, radius = q / 2, q / 2
        self.assertAlmostEqual((c + centre * math.tan(phi)) * math.cos(phi), radius, places=6)
        self.assertIsNone(fs.predicted_ucs_pa(25.0, 0.0))
        self.assertIsNone(fs.predicted_ucs_pa(25.0, -500.0))

    def test_runs_are_grouped_by_pattern_and_law_and_sorted_by_seed(self):
        groups = fs.by_column([run("helix", 3), run("none", 1), run("helix", 1), run("helix", 2, mu_r=0.2),
                               run("helix", 1, wire_cuts=9)])
        self.assertEqual(list(groups), ["helix", "no wire", "helix, μ_r = 0.2", "helix, wire cut at 9 places"])
        self.assertEqual([r["seed"] for r in groups["helix"]], [1, 3])

    def test_mean_and_sample_standard_deviation(self):
        self.assertEqual(fs.mean_sd([1.0, 2.0, 3.0]), "2.0 ± 1.0")
        self.assertEqual(fs.mean_sd([0.02, 0.03], 1e3), "25.0 ± 7.1")
        self.assertEqual(fs.mean_sd([4.0]), "4.0")
        self.assertEqual(fs.mean_sd([None, None]), "—")
        self.assertEqual(fs.mean_sd([None, 2.0, 4.0]), "3.0 ± 1.4")

    def test_the_seed_table_counts_what_stands_and_the_runs_with_a_strength(self):
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            fs.print_seed_table(fs.by_column([run("helix", 1, stands=True, ucs=1000.0), run("helix", 2),
                                              run("helix", 3, ucs=3000.0)]))
        row = out.getvalue().splitlines()[2]
        cells = [c.strip() for c in row.strip("|").split("|")]
        self.assertEqual(cells[:4], ["helix", "1, 2, 3", "1 of 3", "1 of 3"])
        self.assertEqual(cells[4], "2.0 ± 1.0")          # bulk height loss, %
        self.assertEqual(cells[6], "20 ± 10")            # volume lost, %
        self.assertEqual(cells[7], "2.00 ± 1.41 (2 of 3)")


if __name__ == "__main__":
    unittest.main()
