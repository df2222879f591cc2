"""matplotlib helpers that draw what docs/study.md draws: the curves of a test
against axial strain with its yield and max-q states, Mohr circles with an
envelope, the wire's segment strain along its length, the grains' sizes
against the job's sieve curve, and the free-standing test (the unconfined
compression, the column's profile, the wire's tension at the peak).

Stresses are drawn in kPa and strains in %, as on the study's figures; every
marked state is the engine's (summary.json, or the test's attributes), not
re-read from the curve. ``scripts/study_report.py`` draws its figures with
these; each helper draws onto axes it is given, or makes a figure.
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Any, Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np

from .errors import ResultError
from .results import FreeStanding, MohrCoulomb, Result, Snapshot, Test

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.figure import Figure

#: What the curve helpers draw: (column, scale to the drawn unit, axis label, title).
CURVES: Dict[str, Tuple[float, str, str]] = {
    "stress_ratio": (1.0, "stress ratio η = (σ₁ − σ₃,eff)/(σ₁ + σ₃,eff)", "stress ratio (mobilised sin φ)"),
    "deviatoric_stress_pa": (1e-3, "q = σ₁ − σ₃,eff [kPa]", "deviatoric stress"),
    "volumetric_strain": (100.0, "volumetric strain ε_v [%] (contraction > 0)", "volumetric strain"),
}


def _pyplot() -> Any:
    import matplotlib.pyplot as plt
    return plt


def label_curve_axes(axes: Sequence["Axes"], columns: Sequence[str]) -> None:
    """Titles and labels of axes drawn by :func:`draw_test_curves`."""
    for ax, column in zip(axes, columns):
        _, ylabel, title = CURVES.get(column, (1.0, column, column))
        ax.set_ylabel(ylabel)
        ax.set_title(title)
        ax.set_xlabel("axial strain ε_a [%]")
        ax.grid(alpha=0.3)
        ax.set_xlim(left=0)
        if column == "volumetric_strain":
            ax.axhline(0.0, color="0.7", lw=0.8)


def draw_test_curves(axes: Sequence["Axes"], test: Test,
                     columns: Sequence[str] = ("stress_ratio", "deviatoric_stress_pa", "volumetric_strain"),
                     colour: Any = "k", lw: float = 1.5, alpha: float = 1.0, marker_size: float = 7.0,
                     label: Optional[str] = None) -> None:
    """One test's loading curves against axial strain, one column per axis.

    Marks the yield state (○, the maximum of the smoothed stress ratio) on the
    η and q axes and the maximum of q (△) on the q axis, from the engine's
    states; ``marker_size`` 0 draws none.
    """
    loading = test.loading
    strain = loading["axial_strain"].to_numpy() * 100.0
    for i, (ax, column) in enumerate(zip(axes, columns)):
        scale = CURVES.get(column, (1.0, "", ""))[0]
        ax.plot(strain, loading[column].to_numpy() * scale, color=colour, lw=lw, alpha=alpha,
                label=label if i == 0 else None)
    if not marker_size:
        return
    y = test.yield_state or {}
    peak = test.max_q_state
    for ax, column in zip(axes, columns):
        if column in ("stress_ratio", "deviatoric_stress_pa") and y.get("axial_strain") is not None:
            key = "stress_ratio" if column == "stress_ratio" else "deviatoric_stress_pa"
            if y.get(key) is not None:
                ax.plot(y["axial_strain"] * 100.0, y[key] * CURVES[column][0], marker="o", ms=marker_size,
                        mfc=colour, mec="k", ls="none", zorder=5)
        if column == "deviatoric_stress_pa" and peak.get("axial_strain") is not None \
                and peak.get("deviatoric_stress_pa") is not None:
            ax.plot(peak["axial_strain"] * 100.0, peak["deviatoric_stress_pa"] * 1e-3, marker="^", ms=marker_size,
                    mfc="white", mec=colour, mew=1.5, ls="none", zorder=5)


def pressure_colours(pressures_pa: Iterable[float], cmap: str = "viridis") -> Dict[float, Any]:
    """One colour per confining pressure, in ascending order (the same in every figure)."""
    plt = _pyplot()
    ps = sorted(set(float(p) for p in pressures_pa))
    colours = plt.get_cmap(cmap)
    n = max(1, len(ps) - 1)
    return {p: colours(0.85 * i / n) for i, p in enumerate(ps)}


def plot_curves(result: Result, columns: Sequence[str] = ("stress_ratio", "deviatoric_stress_pa", "volumetric_strain"),
                axes: Optional[Sequence["Axes"]] = None) -> "Figure":
    """Every test's loading curves (default: η, q and ε_v against ε_a), coloured by σ₃,
    with the yield and max-q states marked; returns the figure."""
    plt = _pyplot()
    if axes is None:
        fig, made = plt.subplots(1, len(columns), figsize=(5 * len(columns), 4.5), squeeze=False)
        axes = list(made[0])
    fig = axes[0].figure
    colours = pressure_colours(t.confining_pressure_pa for t in result.tests)
    for t in result.tests:
        draw_test_curves(axes, t, columns, colour=colours[t.confining_pressure_pa],
                         label=f"σ₃ = {t.confining_pressure_pa / 1e3:g} kPa")
    label_curve_axes(axes, columns)
    axes[0].legend(fontsize=8)
    fig.suptitle(f"{result.name}: loading (○ yield, △ max q)")
    fig.tight_layout()
    return fig


def draw_mohr_circle(ax: "Axes", sigma1_pa: float, sigma3_pa: float, colour: Any = "k", lw: float = 1.5,
                     alpha: float = 1.0, top_marker: bool = True, label: Optional[str] = None) -> float:
    """The Mohr circle of (σ₁, σ₃) in kPa, its top (p, t) marked; returns its radius [kPa]."""
    s1, s3 = sigma1_pa * 1e-3, sigma3_pa * 1e-3
    centre, radius = 0.5 * (s1 + s3), 0.5 * (s1 - s3)
    angle = np.linspace(0.0, np.pi, 120)
    ax.plot(centre + radius * np.cos(angle), radius * np.sin(angle), color=colour, lw=lw, alpha=alpha, label=label)
    if top_marker:
        ax.plot(centre, radius, "o", color=colour, ms=4)
    return radius


def draw_envelope(ax: "Axes", fit: MohrCoulomb, sigma_kpa: Any, **style: Any) -> None:
    """The envelope τ = c + σ tan φ over the normal stresses ``sigma_kpa`` [kPa]."""
    sigma = np.asarray(sigma_kpa, dtype=float)
    ax.plot(sigma, fit.shear_stress_pa(sigma * 1e3) * 1e-3, **style)


def plot_mohr(result: Result, ax: Optional["Axes"] = None, max_q: bool = False) -> "Figure":
    """The Mohr circles at yield (or at the maximum of q) of every test and the engine's envelope."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(8, 5))
    colours = pressure_colours(t.confining_pressure_pa for t in result.tests)
    top = sigma_max = 0.0
    for t in result.tests:
        state = t.max_q_state if max_q else (t.yield_state or {})
        if state.get("sigma1_pa") is None or state.get("sigma3_effective_pa") is None:
            continue
        r = draw_mohr_circle(ax, state["sigma1_pa"], state["sigma3_effective_pa"], colours[t.confining_pressure_pa],
                             label=f"σ₃ = {t.confining_pressure_pa / 1e3:g} kPa")
        top, sigma_max = max(top, r), max(sigma_max, state["sigma1_pa"] * 1e-3)
    fit = result.mohr_coulomb_max_q if max_q else result.mohr_coulomb
    sigma = np.linspace(0.0, 1.05 * sigma_max if sigma_max else 1.0, 50)
    if fit.friction_angle_deg is not None and fit.cohesion_pa is not None:
        draw_envelope(ax, fit, sigma, color="k", lw=2,
                      label=f"τ = c + σ tan φ: φ = {fit.friction_angle_deg:.1f}°, c = {fit.cohesion_pa / 1e3:.2f} kPa")
    ax.set_xlim(0, sigma[-1])
    ax.set_ylim(0, 1.25 * top if top else 1.0)
    ax.set_aspect("equal")
    ax.set_xlabel("normal stress σ [kPa]")
    ax.set_ylabel("shear stress τ [kPa]")
    ax.set_title(f"{result.name}: Mohr circles at {'the maximum of q' if max_q else 'yield'}")
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    return ax.figure


