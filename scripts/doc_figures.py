#!/usr/bin/env python3
"""The docs' figures of the main job, made from its summary.json, not copied.

A doc marks each sentence made here between two comments,

    <!-- doc-figures:NAME -->...<!-- /doc-figures -->

(NAME: one of BLOCKS below) and this script writes the text between them
from a summary.json of examples/main.json:

    python3 scripts/doc_figures.py --summary S.json FILE...          rewrite
    python3 scripts/doc_figures.py --summary S.json --check FILE...  exit 1 if a block differs

`bash scripts/doc_figures.sh` runs the main job and rewrites the docs and
docs/figures/main-summary.json, the summary they were made from;
tests/scripts/test_doc_figures.py checks that the docs agree with it (and,
labelled physics_long, `bash scripts/doc_figures.sh --check` that a fresh run
still gives them). Python 3 standard library only.
"""
import argparse
import json
import re
import sys

MARK = re.compile(r"<!-- doc-figures:([a-z0-9-]+) -->(.*?)<!-- /doc-figures -->", re.S)

# What each caveat code of a Mohr-Coulomb fit (summary.json mohr_coulomb.caveats,
# engine/analysis/mohr_coulomb.hpp) means, in a few words for a sentence of the docs.
CAVEAT_WORDS = {
    "single_pressure": "one pressure, so c = 0 was imposed",
    "two_pressures": "two pressures, so the line is exact by construction",
    "narrow_band": "a narrow band of circles, so c is a long extrapolation",
    "negative_cohesion": "a negative c, a tensile strength a gravel column does not have (read it as c ≈ 0)",
    "negative_friction_angle": "a negative φ: the circle tops fall as the pressure rises",
}


def number(x, digits):
    """x with `digits` decimals, a real minus sign; '—' when missing."""
    if x is None:
        return "—"
    text = f"{x:.{digits}f}"
    if float(text) == 0:
        text = f"{0:.{digits}f}"  # no "-0.0"
    return text.replace("-", "−")


def kpa(pa, digits=1):
    return number(None if pa is None else pa / 1000, digits)


def fit_sentence(mc):
    """φ, c and R² of a fit, what is wrong with it, and its constrained fits."""
    if mc.get("error"):
        return f"no Mohr–Coulomb fit ({mc['error']})"
    r2 = mc.get("r_squared")
    text = (f"φ = {number(mc['friction_angle_deg'], 1)}°, c = {kpa(mc['cohesion_pa'])} kPa"
            + (f" (R² = {number(r2, 2)})" if r2 is not None else " (no R²)"))
    caveats = [c["code"] for c in mc.get("caveats", [])]
    if caveats:
        nn, c0 = mc["nonnegative"], mc["cohesionless"]
        text += ", an unconstrained line with " + "; and ".join(CAVEAT_WORDS.get(c, c) for c in caveats)
        if nn["cohesion_pa"] == 0 and nn["friction_angle_deg"] == c0["friction_angle_deg"]:
            text += f"; the best fit with c ≥ 0 and φ ≥ 0 is the one with c = 0, φ = {number(c0['friction_angle_deg'], 1)}°"
        else:
            text += (f"; the best fit with c ≥ 0 and φ ≥ 0 gives φ = {number(nn['friction_angle_deg'], 1)}°, "
                     f"c = {kpa(nn['cohesion_pa'])} kPa, the one with c = 0 φ = {number(c0['friction_angle_deg'], 1)}°")
    return text


def shapes_sentence(summary):
    """What kind of maximum each test's yield is (a rising one is a lower bound)."""
    tests = summary.get("tests", [])
    shapes = [(t.get("yield") or {}).get("shape") or "unread" for t in tests]
    pressures = " / ".join(number(t["confining_pressure_pa"] / 1000, 0) for t in tests)
    if shapes and all(s == "rising" for s in shapes):
        return (f"the stress ratio of every test ({pressures} kPa) is still **rising** at its end: the column is "
                "still hardening, so these are lower bounds")
    rising = sum(s == "rising" for s in shapes)
    return (f"the yield at {pressures} kPa is " + " / ".join(f"**{s}**" for s in shapes)
            + (f" ({rising} still rising at its end: lower bounds)" if rising else ""))


BLOCKS = {
    # The yield fit of the main job, with its caveats and constrained fits.
    "main-fit": lambda s: fit_sentence(s["mohr_coulomb"]),
    # The fit through the maxima of q, beside it.
    "main-fit-max-q": lambda s: fit_sentence(s["mohr_coulomb_max_q"]),
    # The kind of maximum of each test's yield.
    "main-shapes": shapes_sentence,
}


def render(text, summary):
    """`text` with every marked block made again from `summary`."""
    def block(m):
        name = m.group(1)
        if name not in BLOCKS:
            raise SystemExit(f"doc_figures: unknown block doc-figures:{name} (known: {', '.join(sorted(BLOCKS))})")
        return f"<!-- doc-figures:{name} -->{BLOCKS[name](summary)}<!-- /doc-figures -->"
    return MARK.sub(block, text)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--summary", required=True, help="summary.json of examples/main.json")
    ap.add_argument("--check", action="store_true", help="change nothing; exit 1 when a block differs")
    ap.add_argument("files", nargs="+")
    args = ap.parse_args(argv)
    with open(args.summary, encoding="utf-8") as f:
        summary = json.load(f)
    stale = []
    for path in args.files:
        with open(path, encoding="utf-8") as f:
            old = f.read()
        if not MARK.search(old):
            raise SystemExit(f"doc_figures: {path} has no doc-figures block")
        new = render(old, summary)
        if new == old:
            continue
        if args.check:
            for (name, before), (_, after) in zip(MARK.findall(old), MARK.findall(new)):
                if before != after:
                    stale.append(f"{path}: doc-figures:{name}\n  says:     {before}\n  run says: {after}")
        else:
            with open(path, "w", encoding="utf-8") as f:
                f.write(new)
            print(f"doc_figures: rewrote {path}")
    if stale:
        print("doc_figures: figures that do not match the summary (bash scripts/doc_figures.sh remakes them):\n"
              + "\n".join(stale), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
