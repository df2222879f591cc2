#!/usr/bin/python3
"""Tests of scripts/study_report.py on a small synthetic RUNS tree.

    /usr/bin/python3 -m unittest discover -s tests/scripts -p 'test_study_report.py'
    (or: bash tests/scripts/test_study_report.sh)

The tree holds what scripts/study.sh leaves (docs/results.md's layout, only the
fields the report reads): helix seeds 1 and 2 and none seed 1 with result.h5,
radial_helix seed 1 as a gathered summary only, and an unfinished campaign.
"""
import importlib.util
import json
import math
import os
import re
import subprocess
import sys
import tempfile
import unittest

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
SCRIPT = os.path.join(ROOT, "scripts", "study_report.py")
spec = importlib.util.spec_from_file_location("study_report", SCRIPT)
report = importlib.util.module_from_spec(spec)
spec.loader.exec_module(report)

SEGMENT_M = 1.25e-3
PERIOD_SEGMENTS = 40  # the synthetic wire strain is a sine of this period


def yield_state(s3_pa, phi_deg, c_pa):
    """(σ₁, σ₃) on the envelope τ = c + σ tan φ: σ₁ = σ₃ (1 + sin φ)/(1 − sin φ) + 2c cos φ/(1 − sin φ)."""
    s = math.sin(math.radians(phi_deg))
    return s3_pa * (1 + s) / (1 - s) + 2 * c_pa * math.cos(math.radians(phi_deg)) / (1 - s), s3_pa


# summary.json's wire lags of the synthetic campaigns (the engine's, not recomputed
# by the report): helix seed 1 by the current binary, seed 2 by one from before
# the prominent maximum (no such key).
WIRE_LAGS = {("helix", 1): {"autocorrelation_lag_m": 0.0125, "autocorrelation_prominent_lag_m": PERIOD_SEGMENTS * SEGMENT_M},
             ("helix", 2): {"autocorrelation_lag_m": PERIOD_SEGMENTS * SEGMENT_M}}


# The state at the start of loading (tests[].loading_start) of helix seed 1: at
# 20 kPa the column lengthened by 2 % in the hold (it flowed in extension), at
# 40 kPa by 0.1 %. The other summaries predate the key.
LOADING_STARTS = {("helix", 1, 20e3): {"sigma1_pa": 20e3, "sigma3_effective_pa": 50e3, "stress_ratio": -3 / 7,
                                       "axial_strain": -0.02, "rebound_axial_strain": 0.02, "radial_strain": 0.01},
                  ("helix", 1, 40e3): {"sigma1_pa": 40e3, "sigma3_effective_pa": 50e3, "stress_ratio": -1 / 9,
                                       "axial_strain": 0.004, "rebound_axial_strain": 0.001, "radial_strain": 0.005}}


def summary(pattern, seed, phi_deg, c_pa):
    tests = []
    for s3 in (20e3, 40e3):
        s1, s3e = yield_state(s3, phi_deg, c_pa)
        # Seed 2's summaries predate the per-test plate speed.
        speed = {} if seed == 2 else {"plate_speed_m_per_s": 1e-7 * s3}
        start = LOADING_STARTS.get((pattern, seed, s3))
        speed.update({"loading_start": start} if start else {})
        tests.append({"confining_pressure_pa": s3, **speed, "peak_deviatoric_stress_pa": s1 - s3e, "peak_axial_strain": 0.04,
                      "sigma1_pa": s1, "sigma3_effective_pa": s3e, "max_q_shape": "rising",
                      "yield": {"shape": "plateau", "stress_ratio": (s1 - s3e) / (s1 + s3e), "axial_strain": 0.03,
                                "sigma1_pa": s1, "sigma3_effective_pa": s3e, "deviatoric_stress_pa": s1 - s3e},
                      "residual_stress_ratio": 0.2 + 0.01 * seed + s3 / 1e6, "quasi_static": True, "max_inertial_number": 5e-4,
                      "mean_kinetic_to_elastic": 2e-3, "steps": 1000, "wall_time_s": 10.0})
    mc = {"friction_angle_deg": phi_deg, "cohesion_pa": c_pa, "r_squared": 1.0,
          "paper_top_line_angle_deg": math.degrees(math.atan(math.sin(math.radians(phi_deg))))}
    return {"name": f"{pattern} {seed}", "tests": tests, "mohr_coulomb": mc, "mohr_coulomb_max_q": mc,
            "definitions": {"end_window_strain": 0.02},
            "specimen": {"grain_volume_fraction": 0.55, "wire_volume_fraction": 0.01 if pattern != "none" else 0.0,
                         "sample_volume_m3": math.pi * 0.02 ** 2 * 0.04, "grains": 3,
                         "wire_nodes": 401 if pattern != "none" else 0, "wire_length_m": 0.5,
                         "nozzle_path_m": 0.5, "pile_height_m": 0.04},
            "wire": {"pattern": pattern, **WIRE_LAGS.get((pattern, seed), {"autocorrelation_lag_m": None,
                                                                          "autocorrelation_prominent_lag_m": None})},
            "engine": {"time_step_s": 1e-5, "steps": 3000, "wall_time_s": 60.0, "body_steps_per_second": 1e7,
                       "threads": 1, "density_scale": 100.0}}