def draw_wire_strain(ax: "Axes", strain: Any, segment_length_m: float, colour: Any = "k", lw: float = 0.8) -> None:
    """Segment strains [%] against the position along the wire [m] (from the end laid first),
    the mean dashed and the largest marked ▼."""
    strain = np.asarray(strain, dtype=float)
    if strain.size == 0:
        raise ValueError("no wire segments to draw (a column without wire)")
    s = (np.arange(len(strain)) + 0.5) * segment_length_m
    ax.plot(s, strain * 100.0, color=colour, lw=lw)
    ax.axhline(float(np.mean(strain)) * 100.0, color="k", ls="--", lw=1)
    i = int(np.argmax(strain))
    ax.plot(s[i], strain[i] * 100.0, "v", color="k", ms=8)
    ax.set_xlabel("position along the wire s [m] (from the end laid first)")
    ax.set_ylabel("segment strain [%] (stretch > 0)")
    ax.grid(alpha=0.3)


def plot_wire_strain(result: Result, snapshot: Optional[Snapshot] = None, ax: Optional["Axes"] = None) -> "Figure":
    """The wire's segment strain along its length at a snapshot (default: the last of the
    highest pressure, the one summary.json's autocorrelation lags are read at)."""
    plt = _pyplot()
    if snapshot is None:
        if not result.tests or not result.tests[-1].snapshots:
            raise ValueError(f"{result.path}: no snapshot")
        snapshot = result.tests[-1].snapshots[-1]
    if ax is None:
        _, ax = plt.subplots(figsize=(10, 4))
    seg = float(result.job_spec["specimen"]["wire"]["segment_length_m"])
    draw_wire_strain(ax, snapshot.wire_segment_strain, seg)
    ax.set_title(f"{result.name}: wire segment strain at ε_a = {snapshot.axial_strain * 100:.2f} %")
    return ax.figure


