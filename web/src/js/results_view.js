// What a succeeded job's results look like, from data in the shapes of the
// result data routes (docs/api.md): the summary, the curves, the Mohr circles
// and the wire's strain, breaks and pieces. Shared by the job page (job.js, data from the API)
// and the offline report (report.js, data embedded by `wiredem report`), so
// both draw the same plots. Imports only dom.js and plots.js (the report
// inlines these four modules into one file).
import { el, num, kpa, figure } from './dom.js';
import { linePlot, mohrSemicircle } from './plots.js';

/// Rows of the loading phase (phase 2): the curves against axial strain.
export function loadingRows(series) {
  const phase = series.columns.phase;
  return series.columns.axial_strain.map((_, i) => i).filter((i) => !phase || phase[i] === 2);
}

export const kPaLabel = (pa) => `σ₃ = ${num(pa / 1000, 4)} kPa`;

/// A length in metres shown in mm, or '—' when there is none.
const mm = (m) => (m != null ? num(m * 1000, 4) : '—');

/// The sign of ε_v = (V₀ − V)/V₀ (engine/analysis/stress.hpp): positive when
/// the column compacts, negative when it dilates; said on the axis and under the plot.
const volumetricLabel = 'ε_v  (> 0 compaction, < 0 dilation)';
const volumetricNote = 'ε_v = (V₀ − V)/V₀: positive when the column compacts (its volume falls), negative when it dilates.';

/// The columns the curves need (the series route's ?columns=).
export const curveColumns = 'axial_strain,deviatoric_stress_pa,stress_ratio,volumetric_strain,phase';

/// Warnings (first: a result that was not quasi-static or not settled must not
/// be read as if it were), the summary figures and the per-test table.
/// The triaxial cell that ran (summary.specimen.cell, triaxial.cell), for people.
export function cellText(c) {
  return { membrane: 'membrane (flexible, pressurised)', cuboid: 'cuboid (six rigid walls; its side walls confine)' }[c] ?? (c == null ? '—' : String(c));
}

export function renderSummary(body, summary) {
  if (summary.warnings && summary.warnings.length)
    body.append(el('div', { class: 'warnings', id: 'warnings' }, el('h2', {}, `Warnings (${summary.warnings.length})`),
      el('ul', {}, summary.warnings.map((w) => el('li', {}, w)))));

  const mc = summary.mohr_coulomb || {};
  const mcq = summary.mohr_coulomb_max_q || {};
  const sp = summary.specimen || {};
  const nn = mc.nonnegative || {};
  const c0 = mc.cohesionless || {};
  body.append(el('h2', {}, 'Summary'),
    el('div', { class: 'figures', id: 'figures' },
      fitFigure(mc, 'φ (yield) [°]', num(mc.friction_angle_deg, 4), 'friction_angle_deg'),
      fitFigure(mc, 'c (yield) [kPa]', kpa(mc.cohesion_pa), 'cohesion_pa'),
      fitFigure(mc, 'R²', num(mc.r_squared, 4), 'r_squared'),
      figure('φ, c with c ≥ 0, φ ≥ 0', `${num(nn.friction_angle_deg, 4)}°, ${kpa(nn.cohesion_pa)} kPa`, 'nonnegative'),
      figure('φ with c = 0 [°]', num(c0.friction_angle_deg, 4), 'cohesionless_friction_angle_deg'),
      figure('α, slope of the tops [°]', num(mc.paper_top_line_angle_deg, 4), 'paper_top_line_angle_deg'),
      fitFigure(mcq, 'φ (max q) [°]', num(mcq.friction_angle_deg, 4), 'max_q_friction_angle_deg'),
      figure('triaxial cell', cellText(sp.cell), 'cell'),
      figure('grain volume fraction', num(sp.grain_volume_fraction, 4), 'grain_volume_fraction'),
      figure('wire volume fraction', num(sp.wire_volume_fraction, 4), 'wire_volume_fraction'),
      figure('grains', sp.grains ?? '—', 'grains'),
      figure('wire nodes', sp.wire_nodes ?? '—', 'wire_nodes'),
      figure('wire autocorrelation lag [mm]', mm((summary.wire || {}).autocorrelation_lag_m), 'autocorrelation_lag_m'),
      figure('wire prominent lag [mm]', mm((summary.wire || {}).autocorrelation_prominent_lag_m), 'autocorrelation_prominent_lag_m')),
    mc.error ? el('div', { class: 'error-box' }, `Mohr–Coulomb fit: ${mc.error}`) : '',
    caveatBox(mc, mcq),
    el('table', { id: 'tests-table' },
      el('thead', {}, el('tr', {}, ['σ₃ [kPa]', 'peak q [kPa]', 'σ₁ at peak [kPa]', 'σ₃,eff at peak [kPa]', 'ε at peak', 'max q shape', 'yield η', 'yield ε', 'quasi-static'].map((h) => el('th', {}, h)))),
      el('tbody', {}, (summary.tests || []).map((t) => el('tr', { 'data-pressure': t.confining_pressure_pa },
        el('td', { class: 'num' }, kpa(t.confining_pressure_pa)),
        el('td', { class: 'num', 'data-key': 'peak_deviatoric_stress_pa' }, kpa(t.peak_deviatoric_stress_pa)),
        el('td', { class: 'num', 'data-key': 'sigma1_pa' }, kpa(t.sigma1_pa)),
        el('td', { class: 'num', 'data-key': 'sigma3_effective_pa' }, kpa(t.sigma3_effective_pa)),
        el('td', { class: 'num', 'data-key': 'peak_axial_strain' }, num(t.peak_axial_strain, 4)),
        el('td', {}, t.max_q_shape || '—'),
        el('td', { class: 'num' }, t.yield ? num(t.yield.stress_ratio, 4) : '—'),
        el('td', { class: 'num' }, t.yield ? num(t.yield.axial_strain, 4) : '—'),
        el('td', {}, t.quasi_static === false ? 'no' : t.quasi_static ? 'yes' : '—'))))));

}