def write_h5(path, pattern, triaxial=None):
    radius, height = 0.02, 0.04
    job = {**({"triaxial": triaxial} if triaxial else {}), "specimen": {"membrane_radius_m": radius,
                        "wire": {"pattern": pattern, "radius_m": 5e-4, "segment_length_m": SEGMENT_M,
                                 "helix_radius_m": 0.012, "inner_radius_m": 0.004,
                                 "period_angle_rad": math.pi / 2}}}
    grains = np.array([[0.0, 0.0, 0.01], [0.005, 0.0, 0.02], [-0.005, 0.0, 0.03]])
    grain_r = np.full(3, 2e-3)
    wire = np.zeros((401 if pattern != "none" else 0, 3))
    if len(wire):
        theta = np.arange(len(wire)) * SEGMENT_M / 0.012
        wire = np.stack([0.012 * np.cos(theta), 0.012 * np.sin(theta), 0.005 + 1e-5 * np.arange(len(wire))], axis=1)
    membrane = np.array([[radius * math.cos(a), radius * math.sin(a), z] for a in np.linspace(0, 6, 12)
                         for z in (0.0, 0.02, 0.04)])
    with h5py.File(path, "w") as f:
        f["job_spec"] = json.dumps(job)
        s = f.create_group("specimen")
        s.attrs["pile_height_m"] = height
        s.attrs["wall_time_s"] = 12.5
        s["grain_position_m"], s["grain_radius_m"] = grains, grain_r
        s["wire_node_position_m"], s["membrane_node_position_m"] = wire, membrane
        for s3 in (20000, 40000):
            g = f.create_group(f"tests/sigma3_{s3}")
            g.attrs["confining_pressure_pa"] = float(s3)
            n = 50
            g["phase"] = np.array([0] * 5 + [2] * (n - 5), dtype=np.int32)
            g["axial_strain"] = np.linspace(0, 0.05, n)
            g["stress_ratio"] = np.tanh(np.linspace(0, 3, n)) * 0.3
            g["deviatoric_stress_pa"] = np.tanh(np.linspace(0, 3, n)) * s3
            g["volumetric_strain"] = np.linspace(0, 0.01, n)
            g["time_s"] = np.linspace(0, 1, n)
            g["height_m"] = height * (1 - np.linspace(0, 0.05, n))
            k = g.create_group("snapshots/snapshot_0")
            k.attrs["axial_strain"], k.attrs["requested_axial_strain"], k.attrs["time_s"] = 0.03, 0.03, 0.6
            k["grain_position_m"], k["grain_radius_m"] = grains, grain_r
            k["wire_node_position_m"], k["membrane_node_position_m"] = wire, membrane
            segments = max(len(wire) - 1, 0)
            k["wire_segment_strain"] = 1e-3 * np.sin(2 * np.pi * np.arange(segments) / PERIOD_SEGMENTS)
            k["contact_bodies"] = np.array([[0, 0, 0, 1], [0, 1, 0, 2]], dtype=np.uint32)
            k["contact_normal_force_n"] = np.array([1.0, 3.0])
            k["contact_force_n"] = np.array([[0, 0, 1.0], [0, 0, 3.0]])
            k["wall_contact_bodies"] = np.array([[0, 0, 0]], dtype=np.uint32)
            k["wall_contact_force_n"] = np.array([[0.0, 0.0, 2.0]])


