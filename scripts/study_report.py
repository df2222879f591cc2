#!/usr/bin/python3
"""Figures and tables of the full-size study (docs/study.md, issue 14).

    /usr/bin/python3 scripts/study_report.py RUNS [--out docs/study]

RUNS holds the campaigns of scripts/study.sh, one folder <pattern>-seed<k>/ each
(result.h5, summary.json, job.json; docs/results.md describes the files). A
campaign without summary.json (unfinished or failed) is skipped; one without
result.h5 still counts in the tables drawn from summary.json. A flat
<pattern>-seed<k>.json in RUNS (the summaries gathered in docs/study/) counts as
such a summary-only campaign, so the tables can be remade from git alone.
Writes OUT/figures/*.png and OUT/tables.md, and prints what it made.

    /usr/bin/python3 scripts/study_report.py RUNS --retests RETESTS [--out ...]

also reads RETESTS, campaigns of the same names tested again from their
specimens with other test settings (scripts/study.sh --specimens-from RUNS),
and adds to tables.md each retest beside its original, test by test, and η at
yield per pattern with the retests in place of their originals.

Reads the campaigns with the wiredem package (python/, docs/python.md), from
the source tree when it is not installed, and draws with its plot helpers; the
wire's autocorrelation R(lag) is the engine's, from the `wiredem` binary
(--wiredem, default $WIREDEM_BIN, the PATH, or build/release/bin/wiredem).
Needs Debian's /usr/bin/python3 with numpy, pandas, h5py and matplotlib
(python3-numpy, python3-pandas, python3-h5py, python3-matplotlib); nothing else.
"""
import argparse
import json
import math
import os
import re
import shutil
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import LineCollection, PatchCollection  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
from matplotlib.ticker import MaxNLocator  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Line3DCollection  # noqa: E402

try:
    import wiredem  # noqa: E402
except ImportError:  # not installed: the package of this source tree
    sys.path.insert(0, os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "python"))
    import wiredem  # noqa: E402
from wiredem import plots  # noqa: E402

PATTERNS = ("none", "helix", "spiral_helix", "radial_helix")
PATTERN_LABEL = {"none": "no wire", "helix": "helix", "spiral_helix": "spiral helix",
                 "radial_helix": "radial helix"}
PATTERN_COLOUR = {"none": "#555555", "helix": "#1f77b4", "spiral_helix": "#d62728",
                  "radial_helix": "#2ca02c"}
# Line styles too, so that envelopes that coincide stay distinguishable.
PATTERN_STYLE = {"none": "-", "helix": "--", "spiral_helix": "-.", "radial_helix": (0, (1, 1))}
CAMPAIGN_NAME = re.compile(r"^(none|helix|spiral_helix|radial_helix)-seed(\d+)(\.json)?$")

# The radial helix's hairpin gap is 2.5 r_w (the Nozzle's NozzlePath in
# engine/specimen/preparation.cpp); the loop lengths below follow
# engine/specimen/pattern.cpp and must change with them.
HAIRPIN_GAP_PER_WIRE_RADIUS = 2.5


# ---------------------------------------------------------------------------
# Numbers (pure functions, tested by tests/scripts/test_study_report.py)

def mean_sd(values):
    """(mean, sample standard deviation, n) of the finite values; sd is None for n < 2."""
    v = [float(x) for x in values if x is not None and math.isfinite(x)]
    if not v:
        return None, None, 0
    mean = sum(v) / len(v)
    sd = math.sqrt(sum((x - mean) ** 2 for x in v) / (len(v) - 1)) if len(v) > 1 else None
    return mean, sd, len(v)


def scaled(stat, factor):
    """A (mean, sd, n) in other units."""
    m, s, n = stat
    return (m * factor if m is not None else None, s * factor if s is not None else None, n)


def difference_exceeds_scatter(a, b):
    """Whether two patterns' means differ by more than their scatter allows.

    a, b: (mean, sd, n). The criterion: |m1 - m2| > 2 sqrt(s1²/n1 + s2²/n2), twice
    the standard error of the difference of two means (Welch): about a 95 %
    two-sided test for normal scatter and many seeds, lenient with 2-3 seeds
    (Student's t for 2 degrees of freedom is 4.3, not 2). Returns (delta, bound,
    verdict) with verdict None when either side has fewer than 2 seeds.
    """
    (m1, s1, n1), (m2, s2, n2) = a, b
    if m1 is None or m2 is None:
        return None, None, None
    delta = m1 - m2
    if n1 < 2 or n2 < 2:
        return delta, None, None
    bound = 2.0 * math.sqrt(s1 * s1 / n1 + s2 * s2 / n2)
    return delta, bound, abs(delta) > bound


def autocorrelation(snapshot, wiredem=None):
    """R(lag) of a snapshot's wire segment strains, the engine's (`wiredem autocorrelation`,
    engine/analysis/autocorrelation.hpp, through the wiredem package): the function
    summary.json's lags come from, so the curve drawn under them is theirs. None
    when there is none (fewer than 2 segments, a constant signal)."""
    reply = snapshot.wire_autocorrelation(wiredem)
    return None if reply["error"] else np.asarray(reply["coefficients"], dtype=float)


# summary.json's wire lags (docs/results.md): the first local maximum of R after
# lag 0 and the first prominent one (prominence above the white-noise band).
LAG_KEYS = (("autocorrelation_lag_m", "first maximum"), ("autocorrelation_prominent_lag_m", "first prominent maximum"))


def summary_lags(summary):
    """{key: lag [m] or None} of summary.json's wire, for LAG_KEYS; a key missing
    from the file (a summary written before it existed) maps to the string
    "absent", so that a table can tell "not computed" from "no such maximum"."""
    wire = summary.get("wire") or {}
    return {key: wire.get(key) if key in wire else "absent" for key, _ in LAG_KEYS}


def loop_lengths_m(wire):
    """The lengths of path of the loops a pattern lays, [(label, metres)].

    `wire` is the job's specimen.wire (every field, as in result.h5's /job_spec).
    The nozzle walks its horizontal path (engine/specimen/pattern.cpp) while it
    rises with the pile; the rise per loop (a pitch of a few mm against loops of
    several cm) lengthens the wire by well under 1 %, so it is left out.
    """
    pattern = wire["pattern"]
    ra = wire["helix_radius_m"]
    if pattern == "helix":
        return [("2π R_a (one turn)", 2.0 * math.pi * ra)]
    if pattern == "spiral_helix":
        ri, phi_rs = wire["inner_radius_m"], wire["period_angle_rad"]
        # P(Θ) = R_a (cos Θ, sin Θ) + R_i (cos ψ, sin ψ), ψ = kΘ, k = 2π/φ_rs: the
        # small circle turns once per φ_rs of the large angle. |dP/dΘ| depends on
        # Θ through cos((k - 1)Θ), so one small loop's arc depends on where it
        # starts; the mean arc per small loop is a large turn's arc / (2π/φ_rs).
        k = 2.0 * math.pi / phi_rs
        theta = np.linspace(0.0, 2.0 * math.pi, 200001)
        speed = np.sqrt(ra * ra + (ri * k) ** 2 + 2.0 * ra * ri * k * np.cos((k - 1.0) * theta))
        large_turn = float(np.sum(0.5 * (speed[1:] + speed[:-1]) * np.diff(theta)))
        return [("2π R_i (small circle)", 2.0 * math.pi * ri),
                ("arc per small loop", large_turn * phi_rs / (2.0 * math.pi)),
                ("arc per large turn", large_turn)]
    if pattern == "radial_helix":
        # NozzlePath::hairpin(): in along the radius to r_min, across by the gap,
        # out on the parallel leg to the circle (meeting it β behind), then the
        # arc φ_rs + β to the next excursion.
        phi_rs = wire["period_angle_rad"]
        gap = HAIRPIN_GAP_PER_WIRE_RADIUS * wire["radius_m"]
        half = 0.5 * min(phi_rs, math.pi)
        r_min = max(gap, 2.0 * gap / (2.0 * math.sin(half)))
        leg_in = ra - r_min
        leg_out = math.sqrt(ra * ra - gap * gap) - r_min
        beta = math.asin(gap / ra)
        return [("path per period φ_rs (with hairpin)", leg_in + gap + leg_out + (phi_rs + beta) * ra)]
    return []


# ---------------------------------------------------------------------------
# Campaigns