/// The caveats of a Mohr–Coulomb fit of summary.json ([] when it has none):
/// [{code, message}], made by the engine's analysis (engine/analysis/mohr_coulomb.hpp).
export const fitCaveats = (mc) => (mc && Array.isArray(mc.caveats) ? mc.caveats : []);

/// A summary tile of an unconstrained fit, marked ⚠ (class `flagged`, the
/// codes in data-caveats) when the fit has caveats.
function fitFigure(mc, label, value, id) {
  const caveats = fitCaveats(mc);
  if (!caveats.length) return figure(label, value, id);
  const tile = figure(`${label} ⚠`, value, id);
  tile.classList.add('flagged');
  tile.dataset.caveats = caveats.map((c) => c.code).join(' ');
  tile.title = 'an unconstrained fit: read the caveats below';
  return tile;
}

/// What the flagged figures are: each fit's caveats in a sentence, under the tiles.
function caveatBox(mc, mcq) {
  const items = [['yield states', mc], ['maxima of q', mcq]].flatMap(([what, fit]) =>
    fitCaveats(fit).map((c) => el('li', { 'data-code': c.code }, `Mohr–Coulomb fit through the ${what}: ${c.message}`)));
  if (!items.length) return '';
  return el('div', { class: 'caveats', id: 'fit-caveats' },
    el('h3', {}, '⚠ The fitted envelope is an unconstrained line: read it with these caveats'), el('ul', {}, items));
}

/// q, the stress ratio and the volumetric strain against axial strain for
/// every test, and the Mohr circles (when there is a summary: not while the
/// job runs); `tests` as GET …/tests gives them, `series` one GET …/series
/// reply per test (curveColumns; a column it lacks draws no points).
export function renderCurves(body, summary, tests, series) {
  body.append(el('h2', {}, 'Curves'));
  const grid = el('div', { class: 'grid' });
  body.append(grid);
  const curves = (column, scale = 1) => tests.map((t, i) => {
    const rows = loadingRows(series[i]);
    const values = series[i].columns[column];
    const drawn = values ? rows : [];
    return { label: kPaLabel(t.attributes.confining_pressure_pa),
      x: drawn.map((r) => series[i].columns.axial_strain[r]), y: drawn.map((r) => values[r] * scale) };
  });
  // A breakable wire's breaks, each a vertical line at the axial strain it broke at.
  const breaks = summary ? breakMarkers((summary.tests || []).map((t) => [kPaLabel(t.confining_pressure_pa), t.wire_breaks])) : [];
  const qBox = linePlot(grid, { id: 'plot-q', title: 'Deviatoric stress q against axial strain (loading)', xLabel: 'axial strain ε₁', yLabel: 'q [kPa]',
    series: curves('deviatoric_stress_pa', 1e-3), markers: breaks,
    note: breaks.length ? 'Dashed lines: the wire broke there (the list under "Wire breaks and pieces").' : undefined });
  qBox.wiredemPlot.breaks = breaks.map((m) => m.x);
  linePlot(grid, { id: 'plot-ratio', title: 'Stress ratio (σ₁ − σ₃)/(σ₁ + σ₃) against axial strain', xLabel: 'axial strain ε₁', yLabel: 'stress ratio', series: curves('stress_ratio') });
  linePlot(grid, { id: 'plot-volumetric', title: 'Volumetric strain against axial strain', xLabel: 'axial strain ε₁', yLabel: volumetricLabel, series: curves('volumetric_strain'),
    note: volumetricNote });
  if (summary) mohrPlot(grid, summary);
}