def passing_fraction(diameters_m: Any, basis: str = "mass") -> Tuple[np.ndarray, np.ndarray]:
    """The grading of drawn grains: their diameters ascending and the fraction of the sample
    (by ``mass``, ∝ D³ for grains of one density, or by ``number``) at or below each."""
    d = np.sort(np.asarray(diameters_m, dtype=float))
    if d.size == 0:
        raise ValueError("no grains")
    if basis not in ("mass", "number"):
        raise ValueError(f"basis {basis!r}: 'mass' or 'number'")
    weight = d ** 3 if basis == "mass" else np.ones_like(d)
    return d, np.cumsum(weight) / np.sum(weight)


def draw_grain_sizes(ax: "Axes", diameters_m: Any, requested: Optional[Dict[str, Any]] = None,
                     drawn_figures: Optional[Dict[str, Any]] = None) -> None:
    """The grading curve of the drawn grains (percent passing against D [mm], log scale) on the
    requested curve's basis (by mass without one), the requested sieve curve (the job's
    ``specimen.grain_sizes``) as given, and the engine's D10, D50, D60 of the drawn grains
    (summary ``specimen.grain_sizes.drawn``) marked ×."""
    basis = str(requested.get("basis", "mass")) if requested else "mass"
    d, passing = passing_fraction(diameters_m, basis)
    ax.step(d * 1e3, passing * 100.0, where="post", color="C0", lw=1.5, label=f"drawn ({d.size} grains, by {basis})")
    if requested:
        ax.plot(np.asarray(requested["diameters_m"], dtype=float) * 1e3,
                np.asarray(requested["fraction_passing"], dtype=float) * 100.0,
                "o-", color="k", lw=1, ms=4, label=f"requested (by {basis})")
    if drawn_figures:
        for key, percent in (("d10_m", 10), ("d50_m", 50), ("d60_m", 60)):
            if drawn_figures.get(key) is not None:
                ax.plot(drawn_figures[key] * 1e3, percent, "x", color="C3", ms=9, mew=2)
    ax.set_xscale("log")
    ax.set_ylim(0, 100)
    ax.set_xlabel("grain diameter D [mm]")
    ax.set_ylabel("passing [%]")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=8)


def plot_grain_sizes(result: Result, ax: Optional["Axes"] = None) -> "Figure":
    """The prepared specimen's grading against the job's sieve curve, with the engine's drawn
    D10/D50/D60 (×) and the Kolmogorov–Smirnov distance in the title when the job has a curve."""
    plt = _pyplot()
    if ax is None:
        _, ax = plt.subplots(figsize=(7, 4.5))
    requested = result.job_spec.get("specimen", {}).get("grain_sizes")
    figures = ((result.summary or {}).get("specimen") or {}).get("grain_sizes") or {}
    draw_grain_sizes(ax, 2.0 * result.specimen.grain_radius_m, requested, figures.get("drawn"))
    title = f"{result.name}: grain sizes"
    if figures.get("ks_distance") is not None:
        title += f" (KS distance {figures['ks_distance']:.3f}, 1 % critical {figures['ks_critical_1pct']:.3f})"
    ax.set_title(title)
    return ax.figure