class Campaign:
    """One campaign: its summary, and its result (wiredem.Result: result.h5 with the
    summary beside it) and full job spec when present."""

    def __init__(self, pattern, seed, summary_path, h5_path):
        self.pattern, self.seed = pattern, seed
        self.name = f"{pattern}-seed{seed}"
        with open(summary_path) as f:
            self.summary = json.load(f)
        self.h5 = h5_path if h5_path and os.path.isfile(h5_path) else None
        self.job = None
        self.result = None
        if self.h5:
            self.result = wiredem.open(self.h5)
            self.job = self.result.job_spec

    def tests(self):
        """summary tests[], by ascending confining pressure."""
        return sorted(self.summary.get("tests", []), key=lambda t: t["confining_pressure_pa"])


def find_campaigns(runs, report_missing=True):
    """({pattern: [Campaign by seed]}, [notes on what was skipped, and, if report_missing, what is missing])."""
    found, notes, skipped = {}, [], set()
    entries = sorted(os.listdir(runs))
    for entry in entries:
        m = CAMPAIGN_NAME.match(entry)
        if not m:
            continue
        pattern, seed, flat = m.group(1), int(m.group(2)), m.group(3) is not None
        path = os.path.join(runs, entry)
        if flat:
            if (pattern, seed) in found or (pattern, seed) in skipped:
                continue  # the campaign's folder, finished or not, wins over a file beside it
            summary, h5 = path, None
        elif os.path.isdir(path):
            summary, h5 = os.path.join(path, "summary.json"), os.path.join(path, "result.h5")
            if not os.path.isfile(summary):
                notes.append(f"{entry}: no summary.json (unfinished or failed), skipped")
                skipped.add((pattern, seed))
                continue
        else:
            continue
        try:
            c = Campaign(pattern, seed, summary, h5)
        except (OSError, ValueError, KeyError, wiredem.WiredemError) as e:
            notes.append(f"{entry}: unreadable ({e}), skipped")
            skipped.add((pattern, seed))
            continue
        if not isinstance(c.summary, dict) or "tests" not in c.summary or "mohr_coulomb" not in c.summary:
            # scripts/study.sh keeps each campaign's job file beside its folder
            notes.append(f"{entry}: not a campaign summary (a job file?), skipped")
            skipped.add((pattern, seed))
            continue
        if c.h5 is None and not flat:
            notes.append(f"{entry}: no result.h5: in the tables only")
        found[(pattern, seed)] = c
    by_pattern = {p: sorted((c for (q, _), c in found.items() if q == p), key=lambda c: c.seed) for p in PATTERNS}
    seeds = {s for (_, s) in found} | {s for (_, s) in skipped}
    for p in PATTERNS if report_missing else ():
        have = {c.seed for c in by_pattern[p]}
        missing = sorted(s for s in seeds - have if (p, s) not in skipped)
        if not have and not any(q == p for q, _ in skipped):
            notes.append(f"{p}: no campaign")
        elif missing:
            notes.append(f"{p}: seed(s) {', '.join(map(str, missing))} missing")
    return {p: cs for p, cs in by_pattern.items() if cs}, notes


def lead(campaigns):
    """The campaign drawn bold or alone: seed 1, else the lowest seed with result.h5."""
    with_h5 = [c for c in campaigns if c.h5]
    return next((c for c in with_h5 if c.seed == 1), with_h5[0] if with_h5 else None)


# ---------------------------------------------------------------------------
# Formatting

def fmt(x, spec=".3g"):
    return "—" if x is None or (isinstance(x, float) and not math.isfinite(x)) else format(x, spec)


def percent(x):
    """A fraction in %, None kept."""
    return None if x is None else 100.0 * x


def ratio_to(x, reference):
    """x / reference, None kept."""
    return None if x is None else x / reference


def fmt_mean(stat, spec=".3g", n_expected=None):
    """'mean ± sd' (or just the mean for one value), with (n=k) when fewer values than seeds."""
    m, s, n = stat
    if m is None:
        return "—"
    text = format(m, spec) + (f" ± {format(s, spec)}" if s is not None else "")
    return text + (f" (n={n})" if n_expected is not None and n != n_expected else "")


def table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def pressure_colours(by_pattern):
    """One colour per confining pressure, the same in every figure."""
    pressures = sorted({t["confining_pressure_pa"] for cs in by_pattern.values() for c in cs for t in c.tests()})
    cmap = plt.get_cmap("viridis")
    n = max(1, len(pressures) - 1)
    return {p: cmap(0.85 * i / n) for i, p in enumerate(pressures)}


def kpa(p):
    return f"{p / 1e3:g} kPa"


def save(fig, out_dir, name, made):
    path = os.path.join(out_dir, name)
    fig.savefig(path, dpi=130)
    plt.close(fig)
    made.append(path)


# ---------------------------------------------------------------------------
# 1. Specimen

def specimen_values(c):
    """Whole-column and core values of one campaign (None when absent); volume fractions of wire in %."""
    sp = c.summary.get("specimen", {})
    v = {"volume_cm3": sp.get("sample_volume_m3") and sp["sample_volume_m3"] * 1e6,
         "grain": sp.get("grain_volume_fraction"),
         "wire_pct": sp.get("wire_volume_fraction") and sp["wire_volume_fraction"] * 100,
         "wire_length_m": sp.get("wire_length_m"), "wire_nodes": sp.get("wire_nodes"),
         "nozzle_path_m": sp.get("nozzle_path_m"),
         "height_cm": sp.get("pile_height_m") and sp["pile_height_m"] * 100,
         "grains": sp.get("grains"),
         # The core's fractions are the engine's (engine/specimen/packing.hpp), written by the runner.
         "core_grain": sp.get("core_grain_volume_fraction"),
         "core_wire_pct": sp.get("core_wire_volume_fraction") and sp["core_wire_volume_fraction"] * 100,
         "prep_wall_s": sp.get("preparation_wall_time_s")}
    if v["wire_length_m"] is not None and v["nozzle_path_m"]:
        v["laid_pct"] = 100.0 * v["wire_length_m"] / v["nozzle_path_m"]
    else:
        v["laid_pct"] = None
    if v["prep_wall_s"] is None and c.result:  # summaries from before the key existed
        v["prep_wall_s"] = float(c.result.specimen.attributes["wall_time_s"])
    if c.pattern == "none":  # "—" rather than rows of zeros
        v.update({k: None for k in WIRE_KEYS})
    return v


SPECIMEN_COLUMNS = [  # key, header, format
    ("volume_cm3", "sample volume [cm³]", ".2f"), ("grains", "grains", ".0f"),
    ("grain", "grain fraction, column", ".3f"), ("core_grain", "grain fraction, core", ".3f"),
    ("wire_pct", "wire fraction, column [%]", ".2f"), ("core_wire_pct", "wire fraction, core [%]", ".2f"),
    ("wire_length_m", "wire laid [m]", ".3f"), ("wire_nodes", "wire nodes", ".0f"),
    ("nozzle_path_m", "nozzle path [m]", ".3f"), ("laid_pct", "laid / path [%]", ".0f"),
    ("height_cm", "pile height [cm]", ".2f"), ("prep_wall_s", "preparation wall time [s]", ".1f")]
WIRE_KEYS = {"wire_pct", "core_wire_pct", "wire_length_m", "wire_nodes", "nozzle_path_m", "laid_pct"}


def specimen_tables(by_pattern):
    per = {p: [(c, specimen_values(c)) for c in cs] for p, cs in by_pattern.items()}
    rows = []
    for p, items in per.items():
        row = [PATTERN_LABEL[p], len(items)]
        for key, _, spec in SPECIMEN_COLUMNS:
            row.append(fmt_mean(mean_sd([v[key] for _, v in items]), spec, len(items)))
        rows.append(row)
    text = ("Mean ± sample standard deviation over the seeds (n); (n=k) where fewer campaigns had a "
            "result.h5. The core is the column a grain diameter away from the membrane and both "
            "plates (the engine's estimate, `engine/specimen/packing.hpp`).\n\n")
    text += table(["pattern", "n"] + [h for _, h, _ in SPECIMEN_COLUMNS], rows)
    detail = []
    for p, items in per.items():
        for c, v in items:
            detail.append([c.name] + [fmt(v[k], spec) for k, _, spec in SPECIMEN_COLUMNS])
    text += "\n<details><summary>per campaign</summary>\n\n"
    text += table(["campaign"] + [h for _, h, _ in SPECIMEN_COLUMNS], detail) + "\n</details>\n"
    return text