/// Mohr circles at yield (σ₃,eff and σ₁ of each test's yield state), the fitted
/// envelope τ = c + σ tan φ (marked ⚠ when it has caveats), the constrained
/// fits of summary.json beside it (c ≥ 0 and φ ≥ 0; c = 0) when they differ
/// from it, and the line through the circle tops t = c cos φ + p tan α. The τ
/// axis goes below 0 when an envelope does (a negative c is not hidden).
export function mohrPlot(parent, summary, id = 'plot-mohr') {
  const mc = summary.mohr_coulomb || {};
  const states = (summary.tests || []).filter((t) => t.yield && t.yield.sigma1_pa != null);
  const series = states.map((t) => {
    const c = mohrSemicircle(t.yield.sigma3_effective_pa / 1000, t.yield.sigma1_pa / 1000);
    return { label: `yield at ${kPaLabel(t.confining_pressure_pa)}`, ...c };
  });
  const sigmaMax = Math.max(1, ...states.map((t) => t.yield.sigma1_pa / 1000)) * 1.05;
  const line = (phiDeg, cPa) => {
    const c = cPa / 1000, tanPhi = Math.tan((phiDeg * Math.PI) / 180);
    return { x: [0, sigmaMax], y: [c, c + sigmaMax * tanPhi] };
  };
  const flagged = fitCaveats(mc).length > 0;
  if (mc.friction_angle_deg != null && mc.cohesion_pa != null) {
    const c = mc.cohesion_pa / 1000;
    series.push({ label: `envelope φ = ${num(mc.friction_angle_deg, 3)}°, c = ${num(c, 3)} kPa${flagged ? ' (unconstrained ⚠)' : ''}`,
      ...line(mc.friction_angle_deg, mc.cohesion_pa), color: '#1d2330', width: 2, envelope: true });
    const differs = (e) => e && e.friction_angle_deg != null && e.cohesion_pa != null
      && (e.friction_angle_deg !== mc.friction_angle_deg || e.cohesion_pa !== mc.cohesion_pa);
    if (differs(mc.nonnegative))
      series.push({ label: `fit with c ≥ 0, φ ≥ 0: φ = ${num(mc.nonnegative.friction_angle_deg, 3)}°, c = ${num(mc.nonnegative.cohesion_pa / 1000, 3)} kPa`,
        ...line(mc.nonnegative.friction_angle_deg, mc.nonnegative.cohesion_pa), color: '#d9480f', width: 2, dash: [10, 5], constrained: 'nonnegative' });
    if (differs(mc.cohesionless) && (!differs(mc.nonnegative) || mc.cohesionless.friction_angle_deg !== mc.nonnegative.friction_angle_deg
        || mc.cohesionless.cohesion_pa !== mc.nonnegative.cohesion_pa))
      series.push({ label: `fit with c = 0: φ = ${num(mc.cohesionless.friction_angle_deg, 3)}°`,
        ...line(mc.cohesionless.friction_angle_deg, 0), color: '#0a7e8c', width: 1.5, dash: [2, 4], constrained: 'cohesionless' });
    if (mc.paper_top_line_angle_deg != null) {
      const tanAlpha = Math.tan((mc.paper_top_line_angle_deg * Math.PI) / 180);
      const a = c * Math.cos((mc.friction_angle_deg * Math.PI) / 180);
      series.push({ label: `slope of the tops α = ${num(mc.paper_top_line_angle_deg, 3)}° (not φ)`, x: [0, sigmaMax], y: [a, a + sigmaMax * tanAlpha], color: '#8250df', dash: [6, 4] });
    }
  }
  const lowest = Math.min(0, ...series.filter((s) => !s.label.startsWith('yield')).flatMap((s) => s.y));
  const yMin = lowest < 0 ? lowest - 0.1 * sigmaMax : 0;
  const box = linePlot(parent, { id, title: 'Mohr circles at yield', xLabel: 'σ [kPa]', yLabel: 'τ [kPa]', series, equalAspect: true, yMin,
    note: [mc.states || '', flagged ? 'The black envelope is an unconstrained fit; see the caveats above the plots.' : ''].filter(Boolean).join(' ') });
  box.wiredemPlot.envelope = { friction_angle_deg: mc.friction_angle_deg, cohesion_pa: mc.cohesion_pa, flagged };
  box.wiredemPlot.yMin = yMin;
  box.wiredemPlot.constrained = series.filter((s) => s.constrained).map((s) => s.constrained);
  return box;
}

