"""Tests of scripts/doc_figures.py: the docs' figures of the main job agree
with the summary they were made from (docs/figures/main-summary.json), and
the sentences say what a fit's caveats are.

    python3 -m unittest -v test_doc_figures      (from tests/scripts)
"""
import json
import os
import re
import sys
import tempfile
import unittest

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
sys.path.insert(0, os.path.join(ROOT, "scripts"))
import doc_figures  # noqa: E402

DOCS = [os.path.join(ROOT, "README.md"), os.path.join(ROOT, "docs", "results.md")]
RECORDED = os.path.join(ROOT, "docs", "figures", "main-summary.json")


def fit(phi, c, r2, caveats=(), nn=None, c0=None):
    return {"friction_angle_deg": phi, "cohesion_pa": c, "r_squared": r2,
            "caveats": [{"code": k, "message": "..."} for k in caveats],
            "nonnegative": nn or {"friction_angle_deg": phi, "cohesion_pa": c, "r_squared": r2},
            "cohesionless": c0 or {"friction_angle_deg": phi, "cohesion_pa": 0.0, "r_squared": r2}}


class DocFigures(unittest.TestCase):
    def test_the_docs_agree_with_the_recorded_summary_of_the_main_job(self):
        self.assertEqual(doc_figures.main(["--check", "--summary", RECORDED, *DOCS]), 0,
                         "bash scripts/doc_figures.sh remakes them")

    def test_every_doc_block_names_a_known_block_and_the_main_fit_is_quoted(self):
        with open(DOCS[0], encoding="utf-8") as f:
            names = [m.group(1) for m in doc_figures.MARK.finditer(f.read())]
        self.assertIn("main-fit", names)
        self.assertTrue(set(names) <= set(doc_figures.BLOCKS), names)

    def test_a_negative_cohesion_is_said_with_the_constrained_fits(self):
        s = doc_figures.fit_sentence(fit(21.34, -2149.0, 0.97, ["negative_cohesion"],
                                         nn={"friction_angle_deg": 19.93, "cohesion_pa": 0.0, "r_squared": 0.9},
                                         c0={"friction_angle_deg": 19.93, "cohesion_pa": 0.0, "r_squared": 0.9}))
        self.assertTrue(s.startswith("φ = 21.3°, c = −2.1 kPa (R² = 0.97), an unconstrained line with a negative c"), s)
        self.assertTrue(s.endswith("the best fit with c ≥ 0 and φ ≥ 0 is the one with c = 0, φ = 19.9°"), s)
        s = doc_figures.fit_sentence(fit(-3.0, 5000.0, 0.5, ["negative_friction_angle"],
                                         nn={"friction_angle_deg": 0.0, "cohesion_pa": 4100.0, "r_squared": 0.0},
                                         c0={"friction_angle_deg": 9.04, "cohesion_pa": 0.0, "r_squared": -3.0}))
        self.assertTrue(s.endswith("with c ≥ 0 and φ ≥ 0 gives φ = 0.0°, c = 4.1 kPa, the one with c = 0 φ = 9.0°"), s)

    def test_a_fit_without_caveats_is_its_figures_alone(self):
        self.assertEqual(doc_figures.fit_sentence(fit(30.04, 1960.0, 0.994)), "φ = 30.0°, c = 2.0 kPa (R² = 0.99)")
        self.assertEqual(doc_figures.fit_sentence(fit(30.0, -1.0, None, ["two_pressures"]))[:38],
                         "φ = 30.0°, c = 0.0 kPa (no R²), an unc")

    def test_every_caveat_of_the_engine_has_its_words(self):
        with open(os.path.join(ROOT, "engine", "analysis", "mohr_coulomb.cpp"), encoding="utf-8") as f:
            codes = set(re.findall(r'case FitCaveat::(\w+): return "(\w+)";', f.read()))
        self.assertTrue(codes)
        for enum, code in codes:
            self.assertEqual(enum, code)
            self.assertIn(code, doc_figures.CAVEAT_WORDS)

    def test_the_shapes_say_when_every_test_is_still_rising(self):
        tests = [{"confining_pressure_pa": p, "yield": {"shape": s}} for p, s in [(2e4, "rising"), (4e4, "rising")]]
        self.assertIn("every test (20 / 40 kPa) is still **rising**", doc_figures.shapes_sentence({"tests": tests}))
        tests[1]["yield"]["shape"] = "peak"
        self.assertEqual(doc_figures.shapes_sentence({"tests": tests}),
                         "the yield at 20 / 40 kPa is **rising** / **peak** (1 still rising at its end: lower bounds)")

    def test_check_fails_on_a_stale_figure_and_a_rewrite_mends_it(self):
        summary = {"mohr_coulomb": fit(21.3, -2100.0, 0.97, ["negative_cohesion"])}
        with tempfile.TemporaryDirectory() as d:
            s_path, doc = os.path.join(d, "s.json"), os.path.join(d, "doc.md")
            with open(s_path, "w", encoding="utf-8") as f:
                json.dump(summary, f)
            with open(doc, "w", encoding="utf-8") as f:
                f.write("measured: <!-- doc-figures:main-fit -->φ = 15.4°, c = 6.1 kPa<!-- /doc-figures -->.\n")
            self.assertEqual(doc_figures.main(["--check", "--summary", s_path, doc]), 1)
            self.assertEqual(doc_figures.main(["--summary", s_path, doc]), 0)
            self.assertEqual(doc_figures.main(["--check", "--summary", s_path, doc]), 0)
            with open(doc, encoding="utf-8") as f:
                self.assertIn("c = −2.1 kPa", f.read())


if __name__ == "__main__":
    unittest.main()