# ---------------------------------------------------------------------------
# 2. Specimen pictures

def specimen_picture(p, c, out, made):
    s = c.result.specimen
    gp, gr, wp = s.grain_position_m * 1e3, s.grain_radius_m * 1e3, s.wire_node_position_m * 1e3
    height = float(s.attributes["pile_height_m"]) * 1e3
    radius = c.job["specimen"]["membrane_radius_m"] * 1e3
    with_wire = len(wp) > 1
    # Tall enough for the column's aspect (the study's is 3:1, main.json's 2:3);
    # without wire only the cut-away.
    fig = plt.figure(figsize=(11 if with_wire else 6, min(11.0, max(4.8, 1.6 + 4.4 * height / (2 * radius)))))
    fig.suptitle(f"Prepared specimen, {PATTERN_LABEL[p]}, seed {c.seed}: {len(gr)} grains"
                 + (f", {len(wp)} wire nodes ({c.summary['specimen'].get('wire_length_m', 0):.3g} m)"
                    if with_wire else "")
                 + ("\nleft: the wire alone, coloured by height; right: " if with_wire else "\n")
                 + "the column cut away (the half y < 0 removed), seen from −y"
                 + (", the wire's half y ≥ 0 drawn over the grains" if with_wire else ""), fontsize=10)

    if with_wire:
        ax = fig.add_subplot(1, 2, 1, projection="3d")
        # Coloured by height: turns laid one above another stay apart in the view.
        segments = np.stack([wp[:-1], wp[1:]], axis=1)
        lc = Line3DCollection(segments, cmap="viridis", linewidths=1.2)
        lc.set_array(0.5 * (segments[:, 0, 2] + segments[:, 1, 2]))
        ax.add_collection3d(lc)
        fig.colorbar(lc, ax=ax, shrink=0.5, pad=0.08, fraction=0.05, label="height z [mm]")
        ang = np.linspace(0, 2 * np.pi, 90)
        for zz in (0.0, height):  # the membrane's outline at both plates
            ax.plot(radius * np.cos(ang), radius * np.sin(ang), zz, color="0.6", lw=0.8)
        ax.set_xlim(-radius, radius)
        ax.set_ylim(-radius, radius)
        ax.set_zlim(0, height)
        # A tall column leaves a 3-D box little room: zoom in, fewer ticks.
        ax.set_box_aspect((2 * radius, 2 * radius, height), zoom=1.0 + 0.12 * min(1.0, height / (2 * radius)))
        ax.xaxis.set_major_locator(MaxNLocator(3))
        ax.yaxis.set_major_locator(MaxNLocator(3))
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_zlabel("z [mm]")

    ax = fig.add_subplot(1, 2, 2) if with_wire else fig.add_subplot(1, 1, 1)
    # Cut-away: the half y < 0 is removed and the rest seen from -y, so the grains
    # are discs in the x–z plane drawn from the back (large y) to the front, the
    # nearer ones darker; the wire's half y >= 0 is drawn over them.
    keep = gp[:, 1] >= 0.0
    order = np.argsort(-gp[keep, 1])
    depth = gp[keep, 1][order] / radius
    shade = 0.55 + 0.35 * depth[:, None] * np.ones(3)
    ax.add_collection(PatchCollection([plt.Circle((x, z), r) for (x, _, z), r in zip(gp[keep][order], gr[keep][order])],
                                      facecolors=shade * np.array([1.0, 0.93, 0.8]), edgecolors="0.3", linewidths=0.3))
    if with_wire:
        front = (wp[:-1, 1] >= 0.0) & (wp[1:, 1] >= 0.0)
        segs = np.stack([wp[:-1, [0, 2]], wp[1:, [0, 2]]], axis=1)[front]
        ax.add_collection(LineCollection(segs, colors=PATTERN_COLOUR[p], linewidths=2.0))
    ax.plot([-radius, -radius], [0, height], color="0.4", lw=1)
    ax.plot([radius, radius], [0, height], color="0.4", lw=1)
    ax.axhline(0.0, color="k", lw=2)
    ax.axhline(height, color="k", lw=2)
    ax.set_xlim(-radius * 1.08, radius * 1.08)
    ax.set_ylim(-0.04 * height, height * 1.04)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("z [mm]")

    fig.tight_layout()
    save(fig, out, f"specimen_{p}.png", made)


# ---------------------------------------------------------------------------
# 3. Curves

CURVE_COLUMNS = ("stress_ratio", "deviatoric_stress_pa", "volumetric_strain")


def curves_figure(p, campaigns, colours, out, made):
    bold = lead(campaigns)
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.8))
    for c in campaigns:
        if not c.h5:
            continue
        lw, alpha = (2.0, 1.0) if c is bold else (0.8, 0.6)
        for t in c.result.tests:  # yield and max-q marked at the engine's states (summary.json)
            plots.draw_test_curves(axes, t, CURVE_COLUMNS, colour=colours.get(t.confining_pressure_pa, "k"), lw=lw,
                                   alpha=alpha, marker_size=7 if c is bold else 5)
    plots.label_curve_axes(axes, CURVE_COLUMNS)
    handles = [Line2D([], [], color=col, lw=2, label=f"σ₃ = {kpa(s3)}") for s3, col in colours.items()]
    handles += [Line2D([], [], color="k", lw=2, label=f"seed {bold.seed}" if bold else "seed 1"),
                Line2D([], [], color="k", lw=0.8, alpha=0.6, label="other seeds"),
                Line2D([], [], marker="o", mfc="0.6", mec="k", ls="none", label="yield (max of smoothed η)"),
                Line2D([], [], marker="^", mfc="white", mec="k", ls="none", label="max of q")]
    fig.legend(handles=handles, loc="lower center", ncol=len(handles), fontsize=8, frameon=False)
    seeds = ", ".join(str(c.seed) for c in campaigns if c.h5)
    fig.suptitle(f"Triaxial tests, {PATTERN_LABEL[p]} (seeds {seeds}; loading only)")
    fig.tight_layout(rect=(0, 0.06, 1, 1))
    save(fig, out, f"curves_{p}.png", made)


# ---------------------------------------------------------------------------
# 4. and 5. Mohr–Coulomb

def fit_stats(campaigns, key):
    """Mean/sd/n of φ, c, R², α of the fit `key` (mohr_coulomb or mohr_coulomb_max_q) over seeds."""
    fits = [c.summary.get(key) or {} for c in campaigns]
    return {"phi": mean_sd([f.get("friction_angle_deg") for f in fits]),
            "c": mean_sd([f.get("cohesion_pa") for f in fits]),
            "r2": mean_sd([f.get("r_squared") for f in fits]),
            "alpha": mean_sd([f.get("paper_top_line_angle_deg") for f in fits])}