/// The wire's segment strain along its length and its autocorrelation (the
/// …/wire_autocorrelation reply) with its first maximum and its first prominent
/// maximum marked (engine/analysis/autocorrelation.hpp; they differ when the
/// first is a bump within R̂'s noise band).
export function renderWire(grid, summary, label, nodePositions, strain, ac) {
  const s = [0];
  for (let k = 1; k < strain.length; ++k) {
    const i = 3 * k;
    s.push(s[k - 1] + Math.hypot(nodePositions[i] - nodePositions[i - 3], nodePositions[i + 1] - nodePositions[i - 2],
      nodePositions[i + 2] - nodePositions[i - 1]) * 1000);
  }
  linePlot(grid, { id: 'plot-wire-strain', title: 'Segment strain along the wire', xLabel: 'distance along the wire [mm]', yLabel: 'segment strain [10⁻³]',
    series: [{ label, x: s, y: Array.from(strain, (e) => e * 1000) }] });
  const lag = ac.first_maximum_lag_m;
  const prominent = ac.prominent_maximum_lag_m;
  const markers = [];
  if (lag != null) markers.push({ x: lag * 1000, label: `first maximum ${mm(lag)} mm` });
  if (prominent != null) markers.push({ x: prominent * 1000, label: `first prominent maximum ${mm(prominent)} mm` });
  const w = summary.wire || {};
  const note = ac.error ? `No autocorrelation: ${ac.error}`
    : lag == null ? 'No local maximum after lag 0.'
    : `First maximum at ${mm(lag)} mm; first prominent maximum (prominence above the white-noise band 1.96/√(N − k)) ${prominent != null ? `at ${mm(prominent)} mm` : 'none'} `
      + `(summary: ${mm(w.autocorrelation_lag_m)} and ${mm(w.autocorrelation_prominent_lag_m)} mm, the end of the test at the highest pressure).`;
  const box = linePlot(grid, { id: 'plot-autocorrelation', title: 'Autocorrelation of the segment strain', xLabel: 'lag [mm]', yLabel: 'R(k)',
    series: [{ label: 'R(k)', x: ac.lag_m.map((l) => l * 1000), y: ac.coefficients }], markers, note });
  box.wiredemPlot.first_maximum_lag_m = lag;
  box.wiredemPlot.prominent_maximum_lag_m = prominent;
  box.wiredemPlot.markers = markers.map((m) => m.label);
}

/// The columns the free-standing plot needs (its series route's ?columns=).
export const freeStandingColumns = 'axial_strain,sigma1_pa,phase';

/// Rows of the free-standing test's unconfined compression (phase 3).
export function compressionRows(series) {
  const phase = series.columns.phase;
  return series.columns.axial_strain.map((_, i) => i).filter((i) => phase && phase[i] === 3);
}

const yesNo = (b) => (b === true ? 'yes' : b === false ? 'no' : '—');

