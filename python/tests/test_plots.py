"""The plot helpers draw the engine's states where the summary puts them."""
from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import wiredem  # noqa: E402
from wiredem import plots  # noqa: E402


def _markers(ax, marker):
    return [line for line in ax.get_lines() if line.get_marker() == marker]


def test_the_curves_mark_yield_and_max_q_at_the_engines_states(tiny_dir: Path, tmp_path: Path) -> None:
    r = wiredem.open(tiny_dir)
    fig = plots.plot_curves(r)
    eta_ax, q_ax, _ = fig.axes
    for t, dot in zip(r.tests, _markers(eta_ax, "o")):
        assert dot.get_xdata()[0] == pytest.approx(100 * t.yield_state["axial_strain"], rel=1e-12)
        assert dot.get_ydata()[0] == pytest.approx(t.yield_state["stress_ratio"], rel=1e-12)
    for t, tri in zip(r.tests, _markers(q_ax, "^")):
        assert tri.get_ydata()[0] == pytest.approx(1e-3 * t.max_q_state["deviatoric_stress_pa"], rel=1e-12)
    curves = [line for line in eta_ax.get_lines() if line.get_marker() in ("None", "")]
    assert len(curves) == len(r.tests)
    np.testing.assert_array_equal(curves[0].get_ydata(), r.tests[0].loading["stress_ratio"].to_numpy())
    fig.savefig(tmp_path / "curves.png")
    plt.close(fig)


def test_the_mohr_circles_are_the_yield_states_and_the_envelope_the_fit(tiny_dir: Path, tmp_path: Path) -> None:
    r = wiredem.open(tiny_dir)
    fig = plots.plot_mohr(r)
    ax = fig.axes[0]
    tops = _markers(ax, "o")
    for t, top in zip(r.tests, tops):
        s1, s3 = t.yield_state["sigma1_pa"] * 1e-3, t.yield_state["sigma3_effective_pa"] * 1e-3
        assert top.get_xdata()[0] == pytest.approx((s1 + s3) / 2, rel=1e-12)
        assert top.get_ydata()[0] == pytest.approx((s1 - s3) / 2, rel=1e-12)
    envelope = next(line for line in ax.get_lines() if "φ =" in str(line.get_label()))
    assert envelope.get_ydata()[0] == pytest.approx(r.mohr_coulomb.cohesion_pa * 1e-3, rel=1e-12)
    fig.savefig(tmp_path / "mohr.png")
    plt.close(fig)


def test_the_wire_strain_is_drawn_along_the_wire() -> None:
    fig, ax = plt.subplots()
    strain = np.array([0.0, 0.01, 0.03, 0.02])
    plots.draw_wire_strain(ax, strain, 0.002)
    line = ax.get_lines()[0]
    np.testing.assert_allclose(line.get_xdata(), [0.001, 0.003, 0.005, 0.007])
    np.testing.assert_allclose(line.get_ydata(), strain * 100)
    peak = _markers(ax, "v")[0]
    assert peak.get_ydata()[0] == pytest.approx(3.0)
    plt.close(fig)


def test_a_column_without_wire_has_no_wire_strain_to_draw(tiny_dir: Path) -> None:
    with pytest.raises(ValueError, match="without wire"):
        plots.plot_wire_strain(wiredem.open(tiny_dir))
    plt.close("all")


def test_the_drawn_grading_passes_by_mass_and_by_number() -> None:
    d = np.array([3e-3, 1e-3, 2e-3])
    sizes, by_mass = plots.passing_fraction(d, "mass")
    np.testing.assert_array_equal(sizes, [1e-3, 2e-3, 3e-3])
    np.testing.assert_allclose(by_mass, [1 / 36, 9 / 36, 1.0], rtol=1e-15)  # D³: 1, 8, 27
    np.testing.assert_allclose(plots.passing_fraction(d, "number")[1], [1 / 3, 2 / 3, 1.0], rtol=1e-15)
    with pytest.raises(ValueError):
        plots.passing_fraction(d, "volume")


def test_the_grain_sizes_plot_draws_the_requested_curve_and_marks_the_engines_figures(tmp_path: Path) -> None:
    fig, ax = plt.subplots()
    requested = {"basis": "number", "diameters_m": [1e-3, 4e-3], "fraction_passing": [0.0, 1.0]}
    plots.draw_grain_sizes(ax, [1e-3, 2e-3, 3e-3, 4e-3], requested,
                           {"d10_m": 1.2e-3, "d50_m": 2.5e-3, "d60_m": 2.8e-3})
    drawn, curve = ax.get_lines()[0], ax.get_lines()[1]
    np.testing.assert_allclose(drawn.get_ydata(), [25, 50, 75, 100])  # by the requested curve's basis
    np.testing.assert_allclose(curve.get_xdata(), [1.0, 4.0])
    marks = _markers(ax, "x")
    assert [(m.get_xdata()[0], m.get_ydata()[0]) for m in marks] == [(1.2, 10), (2.5, 50), (2.8, 60)]
    fig.savefig(tmp_path / "grain_sizes.png")
    plt.close(fig)