def mohr_figure(p, campaigns, colours, out, made):
    bold = lead(campaigns) or campaigns[0]
    fig, ax = plt.subplots(figsize=(9, 6))
    sigma_max = tau_max = 0.0
    for c in campaigns:
        for t in c.tests():
            y = t.get("yield")
            if not y or y.get("sigma1_pa") is None:
                continue
            radius = plots.draw_mohr_circle(ax, y["sigma1_pa"], y["sigma3_effective_pa"],
                                            colours.get(t["confining_pressure_pa"], "k"),
                                            lw=1.8 if c is bold else 0.8, alpha=1.0 if c is bold else 0.6)
            sigma_max, tau_max = max(sigma_max, y["sigma1_pa"] / 1e3), max(tau_max, radius)
    sigma = np.linspace(0.0, 1.05 * sigma_max if sigma_max else 1.0, 50)
    for c in campaigns:  # each seed's own envelope, thin
        mc = wiredem.MohrCoulomb.from_json(c.summary.get("mohr_coulomb"))
        if mc.friction_angle_deg is not None:
            plots.draw_envelope(ax, mc, sigma, color=PATTERN_COLOUR[p], lw=0.6, alpha=0.5)
    st = fit_stats(campaigns, "mohr_coulomb")
    phi, c_pa, alpha = st["phi"][0], st["c"][0], st["alpha"][0]
    if phi is not None:
        ax.plot(sigma, c_pa / 1e3 + sigma * math.tan(math.radians(phi)), color=PATTERN_COLOUR[p], lw=2.2,
                label=f"tangent envelope τ = c + σ tan φ: φ = {fmt_mean(st['phi'], '.1f')}°, "
                      f"c = {fmt_mean(scaled(st['c'], 1e-3), '.2f')} kPa")
        # The line through the circle tops, t = a + p tan α with a = c cos φ (the
        # fit in engine/analysis/mohr_coulomb.hpp), from the means over seeds.
        fits = [c.summary.get("mohr_coulomb") or {} for c in campaigns]
        a = mean_sd([f["cohesion_pa"] * math.cos(math.radians(f["friction_angle_deg"])) for f in fits
                     if f.get("cohesion_pa") is not None and f.get("friction_angle_deg") is not None])[0]
        ax.plot(sigma, a / 1e3 + sigma * math.tan(math.radians(alpha)), color="k", lw=1.2, ls="--",
                label=f"slope of the tops (the paper's reading): α = {fmt_mean(st['alpha'], '.1f')}°")
    ax.plot([], [], color=PATTERN_COLOUR[p], lw=0.6, alpha=0.5, label="each seed's tangent envelope")
    ax.plot([], [], "o", color="0.4", ms=4, label="circle tops (p, t), through which α is fitted")
    for s3, col in colours.items():
        ax.plot([], [], color=col, lw=1.8, label=f"yield circle, σ₃ = {kpa(s3)}")
    # Circles stay circles (equal scales); the envelope is shown up to the
    # largest circle's top and a little above, the figure's height fitted to it.
    top = 1.25 * tau_max if tau_max else 1.0
    ax.set_xlim(0, sigma[-1])
    ax.set_ylim(0, top)
    ax.set_aspect("equal")
    fig.set_size_inches(9, min(9.0, 2.2 + 7.6 * top / sigma[-1]))
    ax.set_xlabel("normal stress σ [kPa]")
    ax.set_ylabel("shear stress τ [kPa]")
    ax.set_title(f"Mohr circles at yield, {PATTERN_LABEL[p]} ({len(campaigns)} seeds; seed {bold.seed} bold); "
                 f"R² = {fmt_mean(st['r2'], '.3f')}", fontsize=10)
    fig.legend(*ax.get_legend_handles_labels(), fontsize=8, loc="lower center", ncol=2, frameon=False)
    ax.grid(alpha=0.3)
    fig.tight_layout(rect=(0, 0.75 / fig.get_figheight(), 1, 1))
    save(fig, out, f"mohr_{p}.png", made)


def envelopes_figure(by_pattern, out, made):
    fig, ax = plt.subplots(figsize=(8, 5.5))
    sigma_max = max((t["yield"]["sigma1_pa"] for cs in by_pattern.values() for c in cs for t in c.tests()
                     if t.get("yield") and t["yield"].get("sigma1_pa") is not None), default=1e5) / 1e3
    sigma = np.linspace(0.0, 1.05 * sigma_max, 60)
    for p, cs in by_pattern.items():
        st = fit_stats(cs, "mohr_coulomb")
        if st["phi"][0] is None:
            continue
        fits = [c.summary.get("mohr_coulomb") or {} for c in cs]
        lines = [f["cohesion_pa"] / 1e3 + sigma * math.tan(math.radians(f["friction_angle_deg"]))
                 for f in fits if f.get("friction_angle_deg") is not None]
        if len(lines) > 1:  # the band the seeds' envelopes span
            ax.fill_between(sigma, np.min(lines, axis=0), np.max(lines, axis=0), color=PATTERN_COLOUR[p], alpha=0.15)
        ax.plot(sigma, st["c"][0] / 1e3 + sigma * math.tan(math.radians(st["phi"][0])), color=PATTERN_COLOUR[p],
                ls=PATTERN_STYLE[p], lw=2.2, label=f"{PATTERN_LABEL[p]}: φ = {fmt_mean(st['phi'], '.1f')}°, "
                            f"c = {fmt_mean(scaled(st['c'], 1e-3), '.2f')}"
                            f" kPa (n = {st['phi'][2]})")
    ax.set_xlim(0, sigma[-1])
    ax.set_ylim(0, None)
    ax.set_xlabel("normal stress σ [kPa]")
    ax.set_ylabel("shear stress τ [kPa]")
    ax.set_title("Mohr–Coulomb envelopes at yield: mean φ and c over seeds\n(band: the span of the seeds' envelopes)",
                 fontsize=10)
    ax.legend(fontsize=8, loc="upper left")
    ax.grid(alpha=0.3)
    fig.tight_layout()
    save(fig, out, "envelopes.png", made)


def per_pressure_stats(campaigns, value, keep=lambda test: True):
    """{σ₃ [Pa]: (mean, sd, n)} of value(test) over the campaigns' tests that keep(test)."""
    by_pressure = {}
    for c in campaigns:
        for t in c.tests():
            if keep(t):
                by_pressure.setdefault(t["confining_pressure_pa"], []).append(value(t))
    return {p: mean_sd(v) for p, v in sorted(by_pressure.items())}


# A column lengthened by more than this after its shortest, before loading,
# flowed in extension during the hold (docs/model.md, "Consolidation"). The
# study's tests fall on either side of it: at most 0.17 % (most below
# 0.07 %) in the columns that did not, 0.4-2.2 % in those that did.
EXTENSION_FLOW_STRAIN = 0.002


def flowed_in_extension(test):
    """True or False from the test's loading_start; None when its summary predates that key."""
    start = test.get("loading_start")
    if not start or start.get("rebound_axial_strain") is None:
        return None
    return start["rebound_axial_strain"] > EXTENSION_FLOW_STRAIN


def yield_ratio(test):
    """The test's stress ratio η at its yield reading (None if it has none)."""
    return (test.get("yield") or {}).get("stress_ratio")


def yield_shape(test):
    """peak, plateau or rising: the shape of the test's η curve at its yield reading."""
    return (test.get("yield") or {}).get("shape")


def residual_ratio(test):
    """The test's residual stress ratio: the mean raw η over the summary's end window."""
    return test.get("residual_stress_ratio")


def yield_ratio_stats(campaigns):
    """{σ₃ [Pa]: (mean, sd, n)} of the stress ratio η at yield over the campaigns' tests.

    η = (σ₁ − σ₃,eff)/(σ₁ + σ₃,eff) at the yield reading is sin φ mobilised, read
    from each test alone: unlike φ and c it needs no fit through circles that
    span a narrow band of σ, where slope and intercept trade off.
    """
    return per_pressure_stats(campaigns, yield_ratio)


def residual_ratio_stats(campaigns):
    """{σ₃ [Pa]: (mean, sd, n)} of the residual stress ratio (the mean η over the last end window)."""
    return per_pressure_stats(campaigns, residual_ratio)


def end_window_text(by_pattern):
    """The residual η's strain window as the summaries define it ("the last 2 % of axial strain")."""
    windows = {(c.summary.get("definitions") or {}).get("end_window_strain")
               for cs in by_pattern.values() for c in cs}
    windows.discard(None)
    if len(windows) != 1:
        return "the last end window of axial strain (summary `definitions.end_window_strain`)"
    return f"the last {100 * windows.pop():g} % of axial strain"


def stress_ratio_figure(by_pattern, out, made):
    """η at yield and the residual η against σ₃: each pattern's mean ± sd over seeds, and every test."""
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.6), sharey=True)
    marker = {"peak": "o", "plateau": "s", "rising": "^"}
    patterns = list(by_pattern)
    # (title, the value per test, the shape its marker shows)
    for ax, (title, value, shape_of) in zip(axes, (
            ("at yield (the maximum of the smoothed η)", yield_ratio, yield_shape),
            (f"residual (mean over {end_window_text(by_pattern)})", residual_ratio, lambda t: None))):
        for i, p in enumerate(patterns):
            shift = (i - (len(patterns) - 1) / 2) * 1.2  # kPa, so the bars do not hide each other
            stats = [(s3, st) for s3, st in per_pressure_stats(by_pattern[p], value).items() if st[0] is not None]
            if not stats:
                continue
            x = np.array([s3 / 1e3 + shift for s3, _ in stats])
            mean = np.array([st[0] for _, st in stats])
            sd = np.array([st[1] if st[1] is not None else 0.0 for _, st in stats])
            n = max(st[2] for _, st in stats)
            ax.errorbar(x, mean, yerr=sd, color=PATTERN_COLOUR[p], ls=PATTERN_STYLE[p], lw=1.8, capsize=4,
                        label=f"{PATTERN_LABEL[p]} (n = {n})")
            for c in by_pattern[p]:
                for t in c.tests():
                    v = value(t)
                    if v is None or not math.isfinite(v):
                        continue
                    ax.plot(t["confining_pressure_pa"] / 1e3 + shift + 0.5, v, marker=marker.get(shape_of(t), "."),
                            ms=4, color=PATTERN_COLOUR[p], mfc="none", ls="none", alpha=0.7)
        ax.set_title(title, fontsize=10)
        ax.set_xlabel("confining pressure σ₃ [kPa]")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("stress ratio η = (σ₁ − σ₃,eff)/(σ₁ + σ₃,eff) = sin φ_mob")
    fig.legend(*axes[0].get_legend_handles_labels(), fontsize=8, loc="lower center", ncol=len(patterns),
               frameon=False)
    # φ mobilised on the right-hand axis: η = sin φ.
    lo, hi = axes[1].get_ylim()
    right = axes[1].twinx()
    right.set_ylim(lo, hi)
    ticks = [d for d in range(0, 90, 2) if lo <= math.sin(math.radians(d)) <= hi]
    right.set_yticks([math.sin(math.radians(d)) for d in ticks], [f"{d}°" for d in ticks])
    right.set_ylabel("φ mobilised = asin η")
    fig.suptitle("Stress ratio per confining pressure: lines mean ± sd over seeds; markers every test "
                 "(left: ○ peak, □ plateau, △ still rising)", fontsize=10)
    fig.tight_layout(rect=(0, 0.45 / fig.get_figheight(), 1, 1))
    save(fig, out, "stress_ratio.png", made)