/// The free-standing test (docs/model.md, "The free-standing test"): its
/// figures from summary.free_standing (whether it stands, read from the
/// grains' bulk height and the grains lost; the top, where the plate was
/// set); σ₁ against axial strain in the
/// unconfined compression with the unconfined strength marked and labelled
/// (peak / plateau / rising) and the envelope's prediction 2c cos φ/(1 − sin φ);
/// the column's radius against height before the removal, settled, at the
/// largest σ₁ and at the end; the wire's tension along its length at the
/// largest σ₁; with a pull-out instead of the compression, the pull force
/// against the pulled length (renderPullOut). `test` as GET …/free_standing
/// gives it, `series` its series reply (freeStandingColumns).
export function renderFreeStanding(body, summary, test, series) {
  const fs = (summary && summary.free_standing) || {};
  const st = fs.settling || {};
  const c = fs.compression || {};
  const dl = fs.dead_load;
  const po = fs.pull_out;
  body.append(el('h2', { id: 'free-standing' }, 'Free-standing test'));
  body.append(el('div', { class: 'figures', id: 'free-standing-figures' },
    figure('stands', yesNo(st.stands), 'fs_stands'),
    figure('grains\' bulk height loss', num(st.bulk_height_loss, 3), 'fs_bulk_height_loss'),
    figure('grains\' bulk height before → after [mm]', `${mm(st.bulk_height_before_m)} → ${mm(st.bulk_height_m)}`, 'fs_bulk_height'),
    figure('grains that left (share of their volume)', st.escaped_grains != null
      ? `${st.escaped_grains} of ${st.grains ?? '—'} (${st.lost_fraction != null ? num(st.lost_fraction * 100, 3) : '—'} %)` : '—', 'fs_escaped_grains'),
    figure('top (grain or wire) before → after [mm]', `${mm(st.height_before_m)} → ${mm(st.height_m)}`, 'fs_height'),
    figure('top height loss', num(st.height_loss, 3), 'fs_height_loss'),
    figure('time to rest [s]', num(st.time_to_rest_s, 3), 'fs_time_to_rest_s'),
    figure('base force / weight', st.weight_n ? num(st.base_force_n / st.weight_n, 4) : '—', 'fs_base_over_weight'),
    figure(`unconfined strength (${c.shape || '—'}) [kPa]`, kpa(c.unconfined_strength_pa), 'fs_unconfined_strength_pa'),
    figure('predicted by the envelope [kPa]', kpa(c.predicted_unconfined_strength_pa), 'fs_predicted_unconfined_strength_pa'),
    figure('strain at failure', num(c.strain_at_failure, 4), 'fs_strain_at_failure'),
    figure('quasi-static', yesNo(c.quasi_static), 'fs_quasi_static'),
    c.peak_failure !== undefined ? figure('failed by', failureText(c.peak_failure), 'fs_peak_failure') : '',
    c.failure_mode != null ? figure('how it failed', failureModeText(c), 'fs_failure_mode') : '',
    dl ? figure(`dead load ${num(dl.force_n, 3)} N holds`, `${yesNo(dl.holds)} (creep ${num(dl.creep_strain, 3)})`, 'fs_dead_load') : '',
    po ? figure('peak pull force [N]', num(po.peak_pull_force_n, 4), 'fs_peak_pull_force_n') : '',
    po ? figure('pulled length at the peak → in all [mm]', `${mm(po.pulled_length_at_peak_m)} → ${mm(po.pulled_length_m)}`, 'fs_pulled_length') : '',
    po ? figure('wire in the column before → after [mm]', `${mm(po.wire_in_column_before_m)} → ${mm(po.wire_in_column_m)}`, 'fs_wire_in_column') : ''));
  const grid = el('div', { class: 'grid' });
  body.append(grid);
  if (po) renderPullOut(grid, po, test && test.pull_out);

  // σ₁ against ε in the compression, the strength as a horizontal line at its
  // value and a vertical one at its strain, the prediction beside it.
  const rows = compressionRows(series);
  const x = rows.map((r) => series.columns.axial_strain[r]);
  const y = rows.map((r) => series.columns.sigma1_pa[r] / 1000);
  const xMax = Math.max(0, ...x.filter(Number.isFinite));
  const curves = [{ label: 'σ₁ = F_top/(π r₀²)', x, y }];
  const markers = [];
  if (c.unconfined_strength_pa != null) {
    curves.push({ label: `unconfined strength (${c.shape}) ${kpa(c.unconfined_strength_pa)} kPa`, x: [0, xMax],
      y: [c.unconfined_strength_pa / 1000, c.unconfined_strength_pa / 1000], color: '#1d2330', dash: [8, 4], width: 2 });
    if (c.strain_at_failure != null) markers.push({ x: c.strain_at_failure, label: `${c.shape} at ε₁ = ${num(c.strain_at_failure, 3)}` });
  }
  if (c.predicted_unconfined_strength_pa != null)
    curves.push({ label: `envelope: 2c cos φ/(1 − sin φ) = ${kpa(c.predicted_unconfined_strength_pa)} kPa`, x: [0, xMax],
      y: [c.predicted_unconfined_strength_pa / 1000, c.predicted_unconfined_strength_pa / 1000], color: '#d9480f', dash: [2, 4], width: 2 });
  const fsBreaks = breakMarkers([['free-standing', c.wire_breaks]]);
  markers.push(...fsBreaks);
  const note = [c.shape === 'rising' ? 'The curve still rises at the end: the strength is a lower bound.' : '',
    c.definition || '', fsBreaks.length ? 'Dashed lines after the strength\'s: the wire broke there.' : ''].filter(Boolean).join(' ');
  const box = linePlot(grid, { id: 'plot-fs-stress', title: 'Unconfined compression: axial stress σ₁ against axial strain',
    xLabel: 'axial strain ε₁', yLabel: 'σ₁ [kPa]', series: curves, markers, note, swatches: true });
  box.wiredemPlot.strength = { value_pa: c.unconfined_strength_pa ?? null, shape: c.shape ?? null,
    strain: c.strain_at_failure ?? null, predicted_pa: c.predicted_unconfined_strength_pa ?? null };
  box.wiredemPlot.breaks = fsBreaks.map((m) => m.x);

  // Radius against height: before the removal, settled, at failure, at the end.
  const profiles = (test && test.profiles) || {};
  const named = [['profile_before', 'before the removal'], ['profile_settled', 'settled'],
    ['profile_at_peak', 'at the largest σ₁ (failure)'], ['profile_at_end', 'at the end of the compression']];
  const shapes = named.filter(([k]) => profiles[k]).map(([k, label]) => ({ label, key: k,
    x: profiles[k].height_m.map((h) => h * 1000), y: profiles[k].radius_m.map((r) => r * 1000) }));
  const profileBox = linePlot(grid, { id: 'plot-fs-profile', title: 'Column radius against height',
    xLabel: 'height above the bottom plate [mm]', yLabel: 'equivalent radius [mm]', series: shapes, swatches: true,
    note: 'Equivalent radius √(2⟨ρ²⟩) + ⟨r⟩ of the standing grains in slices of one grain diameter (a bulge shows as a rise at mid-height).' });
  profileBox.wiredemPlot.profiles = shapes.map((s) => s.key);

  // The wire's tension along its length at the largest σ₁.
  const w = test && test.wire_at_peak;
  const wireBox = linePlot(grid, { id: 'plot-fs-wire', title: 'Wire tension along its length at the largest σ₁',
    xLabel: 'distance along the wire [mm]', yLabel: 'tension [mN]',
    series: w ? [{ label: 'segment tension E_w π r_w² ε', x: w.distance_m.map((d) => d * 1000), y: w.tension_n.map((t) => t * 1000) }] : [],
    note: w ? `Segment k at (k + ½) l_w, l_w = ${mm(w.segment_length_m)} mm; negative: compressed.` : 'No wire, or no compression.' });
  wireBox.wiredemPlot.segments = w ? w.tension_n.length : 0;
}

