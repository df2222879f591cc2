#!/usr/bin/env python3
"""The arctangent polynomial of bend_angle_rad (engine/laws/wire_bond.hpp).

Fits P(u) with atan r = r + r u P(u), u = r^2, |r| <= tan(pi/8), by
interpolating (atan(sqrt u) - sqrt u)/(u sqrt u) at the Chebyshev nodes of
[0, tan^2(pi/8)] in 50-digit arithmetic; prints the coefficients rounded to
double and the fit's relative error; then evaluates bend_angle_rad as the C++
does it (Python floats are IEEE doubles, and the C++ fuses no multiply-add)
over N angles in [0, pi] (uniform, nearly straight, nearly folded back, near
the reduction's thresholds; some scaled off the unit circle) and prints its
largest error in ulp against 50-digit atan2, beside math.atan2's.

usage: scripts/fit_bend_angle.py [--degree 10] [--angles 200000]
needs: python3-mpmath (Debian)
"""
import argparse
import math
import random

import mpmath as mp

mp.mp.dps = 50


def fit(degree):
    u_max = mp.tan(mp.pi / 8) ** 2

    def target(u):
        s = mp.sqrt(u)
        return (mp.atan(s) - s) / (s * u)

    nodes = [u_max / 2 * (1 + mp.cos(mp.pi * (k + mp.mpf(1) / 2) / (degree + 1))) for k in range(degree + 1)]
    vandermonde = mp.matrix([[u ** j for j in range(degree + 1)] for u in nodes])
    c = mp.lu_solve(vandermonde, mp.matrix([target(u) for u in nodes]))
    coefficients = [c[j] for j in range(degree + 1)]
    worst = mp.mpf(0)
    for k in range(1, 2001):
        r = mp.tan(mp.pi / 8) * k / 2000
        u = r * r
        approx = r + r * u * sum(coefficients[j] * u ** j for j in range(degree + 1))
        worst = max(worst, abs(approx / mp.atan(r) - 1))
    return [float(x) for x in coefficients], worst


def bend_angle(sin_z, cos_z, poly):
    """engine/laws/wire_bond.hpp's bend_angle_rad, operation for operation."""
    ax = -cos_z if cos_z < 0.0 else cos_z
    steep = sin_z > ax
    big = sin_z if steep else ax
    small = ax if steep else sin_z
    reduced = small > 0.41421356237309503 * big
    r = (small - big if reduced else small) / (small + big if reduced else big)
    u = r * r
    p = poly[-1]
    for c in reversed(poly[:-1]):
        p = p * u + c
    a = r + (r * u) * p
    if reduced:
        a = math.pi / 4 + a
    if steep:
        a = math.pi / 2 - a
    return math.pi - a if cos_z < 0.0 else a


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--degree", type=int, default=10)
    parser.add_argument("--angles", type=int, default=200000)
    args = parser.parse_args()
    poly, fit_error = fit(args.degree)
    print("inline constexpr std::array<double, %d> bend_angle_polynomial{" % len(poly))
    for c in poly:
        print("    %r," % c)
    print("};")
    print("fit: largest relative error %s" % mp.nstr(fit_error, 3))
    assert math.pi / 4 == float(mp.pi / 4) and 0.41421356237309503 == float(mp.tan(mp.pi / 8))

    rng = random.Random(1)
    worst, worst_libm = (0.0, None), (0.0, None)
    for i in range(args.angles):
        kind = i % 4
        if kind == 0:
            t = rng.uniform(0.0, math.pi)
        elif kind == 1:
            t = 10 ** rng.uniform(-12, 0)
        elif kind == 2:
            t = math.pi - 10 ** rng.uniform(-12, 0)
        else:
            t = rng.choice([math.atan(0.41421356237309503), math.pi / 4, math.pi / 2, 3 * math.pi / 4]) \
                + rng.uniform(-1e-3, 1e-3)
        scale = 10 ** rng.uniform(-3, 3) if i % 8 == 0 else 1.0
        y, x = abs(math.sin(t)) * scale, math.cos(t) * scale
        exact = mp.atan2(mp.mpf(y), mp.mpf(x))
        ulp = math.ulp(float(exact))
        ours = float(abs(mp.mpf(bend_angle(y, x, poly)) - exact) / ulp)
        libm = float(abs(mp.mpf(math.atan2(y, x)) - exact) / ulp)
        if ours > worst[0]:
            worst = (ours, (y, x))
        if libm > worst_libm[0]:
            worst_libm = (libm, (y, x))
    print("bend_angle_rad: largest error %.2f ulp at (sin, cos) = %r; math.atan2: %.2f ulp"
          % (worst[0], worst[1], worst_libm[0]))


if __name__ == "__main__":
    main()