def verdict_cell(verdict):
    """difference_exceeds_scatter's verdict as a table cell."""
    return {True: "**yes**", False: "no", None: "not judged"}[verdict]


def ratio_table(ratios, pressures):
    """A per-pressure mean η per pattern ({pattern: {σ₃: (mean, sd, n)}}) as a table, n in brackets."""
    rows = [[PATTERN_LABEL[p]] + [fmt_mean(r.get(s3, (None, None, 0)), ".3f") + f" ({r.get(s3, (None, None, 0))[2]})"
                                  for s3 in pressures] for p, r in ratios.items()]
    return table(["pattern"] + [f"η at σ₃ = {s3 / 1e3:g} kPa" for s3 in pressures], rows)


def ratio_differences_table(ratios, pressures):
    """Every pair of patterns' difference of a per-pressure mean η ({pattern: {σ₃: (mean, sd, n)}}), judged."""
    rows = []
    patterns = list(ratios)
    for i, p1 in enumerate(patterns):
        for p2 in patterns[i + 1:]:
            for s3 in pressures:
                delta, bound, verdict = difference_exceeds_scatter(ratios[p1].get(s3, (None, None, 0)),
                                                                   ratios[p2].get(s3, (None, None, 0)))
                rows.append([f"{PATTERN_LABEL[p1]} − {PATTERN_LABEL[p2]}", f"{s3 / 1e3:g}", fmt(delta, "+.3f"),
                             fmt(bound, ".3f"), verdict_cell(verdict)])
    return table(["patterns", "σ₃ [kPa]", "Δ mean η", "2 √(s₁²/n₁ + s₂²/n₂)", "exceeds the scatter"], rows)


def strength_tables(by_pattern):
    text = ("φ and c: mean ± sample standard deviation over seeds (n). *yield*: the envelope through the "
            "states at the maximum of the smoothed stress ratio (summary `mohr_coulomb`); *max q*: through "
            "the states at the largest q (`mohr_coulomb_max_q`). α is the slope-of-the-tops angle "
            "(the paper's reading), R² that of the fit through the circle tops.\n\n")
    rows = []
    stats = {}
    for p, cs in by_pattern.items():
        for key, label in (("mohr_coulomb", "yield"), ("mohr_coulomb_max_q", "max q")):
            st = fit_stats(cs, key)
            stats[(p, label)] = st
            rows.append([PATTERN_LABEL[p], label, st["phi"][2], fmt_mean(st["phi"], ".2f"),
                         fmt_mean(scaled(st["c"], 1e-3), ".2f"),
                         fmt_mean(st["alpha"], ".2f"), fmt_mean(st["r2"], ".3f")])
    text += table(["pattern", "fit", "n", "φ [°]", "c [kPa]", "α [°]", "R²"], rows)
    text += ("\nDifferences between patterns. Criterion: a difference of means exceeds the scatter when "
             "|Δ| > 2 √(s₁²/n₁ + s₂²/n₂) (twice the standard error of the difference, Welch); "
             "not judged with fewer than 2 seeds on either side. With 2–3 seeds this is lenient "
             "(Student's t at 95 % is 4.3 for 2 degrees of freedom): a \"yes\" is a hint, not a proof.\n\n")
    rows = []
    patterns = list(by_pattern)
    for label in ("yield", "max q"):
        for i, p1 in enumerate(patterns):
            for p2 in patterns[i + 1:]:
                for q, unit, scale in (("phi", "°", 1.0), ("c", " kPa", 1e-3)):
                    delta, bound, verdict = difference_exceeds_scatter(scaled(stats[(p1, label)][q], scale),
                                                                       scaled(stats[(p2, label)][q], scale))
                    rows.append([label, f"{PATTERN_LABEL[p1]} − {PATTERN_LABEL[p2]}", "φ" if q == "phi" else "c",
                                 fmt(delta, "+.2f") + (unit if delta is not None else ""),
                                 fmt(bound, ".2f") + (unit if bound is not None else ""),
                                 verdict_cell(verdict)])
    text += table(["fit", "patterns", "quantity", "Δ mean", "2 √(s₁²/n₁ + s₂²/n₂)", "exceeds the scatter"], rows)

    # The same comparison without a fit: the stress ratio at yield, pressure by pressure.
    ratios = {p: yield_ratio_stats(cs) for p, cs in by_pattern.items()}
    pressures = sorted({s3 for r in ratios.values() for s3 in r})
    text += ("\nStress ratio at yield, η = (σ₁ − σ₃,eff)/(σ₁ + σ₃,eff) = sin φ mobilised, per confining "
             "pressure: mean ± sample standard deviation over seeds (n). Each test gives it alone, without "
             "the envelope's fit (whose φ and c trade off when the yield circles span a narrow band of σ).\n\n")

    def cell(stat):
        return fmt_mean(stat, ".3f") + (f" ({stat[2]})" if stat[2] else "")

    rows = [[PATTERN_LABEL[p]] + [cell(r.get(s3, (None, None, 0))) for s3 in pressures] for p, r in ratios.items()]
    text += table(["pattern"] + [f"η at σ₃ = {s3 / 1e3:g} kPa" for s3 in pressures], rows)
    text += "\nDifferences of η at yield between patterns, by the criterion above.\n\n"
    text += ratio_differences_table(ratios, pressures)
    residual = {p: residual_ratio_stats(cs) for p, cs in by_pattern.items()}
    text += (f"\nResidual stress ratio (the mean raw η over {end_window_text(by_pattern)}, summary "
             "`residual_stress_ratio`) per confining pressure: mean ± sample standard deviation over seeds (n).\n\n")
    rows = [[PATTERN_LABEL[p]] + [cell(r.get(s3, (None, None, 0))) for s3 in pressures] for p, r in residual.items()]
    text += table(["pattern"] + [f"residual η at σ₃ = {s3 / 1e3:g} kPa" for s3 in pressures], rows)
    return text