/// The pull-out (docs/model.md, "Pulling the wire out"): the pull force (the
/// drive's reaction, a mean over each row's interval) and the end segment's
/// tension along the pull against the pulled length, one point per row of
/// GET …/free_standing's `pull_out` (`rows`), the peak from the summary
/// (`po`) drawn at its value and marked at its pulled length, and the force
/// that accelerating the wire takes in the ramp (`ramp_inertia_n`): a peak of
/// that order during the ramp is the wire's inertia.
function renderPullOut(grid, po, rows) {
  const column = (k) => (rows && rows[k] ? rows[k].values : []);
  const x = column('pulled_length_m').map((v) => v * 1000);
  const curves = [
    { label: 'pull force (the drive\'s reaction)', x, y: column('pull_force_n') },
    { label: 'end segment\'s tension along the pull', x, y: column('end_tension_n'), dash: [6, 3] },
  ];
  const xMax = Math.max(0, ...x.filter(Number.isFinite));
  const markers = [];
  if (po.peak_pull_force_n != null) {
    curves.push({ label: `peak ${num(po.peak_pull_force_n, 4)} N`, x: [0, xMax], y: [po.peak_pull_force_n, po.peak_pull_force_n],
      color: '#1d2330', dash: [8, 4], width: 2 });
    if (po.pulled_length_at_peak_m != null) markers.push({ x: po.pulled_length_at_peak_m * 1000, label: `peak at ${mm(po.pulled_length_at_peak_m)} mm` });
  }
  if (Number.isFinite(po.ramp_inertia_n))
    curves.push({ label: `accelerating the wire in the ramp: ${num(po.ramp_inertia_n, 3)} N`, x: [0, xMax],
      y: [po.ramp_inertia_n, po.ramp_inertia_n], color: '#d9480f', dash: [2, 4], width: 2 });
  const box = linePlot(grid, { id: 'plot-fs-pull', title: 'Pulling the wire out: force against pulled length',
    xLabel: 'pulled length [mm]', yLabel: 'force [N]', series: curves, markers, swatches: true,
    note: `One point per row (means over its sample interval). Ended by ${po.end ?? '—'}${po.wire_broke ? '; the wire broke' : ''}.` });
  box.wiredemPlot.rows = x.length;
  box.wiredemPlot.peak = { force_n: po.peak_pull_force_n ?? null, length_m: po.pulled_length_at_peak_m ?? null };
}

