#!/usr/bin/env python3
"""Writes the toolpath examples (issue 39, section 3) from examples/tiny.json:

examples/toolpath-loops.json  a layered pattern of loops, as the printed
    columns were made: each layer three loops of radius 2.5 mm centred 3.2 mm
    from the axis, 120 degrees apart, walked one after the other through the
    middle; the next layer turned by 60 degrees, so that its loops lie over
    the gaps of the layer below.
examples/toolpath-helix.json  the built-in helix of examples/tiny-wired
    (R_a = 4 mm) given as a toolpath: its inscribed regular 720-gon, not
    turned. The nozzle then follows the helix within its sagitta 3.8e-8 m plus
    8.0e-8 m per turn (the polygon's shorter perimeter; the bound of
    tests/engine/test_pattern.cpp, Toolpath.APolygonReproducesTheHelix...).

Run from the repository's root: python3 scripts/make_toolpath_examples.py
"""
import json
import math
import re
import pathlib

root = pathlib.Path(__file__).resolve().parent.parent
tiny = json.loads((root / "examples" / "tiny.json").read_text())


def job(name, comment, wire):
    j = json.loads(json.dumps(tiny))
    j["name"] = name
    j["comment"] = comment
    j["specimen"]["wire"] = wire
    # The wire is laid at omega R_a = 1.2 m/s while the fill rises at 0.05 m/s.
    j["specimen"]["pouring"]["fill_rate_m_per_s"] = 0.05
    return j


def write(name, j):
    path = root / "examples" / name
    text = json.dumps(j, indent=2, ensure_ascii=False)
    # The point lists on one line each.
    text = re.sub(r"\[\s*(-?[0-9][^\]]*?)\s*\]", lambda m: "[" + re.sub(r"\s+", " ", m.group(1)) + "]", text)
    path.write_text(text + "\n")
    print("wrote", path.relative_to(root))


def loops_layer(loops=3, centre_m=3.2e-3, radius_m=2.5e-3, points_per_loop=24):
    xs, ys = [], []
    for j in range(loops):
        a = 2 * math.pi * j / loops
        cx, cy = centre_m * math.cos(a), centre_m * math.sin(a)
        # Start at the loop's point nearest the axis and go once round it.
        for k in range(points_per_loop + 1):
            t = a + math.pi + 2 * math.pi * k / points_per_loop
            xs.append(round(cx + radius_m * math.cos(t), 9))
            ys.append(round(cy + radius_m * math.sin(t), 9))
    return xs, ys


x, y = loops_layer()
write("toolpath-loops.json", job(
    "tiny, toolpath: three loops per layer",
    "A layered pattern of loops, as the printed columns were made (scripts/make_toolpath_examples.py): "
    "tiny.json's column (150 grains, R = 8 mm) with the wire laid along the robot's own path, each layer "
    "three loops of radius 2.5 mm centred 3.2 mm from the axis (reach 5.7 mm: within R - r_m - r_w - clearance = "
    "6 mm, the preparation's rule), the next layer turned by 60 degrees. Path speed omega R_a = 1.2 m/s, fill 0.05 m/s: "
    "a layer (about 50 mm of path) every 2 mm of fill.",
    {"pattern": "toolpath", "helix_radius_m": 0.004, "toolpath_x_m": x, "toolpath_y_m": y,
     "toolpath_rotation_per_layer_rad": math.pi / 3}))

n = 720
x = [round(4e-3 * math.cos(2 * math.pi * k / n), 12) for k in range(n)]
y = [round(4e-3 * math.sin(2 * math.pi * k / n), 12) for k in range(n)]
write("toolpath-helix.json", job(
    "tiny, toolpath: the built-in helix",
    "The built-in helix (R_a = 4 mm) given as a toolpath, its inscribed regular 720-gon "
    "(scripts/make_toolpath_examples.py); compare with the same job with \"pattern\": \"helix\" "
    "(docs/model.md, \"The robot's own toolpath\").",
    {"pattern": "toolpath", "helix_radius_m": 0.004, "toolpath_x_m": x, "toolpath_y_m": y}))
write("tiny-helix.json", job(
    "tiny, helix",
    "tiny.json's column with the built-in helix of R_a = 4 mm (scripts/make_toolpath_examples.py), "
    "the reference of examples/toolpath-helix.json.",
    {"pattern": "helix", "helix_radius_m": 0.004}))