def loading_start_tables(by_pattern):
    """Every test's state at the start of loading, and η at yield without the tests that flowed in extension."""
    rows = []
    for p, cs in by_pattern.items():
        for c in cs:
            for t in c.tests():
                s3 = t["confining_pressure_pa"]
                start = t.get("loading_start") or {}
                flowed = flowed_in_extension(t)
                rows.append([c.name, f"{s3 / 1e3:g}", fmt(t.get("hold_time_s"), ".3f"),
                             fmt(ratio_to(t.get("consolidated_sigma1_pa"), s3), ".2f"),
                             fmt(ratio_to(start.get("sigma3_effective_pa"), s3), ".2f"),
                             fmt(start.get("stress_ratio"), "+.3f"),
                             fmt(percent(start.get("axial_strain")), "+.2f"),
                             fmt(percent(start.get("rebound_axial_strain")), ".2f"),
                             {True: "**yes**", False: "no", None: "not recorded"}[flowed],
                             fmt(yield_ratio(t), ".3f")])
    text = ("The column as loading started (summary `tests[].loading_start`; docs/model.md, \"Consolidation\"): "
            "the hold's length, σ₁ over the last 5 ms against σ₃ (what the piston consolidates to), σ₃,eff "
            "against σ₃ and their stress ratio η, the axial strain of the ramp and hold (> 0 shortened) and how "
            "much the column lengthened after its shortest. A column lengthened by more than "
            f"{EXTENSION_FLOW_STRAIN * 100:g} % *flowed in extension*: the membrane squeezed it harder than the "
            "piston pressed it. *not recorded*: the summary predates `loading_start` and its run folder was not "
            "kept (`wiredem analyse DIR` rewrites a summary from a run folder).\n\n")
    text += table(["campaign", "σ₃ [kPa]", "hold [s]", "σ₁/σ₃", "σ₃,eff/σ₃", "η at start", "ε_a of ramp and hold [%]",
                   "lengthened after shortest [%]", "flowed in extension", "yield η"], rows)

    def clean(test):
        return flowed_in_extension(test) is not True

    ratios = {p: per_pressure_stats(cs, yield_ratio, clean) for p, cs in by_pattern.items()}
    pressures = sorted({s3 for r in ratios.values() for s3 in r})
    text += ("\nη at yield without the tests that flowed in extension (tests not recorded are kept): mean ± "
             "sample standard deviation over seeds (n), and the pairwise criterion of the strength section.\n\n")
    text += ratio_table(ratios, pressures)
    text += "\n" + ratio_differences_table(ratios, pressures)
    return text


# The runner's warning for a test whose hold ran out before the column had
# consolidated (engine/triaxial/triaxial.cpp; campaign "test k/N at sigma3 = P Pa: ...").
NOT_CONSOLIDATED = re.compile(r"^test \d+/\d+ at sigma3 = ([0-9.eE+-]+) Pa: .*had not consolidated")


def unconsolidated_pressures(summary):
    """The σ₃ [Pa] of the tests that had not consolidated when loading started: their
    `consolidated` verdict, or, in a summary written before tests recorded it, the campaign's
    warning."""
    tests = summary.get("tests") or []
    if any(isinstance(t.get("consolidated"), bool) for t in tests):
        return {float(t["confining_pressure_pa"]) for t in tests if t.get("consolidated") is False}
    found = set()
    for w in summary.get("warnings") or []:
        m = NOT_CONSOLIDATED.match(w)
        if m:
            found.add(float(m.group(1)))
    return found


def consolidation_of(c, test):
    """How the test was consolidated: its summary's `consolidation`, else the campaign job's
    triaxial.consolidation; a job.json wiredem wrote before the field existed ran with
    cell_pressure (as api::parse_written_job_spec reads it). None when neither is at hand."""
    if test.get("consolidation"):
        return test["consolidation"]
    if c.job is None:
        return None
    return (c.job.get("triaxial") or {}).get("consolidation", "cell_pressure")


class Retested:
    """A campaign with some of its tests replaced by a retest's tests at the same σ₃ (the retest may
    test only some of the campaign's pressures)."""

    def __init__(self, original, retest):
        self.pattern, self.seed, self.name = original.pattern, original.seed, original.name
        again = {t["confining_pressure_pa"]: t for t in retest.tests()}
        self._tests = [again.get(t["confining_pressure_pa"], t) for t in original.tests()]

    def tests(self):
        return self._tests


def with_retests(by_pattern, retests):
    """by_pattern with each retest's tests in place of the same campaign's tests at the same σ₃."""
    merged = {}
    for p, cs in by_pattern.items():
        again = {c.seed: c for c in retests.get(p, [])}
        merged[p] = [Retested(c, again[c.seed]) if c.seed in again else c for c in cs]
    return merged


def retest_tables(by_pattern, retests):
    """Each retest test beside its original, and η at yield per pattern with the retests in their place."""
    originals = {(c.pattern, c.seed): c for cs in by_pattern.values() for c in cs}
    rows, orphans = [], []
    for p, cs in retests.items():
        for r in cs:
            o = originals.get((p, r.seed))
            if o is None:
                orphans.append(r.name)
                continue
            by_s3 = {t["confining_pressure_pa"]: t for t in o.tests()}
            for t in r.tests():
                s3 = t["confining_pressure_pa"]
                for c, test in ((o, by_s3.get(s3)), (r, t)):
                    if test is None:
                        continue
                    start = test.get("loading_start") or {}
                    y = test.get("yield") or {}
                    rows.append([c.name if c is o else "↳ retest", f"{s3 / 1e3:g}",
                                 (consolidation_of(c, test) or "—").replace("_", " "),
                                 fmt(test.get("hold_time_s"), ".3f"),
                                 "**yes**" if s3 in unconsolidated_pressures(c.summary) else "no",
                                 fmt(start.get("stress_ratio"), "+.3f"),
                                 fmt(percent(start.get("rebound_axial_strain")), ".2f"),
                                 fmt(y.get("stress_ratio"), ".3f") + (f" ({y['shape']})" if y.get("shape") else ""),
                                 fmt(percent(y.get("axial_strain")), ".1f"),
                                 fmt(residual_ratio(test), ".3f"),
                                 fmt(test.get("max_inertial_number"), ".2g"),
                                 "yes" if test.get("quasi_static") else "**no**"])
    text = ("Campaigns tested again from their own specimens with other test settings (the retest's job "
            "differs from the campaign's in `triaxial` only: `wiredem run --specimen-from`), each test beside "
            "the study's: the consolidation (docs/model.md, \"Consolidation\"), the hold, whether the campaign "
            "warned that the test had not consolidated when loading started, η at the start of loading, how "
            "much the column lengthened after its shortest, η at yield (its shape), the axial strain there, "
            "the residual η, the largest inertial number and the quasi-static verdict.\n\n")
    text += table(["campaign", "σ₃ [kPa]", "consolidation", "hold [s]", "warned: not consolidated", "η at start",
                   "lengthened after shortest [%]", "yield η", "at ε_a [%]", "residual η", "max I", "quasi-static"],
                  rows)
    if orphans:
        text += "\nRetests without a study campaign of their name (not compared): " + ", ".join(orphans) + ".\n"
    merged = with_retests(by_pattern, retests)
    ratios = {p: yield_ratio_stats(cs) for p, cs in merged.items()}
    pressures = sorted({s3 for r in ratios.values() for s3 in r})
    replaced = sorted(r.name for cs in retests.values() for r in cs if r.name not in orphans)
    text += (f"\nη at yield with the retested tests ({', '.join(replaced) or 'none'}) in place of the study's at the "
             "same σ₃: mean ± sample standard deviation over seeds (n), and the pairwise criterion of the strength "
             "section.\n\n")
    text += ratio_table(ratios, pressures)
    text += "\n" + ratio_differences_table(ratios, pressures)
    return text


def tests_table(by_pattern):
    rows = []
    for p, cs in by_pattern.items():
        for c in cs:
            for t in c.tests():
                y = t.get("yield") or {}
                rows.append([c.name, f"{t['confining_pressure_pa'] / 1e3:g}",
                             fmt(t.get("plate_speed_m_per_s") and t["plate_speed_m_per_s"] * 1e3, ".3g"),
                             fmt(y.get("stress_ratio"), ".3f"),
                             fmt(y.get("axial_strain") and y["axial_strain"] * 100, ".2f"),
                             y.get("shape", "—"),
                             fmt(y.get("deviatoric_stress_pa") and y["deviatoric_stress_pa"] / 1e3, ".1f"),
                             fmt(y.get("sigma3_effective_pa") and y["sigma3_effective_pa"] / 1e3, ".1f"),
                             fmt(t.get("peak_deviatoric_stress_pa") and t["peak_deviatoric_stress_pa"] / 1e3, ".1f"),
                             fmt(t.get("peak_axial_strain") and t["peak_axial_strain"] * 100, ".2f"),
                             t.get("max_q_shape") or "—",
                             fmt(t.get("residual_stress_ratio"), ".3f"),
                             "yes" if t.get("quasi_static") else "**no**",
                             fmt(t.get("max_inertial_number"), ".2g"), fmt(t.get("mean_kinetic_to_elastic"), ".2g")])
    return ("Every test. Yield: the maximum of the smoothed stress ratio η, its shape (peak, plateau, or "
            "rising: still rising at the end, a lower bound); max q: the largest raw q and the shape of the "
            "smoothed q curve; residual η: mean over the last 2 % of strain (summary `definitions`).\n\n"
            + table(["campaign", "σ₃ [kPa]", "plate [mm/s]", "yield η", "at ε_a [%]", "yield shape", "q at yield [kPa]",
                     "σ₃,eff at yield [kPa]", "max q [kPa]", "at ε_a [%]", "max-q shape", "residual η",
                     "quasi-static", "max I", "mean KE/E"], rows))