/// What gave way at the peak (a test's peak_failure, docs/results.md), for people.
export function failureText(f) {
  return { grains: 'the grains (wire whole)', wire: 'the wire (a break at the peak)',
    grains_after_break: 'the grains, after the wire broke' }[f] ?? (f == null ? '—' : String(f));
}

/// How the unconfined compression failed (compression.failure_mode, docs/model.md
/// "How it failed"), with what the rule read: the grains spilled and the widest slice's gain.
export function failureModeText(c) {
  const mode = { wire_break: 'the wire broke at the peak', grains_spilling: 'grains spilling', bulging: 'bulging',
    unresolved: 'not resolved by the record' }[c.failure_mode] ?? String(c.failure_mode);
  const spilled = c.spilled_fraction != null ? `${num(c.spilled_fraction * 100, 3)} %` : '—';
  return `${mode} (spilled ${spilled} of the grains, widest slice +${mm(c.bulge_m)} mm)`;
}

/// Plot markers for the breaks of `[[label, wire_breaks]]`: one vertical
/// line per break at its axial strain; the first break of each test says
/// how many there are (a label per break would pile up).
function breakMarkers(tests) {
  const out = [];
  for (const [label, breaks] of tests) {
    (breaks || []).forEach((b, i) => out.push({ x: b.axial_strain,
      label: i ? '' : `${label}: wire broke ${breaks.length === 1 ? 'once' : `${breaks.length} times`} from ε₁ = ${num(b.axial_strain, 3)}` }));
  }
  return out;
}