NOT_CONSOLIDATED_20KPA = ("test 1/2 at sigma3 = 20000 Pa: test at σ₃ = 2e+04 Pa had not consolidated when loading "
                          "started: σ₁ = 1.73e+04 Pa (mean over the last 5 ms), more than 10 % off σ₃ after a hold of "
                          "0.25 s; lengthen hold_time_s or max_hold_time_s")


class StudyReport(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.TemporaryDirectory()
        runs = cls.runs = os.path.join(cls.tmp.name, "runs")
        cls.out = os.path.join(cls.tmp.name, "out")
        campaigns = {("helix", 1): (30.0, 1e3), ("helix", 2): (34.0, 3e3), ("none", 1): (20.0, 0.0)}
        for (pattern, seed), (phi, c) in campaigns.items():
            d = os.path.join(runs, f"{pattern}-seed{seed}")
            os.makedirs(d)
            s = summary(pattern, seed, phi, c)
            if (pattern, seed) == ("helix", 1):  # the hold ran out at 20 kPa, where the column flowed
                s["warnings"] = [NOT_CONSOLIDATED_20KPA, "test 2/2 at sigma3 = 40000 Pa: some other warning"]
            with open(os.path.join(d, "summary.json"), "w") as f:
                json.dump(s, f)
            write_h5(os.path.join(d, "result.h5"), pattern)
        with open(os.path.join(runs, "radial_helix-seed1.json"), "w") as f:  # a gathered summary
            json.dump(summary("radial_helix", 1, 25.0, 2e3), f)
        os.makedirs(os.path.join(runs, "spiral_helix-seed1"))  # unfinished: no summary.json
        with open(os.path.join(runs, "spiral_helix-seed1.json"), "w") as f:  # its job file, as study.sh keeps it
            json.dump({"name": "a job", "seed": 1, "specimen": {"wire": {"pattern": "spiral_helix"}}}, f)
        with open(os.path.join(runs, "spiral_helix-seed2.json"), "w") as f:  # a job file without its folder
            json.dump({"name": "a job", "seed": 2}, f)
        cls.proc = subprocess.run([sys.executable, SCRIPT, runs, "--out", cls.out], capture_output=True, text=True)
        with open(os.path.join(cls.out, "tables.md")) as f:
            cls.tables = f.read()

    @classmethod
    def tearDownClass(cls):
        cls.tmp.cleanup()

    def test_makes_the_figures_and_tables(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)
        figures = os.path.join(self.out, "figures")
        for name in ("specimen_none", "specimen_helix", "curves_none", "curves_helix", "mohr_none", "mohr_helix",
                     "mohr_radial_helix", "envelopes", "stress_ratio", "wire_strain_helix", "force_network_none"):
            path = os.path.join(figures, name + ".png")
            self.assertTrue(os.path.getsize(path) > 1000, path)
            self.assertIn(path, self.proc.stdout)
        # radial_helix has no result.h5: no pictures, but it counts in the tables
        self.assertFalse(os.path.exists(os.path.join(figures, "specimen_radial_helix.png")))
        self.assertIn("| radial helix | yield | 1 | 25.00 |", self.tables)
        self.assertIn("spiral_helix-seed1: no summary.json", self.proc.stdout)
        self.assertIn("spiral_helix-seed1: no summary.json", self.tables)
        # A job file beside a campaign folder is not its summary: no figure of a pattern without results.
        self.assertFalse(os.path.exists(os.path.join(figures, "mohr_spiral_helix.png")))
        self.assertIn("spiral_helix-seed2.json: not a campaign summary", self.proc.stdout)

    def test_mean_and_spread_of_phi_and_c_over_seeds(self):
        # φ = 30°, 34°: mean 32, sample sd 2√2 = 2.83; c = 1, 3 kPa: 2 ± √2
        self.assertIn("| helix | yield | 2 | 32.00 ± 2.83 | 2.00 ± 1.41 |", self.tables)

    def test_stress_ratio_at_yield_per_pressure_over_seeds(self):
        # The helix's two seeds: η at 20 kPa from their envelopes (30°, 1 kPa) and (34°, 3 kPa).
        etas = []
        for phi, c in ((30.0, 1e3), (34.0, 3e3)):
            s1, s3 = yield_state(20e3, phi, c)
            etas.append((s1 - s3) / (s1 + s3))
        mean = sum(etas) / 2
        sd = abs(etas[0] - etas[1]) / math.sqrt(2)
        self.assertRegex(self.tables, r"\| helix \| " + re.escape(f"{mean:.3f} ± {sd:.3f} (2)") + r" \| ")
        stats = report.yield_ratio_stats(report.find_campaigns(self.runs)[0]["helix"])
        self.assertAlmostEqual(stats[20e3][0], mean)
        self.assertAlmostEqual(stats[20e3][1], sd)
        self.assertEqual(stats[20e3][2], 2)
        # One seed without wire: its η is listed, but no difference with it is judged.
        self.assertRegex(self.tables, r"\| no wire − helix \| 20 \| [-+]0\.[0-9]{3} \| — \| not judged \|")

    def test_residual_stress_ratio_per_pressure_over_seeds(self):
        # The helix's seeds 1 and 2 at 40 kPa: 0.25 and 0.26, mean 0.255, sd 0.01/√2; one seed without wire.
        self.assertIn("| helix | 0.235 ± 0.007 (2) | 0.255 ± 0.007 (2) |", self.tables)
        self.assertIn("residual η at σ₃ = 40 kPa", self.tables)
        self.assertIn("over the last 2 % of axial strain", self.tables)
        stats = report.residual_ratio_stats(report.find_campaigns(self.runs)[0]["helix"])
        self.assertAlmostEqual(stats[40e3][0], 0.255)
        self.assertAlmostEqual(stats[40e3][1], 0.01 / math.sqrt(2))

    def test_tests_that_flowed_in_extension_before_loading(self):
        # Helix seed 1 lengthened by 2 % in the hold at 20 kPa (flowed), by 0.1 % at 40 kPa (did not);
        # seed 2's summary predates loading_start.
        self.assertIn("| helix-seed1 | 20 | — | — | 2.50 | -0.429 | -2.00 | 2.00 | **yes** |", self.tables)
        self.assertIn("| helix-seed1 | 40 | — | — | 1.25 | -0.111 | +0.40 | 0.10 | no |", self.tables)
        self.assertIn("| helix-seed2 | 20 | — | — | — | — | — | — | not recorded |", self.tables)
        helix = report.find_campaigns(self.runs)[0]["helix"]
        flags = [report.flowed_in_extension(t) for c in helix for t in c.tests()]
        self.assertEqual(flags, [True, False, None, None])
        # η at yield without it: seed 2 alone at 20 kPa, both seeds at 40 kPa.
        s1, s3 = yield_state(20e3, 34.0, 3e3)
        clean = report.per_pressure_stats(helix, report.yield_ratio, lambda t: report.flowed_in_extension(t) is not True)
        self.assertAlmostEqual(clean[20e3][0], (s1 - s3) / (s1 + s3))
        self.assertEqual(clean[20e3][2], 1)
        self.assertEqual(clean[40e3][2], 2)
        self.assertIn(f"| helix | {(s1 - s3) / (s1 + s3):.3f} (1) |", self.tables)

    def test_retests_beside_their_campaigns_and_in_their_place(self):
        # Helix seed 1 tested again from its specimen consolidated to σ₃,eff (φ 31°, c 1 kPa instead of
        # 30°, 1 kPa), and a retest of a campaign the study does not have.
        retests = os.path.join(self.tmp.name, "retests")
        d = os.path.join(retests, "helix-seed1")
        os.makedirs(d)
        again = summary("helix", 1, 31.0, 1e3)
        again["tests"] = again["tests"][:1]  # the 20 kPa test only
        # consolidated to σ₃,eff: loading starts from η ≈ 0, nothing flowed
        again["tests"][0]["loading_start"] = {"stress_ratio": -0.01, "rebound_axial_strain": 0.0004}
        with open(os.path.join(d, "summary.json"), "w") as f:
            json.dump(again, f)
        write_h5(os.path.join(d, "result.h5"), "helix", {"consolidation": "effective"})
        # A gathered retest summary (no result.h5) says how its tests were consolidated itself.
        gathered = summary("radial_helix", 1, 26.0, 2e3)
        for t in gathered["tests"]:
            t["consolidation"] = "effective"
        with open(os.path.join(retests, "radial_helix-seed1.json"), "w") as f:
            json.dump(gathered, f)
        with open(os.path.join(retests, "none-seed7.json"), "w") as f:
            json.dump(summary("none", 7, 20.0, 0.0), f)
        out = os.path.join(self.tmp.name, "out-retests")
        proc = subprocess.run([sys.executable, SCRIPT, self.runs, "--retests", retests, "--out", out],
                              capture_output=True, text=True)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        with open(os.path.join(out, "tables.md")) as f:
            tables = f.read()
        self.assertIn("## Retests", tables)
        self.assertNotIn("## Retests", self.tables)  # only when asked for
        eta = {}
        for phi, c in ((30.0, 1e3), (31.0, 1e3), (34.0, 3e3)):
            s1, s3 = yield_state(20e3, phi, c)
            eta[phi] = (s1 - s3) / (s1 + s3)
        self.assertIn(f"| helix-seed1 | 20 | cell pressure | — | **yes** | -0.429 | 2.00 | {eta[30.0]:.3f} (plateau) |",
                      tables)
        self.assertIn(f"| ↳ retest | 20 | effective | — | no | -0.010 | 0.04 | {eta[31.0]:.3f} (plateau) |", tables)
        self.assertIn("Retests without a study campaign of their name (not compared): none-seed7.", tables)
        self.assertRegex(tables, r"\| radial_helix-seed1 \| 20 \| — \| — \| no \|")  # no result.h5, no key
        self.assertRegex(tables, r"\| ↳ retest \| 20 \| effective \| — \| no \| — \| — \| 0\.4")
        self.assertRegex(tables, r"\| ↳ retest \| 40 \| effective \|")
        self.assertEqual(tables.count("| ↳ retest | 40 |"), 1)  # helix-seed1's retest has no 40 kPa test
        # The helix's η at 20 kPa with seed 1's retest in place of its test: seeds (31°, 1 kPa) and
        # (34°, 3 kPa); at 40 kPa, not retested, the study's (30°, 1 kPa) and (34°, 3 kPa).
        mean = (eta[31.0] + eta[34.0]) / 2
        sd = abs(eta[31.0] - eta[34.0]) / math.sqrt(2)
        self.assertIn(f"| helix | {mean:.3f} ± {sd:.3f} (2) | 0.548 ± 0.053 (2) |", tables)
        self.assertIn("η at yield with the retested tests (helix-seed1, radial_helix-seed1)", tables)
        self.assertEqual(report.unconsolidated_pressures({"warnings": [NOT_CONSOLIDATED_20KPA]}), {20e3})
        self.assertEqual(report.unconsolidated_pressures(
            {"warnings": ["test 2/2 at sigma3 = 40000 Pa: some other warning"]}), set())
        self.assertEqual(report.unconsolidated_pressures({}), set())
        # A summary whose tests carry their verdict is read by it, not by the warnings.
        verdicts = {"tests": [{"confining_pressure_pa": 20000, "consolidated": True},
                              {"confining_pressure_pa": 40000, "consolidated": False}],
                    "warnings": [NOT_CONSOLIDATED_20KPA]}
        self.assertEqual(report.unconsolidated_pressures(verdicts), {40e3})
        # And on warnings the engine wrote: the study's radial helix seed 2 (docs/study/), whose 20 and
        # 40 kPa tests ran out the hold off σ₃, and its retest of them, which did not.
        with open(os.path.join(ROOT, "docs", "study", "radial_helix-seed2.json")) as f:
            self.assertEqual(report.unconsolidated_pressures(json.load(f)), {20e3, 40e3})
        with open(os.path.join(ROOT, "docs", "study", "retests", "radial_helix-seed2.json")) as f:
            self.assertEqual(report.unconsolidated_pressures(json.load(f)), set())
        # A missing retest folder is an error, not an empty section.
        proc = subprocess.run([sys.executable, SCRIPT, self.runs, "--retests", os.path.join(retests, "nope"),
                               "--out", out], capture_output=True, text=True)
        self.assertEqual(proc.returncode, 2)
        self.assertIn("is not a folder", proc.stderr)

    def test_difference_criterion(self):
        delta, bound, verdict = report.difference_exceeds_scatter((32.0, 2 * math.sqrt(2), 2), (20.0, 1.0, 2))
        self.assertAlmostEqual(delta, 12.0)
        self.assertAlmostEqual(bound, 2 * math.sqrt(8 / 2 + 1 / 2))
        self.assertTrue(verdict)
        self.assertFalse(report.difference_exceeds_scatter((32.0, 2 * math.sqrt(2), 2), (29.0, 1.0, 2))[2])
        self.assertIsNone(report.difference_exceeds_scatter((32.0, 2.0, 2), (20.0, None, 1))[2])

    def test_every_test_states_its_plate_speed(self):
        self.assertRegex(self.tables, r"\| helix-seed1 \| 20 \| 2 \| ")
        self.assertRegex(self.tables, r"\| helix-seed1 \| 40 \| 4 \| ")
        self.assertRegex(self.tables, r"\| helix-seed2 \| 20 \| — \| ")

    def test_wire_lags_are_summary_jsons(self):
        # Both lags of seed 1 as summary.json gives them, not R's maximum of the synthetic sine (50 mm);
        # seed 2's summary predates the prominent lag: absent, not "no maximum".
        self.assertRegex(self.tables, r"\| helix-seed1 \|.*\| 12\.50 \| 50\.00 \|")
        self.assertRegex(self.tables, r"\| helix-seed2 \|.*\| 50\.00 \| absent \|")
        self.assertEqual(report.summary_lags({"wire": {"autocorrelation_lag_m": None}}),
                         {"autocorrelation_lag_m": None, "autocorrelation_prominent_lag_m": "absent"})

    def test_the_wire_autocorrelation_is_the_engines(self):
        # R of the synthetic sine from `wiredem autocorrelation` (the package's door to the engine's
        # function): 1 at lag 0, its first maximum after 0 at the sine's period, 40 segments.
        c = report.find_campaigns(self.runs)[0]["helix"][0]
        r = report.autocorrelation(report.wire_snapshot(c)[3], report.default_wiredem())
        self.assertAlmostEqual(r[0], 1.0, places=12)
        k = int(np.argmax(r[1:60])) + 1
        self.assertEqual(k, PERIOD_SEGMENTS)

    def test_loop_lengths(self):
        wire = {"pattern": "helix", "helix_radius_m": 0.012}
        self.assertAlmostEqual(report.loop_lengths_m(wire)[0][1], 2 * math.pi * 0.012)
        # spiral helix: the arc of a large turn against a fine polyline of P(Θ)
        ra, ri, phi = 0.012, 0.004, math.pi / 2
        th = np.linspace(0, 2 * math.pi, 400001)
        p = np.stack([ra * np.cos(th) + ri * np.cos(4 * th), ra * np.sin(th) + ri * np.sin(4 * th)], axis=1)
        polyline = float(np.sum(np.linalg.norm(np.diff(p, axis=0), axis=1)))
        loops = dict(report.loop_lengths_m({"pattern": "spiral_helix", "helix_radius_m": ra, "inner_radius_m": ri,
                                            "period_angle_rad": phi}))
        self.assertAlmostEqual(loops["arc per large turn"], polyline, delta=1e-7)
        self.assertAlmostEqual(loops["arc per small loop"], polyline / 4, delta=1e-7)
        self.assertAlmostEqual(loops["2π R_i (small circle)"], 2 * math.pi * ri)
        # radial helix, R_a = 7 mm, r_w = 0.5 mm, φ_rs = π/2, worked by hand: gap 1.25 mm,
        # r_min = 1.25/sin 45° = 1.7678 mm, legs 5.2322 and √(49 − 1.5625) − 1.7678 = 5.1197 mm,
        # β = asin(1.25/7) = 0.17953, arc (π/2 + β) 7 mm = 12.2523 mm: 23.854 mm
        period = report.loop_lengths_m({"pattern": "radial_helix", "helix_radius_m": 0.007, "radius_m": 5e-4,
                                        "period_angle_rad": math.pi / 2})[0][1]
        self.assertAlmostEqual(period * 1e3, 23.854, delta=0.002)


if __name__ == "__main__":
    unittest.main()