# ---------------------------------------------------------------------------
# 6. Wire strain

def wire_snapshot(c):
    """(σ₃, axial strain, segment strains, the snapshot) of the highest-pressure test's last snapshot, or None."""
    tests = c.result.tests
    if not tests or not tests[-1].snapshots:
        return None
    last = tests[-1].snapshots[-1]
    strain = last.wire_segment_strain
    if strain.shape[0] < 2:
        return None
    return tests[-1].confining_pressure_pa, last.axial_strain, strain, last


def is_lag(v):
    """Whether a summary_lags value is a lag (not None, not "absent")."""
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def lag_cell(lag_m):
    """A summary lag in mm for a table: '—' for no such maximum, 'absent' kept."""
    return lag_m if lag_m == "absent" else fmt(lag_m and lag_m * 1e3, ".2f")


def wire_figure_and_rows(p, campaigns, out, made, wiredem=None):
    bold = lead(campaigns)
    rows, done = [], []
    for c in campaigns:
        if not c.h5:
            continue
        snap = wire_snapshot(c)
        if snap is None:
            continue
        s3, ea, strain, last = snap
        seg = c.job["specimen"]["wire"]["segment_length_m"]
        r = autocorrelation(last, wiredem)
        lags = summary_lags(c.summary)
        loops = loop_lengths_m(c.job["specimen"]["wire"])
        done.append((c, s3, ea, strain, seg, r, lags, loops))
        rows.append([c.name, f"{s3 / 1e3:g}", f"{ea * 100:.2f}", len(strain), f"{len(strain) * seg:.3g}",
                     f"{np.mean(strain) * 100:.3f}", f"{np.max(strain) * 100:.3f}"]
                    + [lag_cell(lags[key]) for key, _ in LAG_KEYS]
                    + [", ".join(f"{name} {v * 1e3:.1f}" for name, v in loops)])
    if not done:
        return rows
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(11, 7.5))
    head = next((d for d in done if d[0] is bold), done[0])
    c, s3, ea, strain, seg, r, lags, loops = head
    plots.draw_wire_strain(ax1, strain, seg, PATTERN_COLOUR[p])
    i = int(np.argmax(strain))
    ax1.set_title(f"segment strain, {PATTERN_LABEL[p]}, seed {c.seed}: σ₃ = {kpa(s3)}, ε_a = {ea * 100:.1f} %; "
                  f"mean {np.mean(strain) * 100:.3f} % (dashed), max {strain[i] * 100:.3f} % (▼)", fontsize=10)
    found = [v for d in done for v in d[6].values() if is_lag(v)]
    longest = max([v for _, v in loops] + found + [0.0])
    shown = min(len(strain) * seg / 2, max(5 * longest, 20 * seg))
    # The first maximum as a circle, the first prominent one as a star; the
    # lead campaign's labelled (the others' markers are smaller).
    marker = {"autocorrelation_lag_m": ("o", 6), "autocorrelation_prominent_lag_m": ("*", 10)}
    for d in done:
        dc, _, _, _, dseg, dr, dlags, _ = d
        if dr is None:
            continue
        x = np.arange(len(dr)) * dseg
        keep = x <= shown
        ax2.plot(x[keep], dr[keep], color=PATTERN_COLOUR[p], lw=1.8 if dc is c else 0.7,
                 alpha=1.0 if dc is c else 0.5, label=f"seed {dc.seed}")
        for j, (key, what) in enumerate(LAG_KEYS):
            lag = dlags[key]
            if not is_lag(lag):
                continue
            k = min(int(round(lag / dseg)), len(dr) - 1)
            shape, size = marker[key]
            ax2.plot(lag, dr[k], shape, color="k", ms=size if dc is c else 0.7 * size, zorder=5,
                     label=f"{what} (summary.json)" if dc is c else None)
            if dc is c:
                ax2.annotate(f"{what} {lag * 1e3:.1f} mm", (lag, dr[k]), textcoords="offset points",
                             xytext=(8, 8 + 12 * j), fontsize=8)
    styles = [":", "-.", (0, (5, 2))]
    for j, (name, v) in enumerate(loops):
        ax2.axvline(v, color="0.3", ls=styles[j % len(styles)], lw=1.1, label=f"{name} = {v * 1e3:.1f} mm")
    ax2.axhline(0.0, color="0.7", lw=0.8)
    ax2.set_xlim(0, shown)
    ax2.set_xlabel("lag along the wire [m]")
    ax2.set_ylabel("autocorrelation R(lag)")
    ax2.set_title("autocorrelation of the segment strain; maxima from summary.json (engine/analysis/autocorrelation.hpp)",
                  fontsize=10)
    ax2.legend(fontsize=8, loc="best")
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    save(fig, out, f"wire_strain_{p}.png", made)
    return rows


# ---------------------------------------------------------------------------
# 7. Force network

def force_network_figure(campaigns, out, made):
    """The unreinforced column's contacts near yield at the highest pressure, or a reason why not."""
    c = lead(campaigns)
    if c is None:
        return "no result.h5 of the unreinforced column"
    tests = c.tests()
    if not tests:
        return f"{c.name}: no tests"
    y = tests[-1].get("yield") or {}
    target = y.get("axial_strain")
    if target is None:
        target = tests[-1].get("peak_axial_strain")
    g = c.result.tests[-1]
    if not g.snapshots or target is None:
        return f"{c.name}: no snapshot or no yield strain"
    snap = g.snapshot_near(target)
    ea = snap.axial_strain
    positions = snap.body_positions_m()
    radii = snap.array("grain_radius_m")
    bodies = snap.array("contact_bodies")
    fn = snap.array("contact_normal_force_n")
    wall_bodies = snap.array("wall_contact_bodies")
    wall_force = snap.array("wall_contact_force_n")
    s3 = g.confining_pressure_pa
    # The column's height at the snapshot, from the nearest row of the time series.
    series = g.series
    row = int(np.argmin(np.abs(series["time_s"].to_numpy() - snap.time_s)))
    height = float(series["height_m"].iloc[row])
    r_mean = float(np.mean(radii))
    a = np.array([positions[k][i] for k, i in bodies[:, :2]]) if len(bodies) else np.zeros((0, 3))
    b = np.array([positions[k][i] for k, i in bodies[:, 2:]]) if len(bodies) else np.zeros((0, 3))
    # Plate contacts: from the body's centre one radius towards the plate (the
    # force on the body points away from it); |F| stands for the normal force.
    wf = np.linalg.norm(wall_force, axis=1) if len(wall_force) else np.zeros(0)
    wa = np.array([positions[k][i] for k, i in wall_bodies[:, 1:]]) if len(wall_bodies) else np.zeros((0, 3))
    wb = wa - r_mean * wall_force / np.maximum(wf, 1e-300)[:, None] if len(wa) else wa
    all_a, all_b = np.vstack([a, wa]), np.vstack([b, wb])
    force = np.concatenate([fn, wf])
    mean_force = float(np.mean(force)) if force.size else 0.0
    # The slab: contacts whose midpoint lies within one mean grain radius of the
    # plane y = 0 (a slab one grain diameter thick through the axis).
    mid_y = 0.5 * (all_a[:, 1] + all_b[:, 1])
    slab = np.abs(mid_y) <= r_mean
    radius = c.job["specimen"]["membrane_radius_m"] * 1e3
    fig, ax = plt.subplots(figsize=(7, min(13.0, max(5.5, 2.4 + 5.2 * height * 1e3 / (2.6 * radius)))))
    gp = positions[0]
    in_slab = np.abs(gp[:, 1]) <= r_mean
    for (x, yy, z), r in zip(gp[in_slab], radii[in_slab]):
        # the grain's section by the plane y = 0
        ax.add_patch(plt.Circle((x * 1e3, z * 1e3), math.sqrt(max(r * r - yy * yy, 0.0)) * 1e3,
                                facecolor="0.93", edgecolor="0.75", lw=0.4))
    f_max = float(np.max(force[slab])) if np.any(slab) else 1.0
    segs = np.stack([all_a[:, [0, 2]], all_b[:, [0, 2]]], axis=1) * 1e3
    strong = slab & (force > mean_force)
    weak = slab & ~strong
    width = 6.0 * force / f_max  # line width [pt] ∝ normal force
    ax.add_collection(LineCollection(segs[weak], linewidths=width[weak], colors="#6a8fbf", alpha=0.8))
    ax.add_collection(LineCollection(segs[strong], linewidths=width[strong], colors="#b2182b"))
    # The membrane where it crosses the slab (its nodes within the slab).
    mp = positions[2]
    near = np.abs(mp[:, 1]) <= r_mean
    ax.plot(mp[near, 0] * 1e3, mp[near, 2] * 1e3, ".", color="0.45", ms=2, label="membrane nodes in the slab")
    ax.axhline(0.0, color="k", lw=2)
    ax.axhline(height * 1e3, color="k", lw=2)
    ax.set_xlim(-radius * 1.3, radius * 1.3)
    ax.set_ylim(-1, height * 1e3 + 1)
    ax.set_aspect("equal")
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("z [mm]")
    ax.set_title(f"Force network, no wire, seed {c.seed}: σ₃ = {kpa(s3)}, ε_a = {ea * 100:.2f} %\n"
                 f"(yield at {target * 100:.2f} %); contacts with midpoint |y| ≤ {r_mean * 1e3:.2f} mm", fontsize=10)
    fig.legend(handles=[Line2D([], [], color="#b2182b", lw=3,
                               label=f"strong: F_n above the mean {mean_force:.3g} N "
                                     f"({int(np.sum(strong))} in the slab)"),
                        Line2D([], [], color="#6a8fbf", lw=1, label=f"weak: below it ({int(np.sum(weak))})"),
                        Line2D([], [], color="k", lw=6.0, label=f"line width ∝ F_n: 6 pt = {f_max:.3g} N"),
                        Line2D([], [], color="0.45", marker=".", ls="none", label="membrane nodes in the slab")],
               fontsize=8, loc="lower center", ncol=2, frameon=False)
    fig.tight_layout(rect=(0, 0.6 / fig.get_figheight(), 1, 1))
    save(fig, out, "force_network_none.png", made)
    return None