/// A breakable or cut wire (specimen.wire.breaking_strain, cuts_at_m,
/// cut_every_loops): what gave way at each test's peak (peak_failure), every
/// break of every test (time since the test started, the test's axial
/// strain, the position along the wire as its rest length to the segment's
/// middle, the segment and its strain when it broke), and the prepared
/// wire's pieces with their lengths (summary.specimen.wire_pieces). Nothing
/// for an unbreakable wire that was not cut.
export function renderWireParts(body, summary) {
  const sp = (summary && summary.specimen) || {};
  const tests = (summary && summary.tests) || [];
  const fs = summary && summary.free_standing && summary.free_standing.compression;
  const rows = tests.map((t) => [kPaLabel(t.confining_pressure_pa), t, String(t.confining_pressure_pa)]);
  if (fs) rows.push(['free-standing compression', fs, 'free_standing']);
  const breakable = rows.some(([, t]) => t.peak_failure !== undefined || t.wire_breaks !== undefined);
  if (!breakable && !sp.wire_pieces) return;
  const section = el('div', { id: 'wire-parts' });
  body.append(el('h2', {}, 'Wire breaks and pieces'), section);
  if (breakable) {
    section.append(el('table', { id: 'wire-failure-table' },
      el('thead', {}, el('tr', {}, ['test', 'failed at the peak by', 'breaks'].map((h) => el('th', {}, h)))),
      el('tbody', {}, rows.map(([label, t, key]) => el('tr', { 'data-test': key }, el('td', {}, label),
        el('td', { 'data-key': 'peak_failure', 'data-value': t.peak_failure ?? '' }, failureText(t.peak_failure)),
        el('td', { class: 'num', 'data-key': 'breaks' }, (t.wire_breaks || []).length))))));
    const all = rows.flatMap(([label, t, key]) => (t.wire_breaks || []).map((b) => [label, key, b]));
    section.append(all.length ? el('table', { id: 'wire-breaks-table' },
      el('thead', {}, el('tr', {}, ['test', 'time [s]', 'axial strain ε₁', 'position along the wire [mm]', 'segment', 'segment strain'].map((h) => el('th', {}, h)))),
      el('tbody', {}, all.map(([label, key, b]) => el('tr', { 'data-test': key },
        el('td', {}, label), el('td', { class: 'num', 'data-key': 'time_s' }, num(b.time_s, 4)),
        el('td', { class: 'num', 'data-key': 'axial_strain' }, num(b.axial_strain, 4)),
        el('td', { class: 'num', 'data-key': 'position_m' }, mm(b.position_m)),
        el('td', { class: 'num', 'data-key': 'segment' }, b.segment),
        el('td', { class: 'num', 'data-key': 'segment_strain' }, num(b.segment_strain, 4))))))
      : el('p', { class: 'muted', id: 'wire-breaks-none' }, 'The wire broke in no test.'));
  }
  const pieces = sp.wire_pieces;
  if (pieces) {
    section.append(el('div', { class: 'figures', id: 'wire-pieces-figures' },
      figure('pieces', pieces.length, 'wire_pieces'),
      figure('segments cut', sp.wire_cuts ?? '—', 'wire_cuts'),
      figure('broke in the preparation', sp.wire_breaks_in_preparation ?? '—', 'wire_breaks_in_preparation')),
    el('table', { id: 'wire-pieces-table' },
      el('thead', {}, el('tr', {}, ['piece', 'first node', 'nodes', 'rest length [mm]', 'length along its nodes [mm]'].map((h) => el('th', {}, h)))),
      el('tbody', {}, pieces.map((p, i) => el('tr', { 'data-piece': i },
        el('td', { class: 'num' }, i + 1), el('td', { class: 'num' }, p.first_node), el('td', { class: 'num' }, p.nodes),
        el('td', { class: 'num', 'data-key': 'rest_length_m' }, mm(p.rest_length_m)),
        el('td', { class: 'num', 'data-key': 'length_m' }, mm(p.length_m)))))),
    el('p', { class: 'muted' }, 'The prepared wire\'s pieces in chain order, before any test (a piece of one node is a node between two removed segments).'));
  }
}

/// A job with a grain-size curve (specimen.grain_sizes): the sizes drawn
/// against those asked for (D10, D50, D60, the uniformity coefficient C_u =
/// D60/D10, by mass) and the Kolmogorov–Smirnov distance between the drawn
/// and requested number distributions beside the value a true draw exceeds
/// with probability 1 % (summary.specimen.grain_sizes; docs/model.md, "Size
/// distribution"). Nothing without a curve.
export function renderGrainSizes(body, summary) {
  const g = summary && summary.specimen && summary.specimen.grain_sizes;
  if (!g) return;
  const rows = [['D10 [mm]', 'd10_m', 1000], ['D50 [mm]', 'd50_m', 1000], ['D60 [mm]', 'd60_m', 1000], ['C_u = D60/D10', 'uniformity_coefficient', 1]];
  const within = g.ks_distance != null && g.ks_critical_1pct != null ? g.ks_distance <= g.ks_critical_1pct : null;
  body.append(el('h2', {}, 'Grain sizes'), el('table', { id: 'grain-sizes-table' },
    el('thead', {}, el('tr', {}, ['', 'requested', `drawn (${g.grains ?? '—'} grains)`].map((h) => el('th', {}, h)))),
    el('tbody', {}, rows.map(([label, key, scale]) => el('tr', { 'data-key': key }, el('td', {}, label),
      el('td', { class: 'num', 'data-which': 'requested' }, num((g.requested || {})[key] * scale, 4)),
      el('td', { class: 'num', 'data-which': 'drawn' }, num((g.drawn || {})[key] * scale, 4)))))),
  el('p', { class: 'muted', id: 'grain-sizes-ks' }, `Kolmogorov–Smirnov distance of the drawn sizes from the curve: ${num(g.ks_distance, 3)} `
    + `(a true draw of this many grains exceeds ${num(g.ks_critical_1pct, 3)} with probability 1 %${within === false ? ': this one does' : ''}).`));
}