def draw_unconfined_compression(ax: "Axes", fs: FreeStanding, colour: Any = "k", lw: float = 1.5,
                                label: Optional[str] = None) -> None:
    """σ₁ [kPa] of the unconfined compression against its axial strain [%], the unconfined
    strength (the smoothed maximum, at its strain) marked ○ and the largest raw σ₁ △, from
    the engine's figures (summary.json's ``compression``, else the group's attributes)."""
    c = fs.compression
    if c.empty:
        raise ValueError("no unconfined compression (the job pulled the wire out instead)")
    ax.plot(c["axial_strain"].to_numpy() * 100.0, c["sigma1_pa"].to_numpy() * 1e-3, color=colour, lw=lw, label=label)
    figures = fs.unconfined_compression or {}
    strength = figures.get("unconfined_strength_pa", fs.attributes.get("strength_smoothed_maximum"))
    at = figures.get("strain_at_failure", fs.attributes.get("strength_axial_strain"))
    if strength is not None and at is not None:
        ax.plot(at * 100.0, strength * 1e-3, "o", color=colour, ms=7, mfc="none", mew=1.5)
    peak = fs.attributes.get("max_sigma1_sample")
    if peak is not None:
        ax.plot(c.loc[int(peak), "axial_strain"] * 100.0, c.loc[int(peak), "sigma1_pa"] * 1e-3, "^", color=colour, ms=7)
    ax.set_xlabel("axial strain ε_a [%]")
    ax.set_ylabel("σ₁ = F_top/(π r₀²) [kPa]")
    ax.grid(alpha=0.3)
    ax.set_xlim(left=0)


def draw_profiles(ax: "Axes", fs: FreeStanding, which: Sequence[str] = ("before", "settled", "at_peak")) -> None:
    """The column's radius [mm] against height [mm], one line per profile (``before`` the
    formwork went, ``settled``, ``at_peak`` and ``at_end`` of the compression) it holds."""
    styles = {"before": ("0.6", "--"), "settled": ("C0", "-"), "at_peak": ("C3", "-"), "at_end": ("C1", ":")}
    for name in which:
        try:
            p = fs.profile(name)
        except ResultError:  # a pull-out has no profile at the peak: draw what there is
            continue
        colour, ls = styles.get(name, ("k", "-"))
        ax.plot(p["radius_m"].to_numpy() * 1e3, p["height_m"].to_numpy() * 1e3, ls, color=colour, marker=".",
                label=name.replace("_", " "))
    ax.set_xlabel("radius [mm] (equivalent radius of a slice's grains)")
    ax.set_ylabel("height [mm]")
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)


def plot_free_standing(result: Result) -> "Figure":
    """The free-standing test on one figure: the unconfined compression (or the pull-out's
    force against the pulled length), the column's profiles, and the wire's tension along
    its length at the compression's largest σ₁ (when the column has a wire and a compression);
    the title says whether the column stands."""
    fs = result.free_standing
    if fs is None:
        raise ValueError(f"{result.path}: the job ran no free-standing test")
    plt = _pyplot()
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    pulled = fs.pull_out
    if pulled is not None:
        axes[0].plot(pulled["pulled_length_m"].to_numpy() * 1e3, pulled["pull_force_n"].to_numpy(), color="k")
        axes[0].set_xlabel("pulled length [mm]")
        axes[0].set_ylabel("pull force [N]")
        axes[0].grid(alpha=0.3)
        axes[0].set_title("pull-out")
    else:
        draw_unconfined_compression(axes[0], fs)
        axes[0].set_title("unconfined compression (○ strength, △ largest σ₁)")
    draw_profiles(axes[1], fs)
    axes[1].set_title("column profile")
    try:
        w = fs.wire_at_peak()
    except ResultError:  # no wire, or no compression
        axes[2].set_axis_off()
    else:
        seg = float(result.job_spec["specimen"]["wire"]["segment_length_m"])
        axes[2].plot((w.index.to_numpy() + 0.5) * seg, w["tension_n"].to_numpy(), color="k", lw=0.8)
        axes[2].set_xlabel("position along the wire s [m] (from the end laid first)")
        axes[2].set_ylabel("segment tension [N]")
        axes[2].grid(alpha=0.3)
        axes[2].set_title("wire tension at the largest σ₁")
    settling = fs.settling
    verdict = "stands" if fs.stands else "does not stand"
    loss = settling.get("bulk_height_loss")
    lost = settling.get("lost_fraction")
    detail = "" if loss is None or lost is None else \
        f" (bulk height {-100 * loss:+.1f} %, {100 * lost:.0f} % of the grains' volume lost" \
        + ("" if settling.get("at_rest", True) else ", not at rest") + ")"
    fig.suptitle(f"{result.name}: the column {verdict}{detail}")
    fig.tight_layout()
    return fig


def tests_by_pressure(results: Iterable[Result]) -> Dict[float, List[Test]]:
    """{σ₃ [Pa]: the tests at it} over several results (e.g. the seeds of a pattern)."""
    out: Dict[float, List[Test]] = {}
    for r in results:
        for t in r.tests:
            out.setdefault(t.confining_pressure_pa, []).append(t)
    return dict(sorted(out.items()))