# ---------------------------------------------------------------------------
# 8. Runtime

def runtime_table(by_pattern):
    rows, total = [], 0.0
    for p, cs in by_pattern.items():
        for c in cs:
            e = c.summary.get("engine", {})
            tests_wall = sum(t.get("wall_time_s") or 0.0 for t in c.tests())
            total += e.get("wall_time_s") or 0.0
            rows.append([c.name, fmt(e.get("wall_time_s") and e["wall_time_s"] / 60, ".1f"),
                         fmt(tests_wall / 60, ".1f"), fmt(e.get("steps"), ",d") if e.get("steps") is not None else "—",
                         fmt(e.get("body_steps_per_second") and e["body_steps_per_second"] / 1e6, ".2f"),
                         e.get("threads", "—"), fmt(e.get("time_step_s"), ".3g"), fmt(e.get("density_scale"), "g")])
    return ("Summary `engine`: the campaign's wall time (preparation, tests, analysis, writing), the tests' "
            "own, all steps, body-steps per second of stepping wall time, threads, the tests' time step and the "
            f"mass scaling. Total {total / 3600:.2f} h of wall time.\n\n"
            + table(["campaign", "wall time [min]", "tests [min]", "steps", "body-steps/s [10⁶]", "threads",
                     "δt [s]", "density scale"], rows))


# ---------------------------------------------------------------------------

def default_wiredem():
    """$WIREDEM_BIN, else wiredem on the PATH, else this tree's Release build (None when none is there)."""
    built = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "build", "release", "bin",
                         "wiredem")
    return os.environ.get("WIREDEM_BIN") or shutil.which("wiredem") or (built if os.path.isfile(built) else None)


def main(argv=None):
    ap = argparse.ArgumentParser(description="Figures and tables of the study (docs/study.md).")
    ap.add_argument("runs", help="folder of the campaigns <pattern>-seed<k>/ (scripts/study.sh --runs)")
    ap.add_argument("--out", default="docs/study", help="output folder (default docs/study)")
    ap.add_argument("--retests", help="folder of campaigns tested again from the specimens of RUNS' campaigns "
                                      "of the same names (scripts/study.sh --specimens-from)")
    ap.add_argument("--wiredem", default=default_wiredem(),
                    help="the wiredem binary, whose `wiredem autocorrelation` gives the wire's R(lag) "
                         "(default: $WIREDEM_BIN, else wiredem on the PATH, else build/release/bin/wiredem)")
    args = ap.parse_args(argv)
    for folder in (args.runs, args.retests):
        if folder is not None and not os.path.isdir(folder):
            print(f"study_report: {folder} is not a folder", file=sys.stderr)
            return 2
    by_pattern, notes = find_campaigns(args.runs)
    if not by_pattern:
        print(f"study_report: no campaign with a summary.json in {args.runs}", file=sys.stderr)
        for n in notes:
            print("  " + n, file=sys.stderr)
        return 1
    if args.retests is not None:
        retests, retest_notes = find_campaigns(args.retests, report_missing=False)
        notes += [f"retests: {n}" for n in retest_notes]
    figures = os.path.join(args.out, "figures")
    os.makedirs(figures, exist_ok=True)
    made = []
    colours = pressure_colours(by_pattern)

    md = ["# Study tables\n",
          f"Made by `/usr/bin/python3 scripts/study_report.py {args.runs} --out {args.out}"
          + (f" --retests {args.retests}" if args.retests is not None else "") + "` from "
          f"{sum(len(cs) for cs in by_pattern.values())} campaigns: "
          + "; ".join(f"{PATTERN_LABEL[p]} seeds {', '.join(str(c.seed) for c in cs)}" for p, cs in by_pattern.items())
          + ".\n"]
    if notes:
        md.append("Skipped or missing:\n\n" + "".join(f"- {n}\n" for n in notes))
    md.append("\n## Specimen\n\n" + specimen_tables(by_pattern))
    md.append("\n## Strength\n\n" + strength_tables(by_pattern))
    md.append("\n## The state at the start of loading\n\n" + loading_start_tables(by_pattern))
    if args.retests is not None:
        md.append("\n## Retests\n\n" + retest_tables(by_pattern, retests))
    md.append("\n## Tests\n\n" + tests_table(by_pattern))

    for p, cs in by_pattern.items():
        c = lead(cs)
        if c:
            specimen_picture(p, c, figures, made)
            curves_figure(p, cs, colours, figures, made)
        mohr_figure(p, cs, colours, figures, made)
    envelopes_figure(by_pattern, figures, made)
    stress_ratio_figure(by_pattern, figures, made)

    wire_rows = []
    for p, cs in by_pattern.items():
        if p != "none":
            wire_rows += wire_figure_and_rows(p, cs, figures, made, args.wiredem)
    md.append("\n## Wire strain\n\nThe segment strains of the highest-pressure test at its last snapshot "
              "(the largest strain), the snapshot summary.json's lags are read from "
              "(engine/analysis/autocorrelation.hpp, docs/model.md \"Wire autocorrelation\"): the first "
              "local maximum of their autocorrelation after lag 0 (`wire.autocorrelation_lag_m`) and the "
              "first maximum whose prominence exceeds the white-noise band 1.96/√(N − k) "
              "(`wire.autocorrelation_prominent_lag_m`); — when there is none, *absent* when the summary "
              "was written before that key existed (run `wiredem analyse` again). Loop lengths from the "
              "job's `specimen.wire` and engine/specimen/pattern.cpp.\n\n")
    md.append(table(["campaign", "σ₃ [kPa]", "ε_a [%]", "segments", "wire [m]", "mean strain [%]",
                     "max strain [%]", "first maximum [mm]", "first prominent maximum [mm]", "loops [mm]"], wire_rows)
              if wire_rows else "No wire snapshot found.\n")

    if "none" in by_pattern:
        why_not = force_network_figure(by_pattern["none"], figures, made)
        if why_not:
            notes.append(f"force network: {why_not}")
    md.append("\n## Runtime\n\n" + runtime_table(by_pattern))

    tables_path = os.path.join(args.out, "tables.md")
    with open(tables_path, "w") as f:
        f.write("".join(md))
    made.append(tables_path)
    print(f"study_report: {sum(len(cs) for cs in by_pattern.values())} campaigns read from {args.runs}")
    for n in notes:
        print(f"  {n}")
    for path in made:
        print(f"made {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
