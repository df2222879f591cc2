// One job: its state (polled while it runs), then the summary, the plots, the
// 3D view and the downloads, all from the result data routes (docs/api.md).
import { json, blob, array, cancelJob } from './api.js';
import { el, replace, num, kpa, seconds, figure, saveBlob } from './dom.js';
import { linePlot, mohrSemicircle } from './plots.js';
import { View3d } from './view3d.js';

const finalStates = new Set(['succeeded', 'failed', 'cancelled']);

/// Rows of the loading phase (phase 2): the curves against axial strain.
export function loadingRows(series) {
  const phase = series.columns.phase;
  return series.columns.axial_strain.map((_, i) => i).filter((i) => !phase || phase[i] === 2);
}

export const kPaLabel = (pa) => `σ₃ = ${num(pa / 1000, 4)} kPa`;

export function show(main, id) {
  const head = el('div');
  const body = el('div');
  main.append(head, body);
  let timer = null;
  let stopped = false;
  let view = null;
  let shownResults = false;

  async function poll() {
    clearTimeout(timer);
    let job;
    try {
      job = await json(`/v1/jobs/${encodeURIComponent(id)}`);
    } catch (e) {
      if (!stopped) replace(head, el('h1', {}, 'Job'), el('div', { class: 'error-box' }, e.message));
      return;
    }
    if (stopped) return;
    renderHead(job);
    if (job.state === 'succeeded' && !shownResults) {
      shownResults = true;
      try { view = await renderResults(body, job); } catch (e) {
        console.error(e);
        body.append(el('div', { class: 'error-box' }, `Cannot show the results: ${e.message}`));
      }
    }
    if (!finalStates.has(job.state)) timer = setTimeout(poll, 1000);
  }

  function renderHead(job) {
    const cancel = finalStates.has(job.state) ? '' : el('button', { id: 'cancel-job', onclick: async () => {
      try { await cancelJob(job.id); } catch (e) { head.append(el('div', { class: 'error-box' }, e.message)); }
      poll();
    } }, 'Cancel');
    replace(head,
      el('h1', { id: 'job-name' }, job.name || job.id),
      el('div', { class: 'toolbar' },
        el('span', { class: `state state-${job.state}`, id: 'job-state' }, job.state),
        job.stage && !finalStates.has(job.state) ? el('span', {}, `stage: ${job.stage}`) : '',
        finalStates.has(job.state) ? '' : el('progress', { max: 1, value: job.progress ?? 0 }),
        finalStates.has(job.state) ? '' : el('span', {}, `ETA ${seconds(job.eta_s)}`),
        finalStates.has(job.state) ? '' : el('span', { class: 'muted' }, job.message || ''),
        cancel),
      job.error ? el('div', { class: 'error-box', id: 'job-error' }, job.error) : '',
      el('p', { class: 'muted' }, `id ${job.id} · created ${new Date(job.created_at).toLocaleString()} · attempts ${job.attempts}`),
      finalStates.has(job.state) ? '' : el('p', { class: 'muted' }, 'Results appear here when the job has succeeded.'));
  }

  poll();
  return () => { stopped = true; clearTimeout(timer); if (view) view.dispose(); };
}

async function download(path, name) {
  saveBlob(await blob(path), name);
}

async function renderResults(body, job) {
  const base = `/v1/jobs/${job.id}`;
  const [summary, { tests }] = await Promise.all([json(`${base}/summary`), json(`${base}/tests`)]);
  const columns = 'axial_strain,deviatoric_stress_pa,stress_ratio,volumetric_strain,phase';
  const series = await Promise.all(tests.map((t) => json(`${t.series_url}?max_points=1000&columns=${columns}`)));

  // Warnings first: a result that was not quasi-static or not settled must not be read as if it were.
  if (summary.warnings && summary.warnings.length)
    body.append(el('div', { class: 'warnings', id: 'warnings' }, el('h2', {}, `Warnings (${summary.warnings.length})`),
      el('ul', {}, summary.warnings.map((w) => el('li', {}, w)))));

  const mc = summary.mohr_coulomb || {};
  const mcq = summary.mohr_coulomb_max_q || {};
  const sp = summary.specimen || {};
  body.append(el('h2', {}, 'Summary'),
    el('div', { class: 'figures', id: 'figures' },
      figure('φ (yield) [°]', num(mc.friction_angle_deg, 4), 'friction_angle_deg'),
      figure('c (yield) [kPa]', kpa(mc.cohesion_pa), 'cohesion_pa'),
      figure('R²', num(mc.r_squared, 4), 'r_squared'),
      figure('α, slope of the tops [°]', num(mc.paper_top_line_angle_deg, 4), 'paper_top_line_angle_deg'),
      figure('φ (max q) [°]', num(mcq.friction_angle_deg, 4), 'max_q_friction_angle_deg'),
      figure('grain volume fraction', num(sp.grain_volume_fraction, 4), 'grain_volume_fraction'),
      figure('wire volume fraction', num(sp.wire_volume_fraction, 4), 'wire_volume_fraction'),
      figure('grains', sp.grains ?? '—', 'grains'),
      figure('wire nodes', sp.wire_nodes ?? '—', 'wire_nodes'),
      figure('wire autocorrelation lag [mm]', summary.wire && summary.wire.autocorrelation_lag_m != null ? num(summary.wire.autocorrelation_lag_m * 1000, 4) : '—', 'autocorrelation_lag_m')),
    mc.error ? el('div', { class: 'error-box' }, `Mohr–Coulomb fit: ${mc.error}`) : '',
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

  body.append(el('h2', {}, 'Downloads'), el('div', { class: 'toolbar', id: 'downloads' },
    el('button', { onclick: () => download(`${base}/summary`, 'summary.json') }, 'summary.json'),
    el('button', { onclick: () => download(`${base}/result.h5`, 'result.h5') }, 'result.h5'),
    el('button', { onclick: () => download(`${base}/result.xdmf`, 'result.xdmf') }, 'result.xdmf (ParaView, beside result.h5)')));

  body.append(el('h2', {}, 'Curves'));
  const grid = el('div', { class: 'grid' });
  body.append(grid);
  const curves = (column, scale = 1) => tests.map((t, i) => {
    const rows = loadingRows(series[i]);
    return { label: kPaLabel(t.attributes.confining_pressure_pa),
      x: rows.map((r) => series[i].columns.axial_strain[r]), y: rows.map((r) => series[i].columns[column][r] * scale) };
  });
  linePlot(grid, { id: 'plot-q', title: 'Deviatoric stress q against axial strain (loading)', xLabel: 'axial strain ε₁', yLabel: 'q [kPa]', series: curves('deviatoric_stress_pa', 1e-3) });
  linePlot(grid, { id: 'plot-ratio', title: 'Stress ratio (σ₁ − σ₃)/(σ₁ + σ₃) against axial strain', xLabel: 'axial strain ε₁', yLabel: 'stress ratio', series: curves('stress_ratio') });
  linePlot(grid, { id: 'plot-volumetric', title: 'Volumetric strain against axial strain', xLabel: 'axial strain ε₁', yLabel: 'volumetric strain', series: curves('volumetric_strain') });
  mohrPlot(grid, summary);

  const withWire = (summary.specimen && summary.specimen.wire_nodes > 1) && tests.some((t) => t.snapshots.length);
  const view = new View3d(body, job, tests);
  if (withWire) await wireSection(body, tests, summary);
  await view.ready;
  return view;
}

/// Mohr circles at yield (σ₃,eff and σ₁ of each test's yield state), the fitted
/// envelope τ = c + σ tan φ and the line through the circle tops t = c cos φ + p tan α.
export function mohrPlot(parent, summary, id = 'plot-mohr') {
  const mc = summary.mohr_coulomb || {};
  const states = (summary.tests || []).filter((t) => t.yield && t.yield.sigma1_pa != null);
  const series = states.map((t) => {
    const c = mohrSemicircle(t.yield.sigma3_effective_pa / 1000, t.yield.sigma1_pa / 1000);
    return { label: `yield at ${kPaLabel(t.confining_pressure_pa)}`, ...c };
  });
  const sigmaMax = Math.max(1, ...states.map((t) => t.yield.sigma1_pa / 1000)) * 1.05;
  if (mc.friction_angle_deg != null && mc.cohesion_pa != null) {
    const tanPhi = Math.tan((mc.friction_angle_deg * Math.PI) / 180);
    const c = mc.cohesion_pa / 1000;
    series.push({ label: `envelope φ = ${num(mc.friction_angle_deg, 3)}°, c = ${num(c, 3)} kPa`, x: [0, sigmaMax], y: [c, c + sigmaMax * tanPhi], color: '#1d2330', width: 2, envelope: true });
    if (mc.paper_top_line_angle_deg != null) {
      const tanAlpha = Math.tan((mc.paper_top_line_angle_deg * Math.PI) / 180);
      const a = c * Math.cos((mc.friction_angle_deg * Math.PI) / 180);
      series.push({ label: `slope of the tops α = ${num(mc.paper_top_line_angle_deg, 3)}° (not φ)`, x: [0, sigmaMax], y: [a, a + sigmaMax * tanAlpha], color: '#8250df', dash: [6, 4] });
    }
  }
  const box = linePlot(parent, { id, title: 'Mohr circles at yield', xLabel: 'σ [kPa]', yLabel: 'τ [kPa]', series, equalAspect: true,
    note: mc.states || '' });
  box.wiredemPlot.envelope = { friction_angle_deg: mc.friction_angle_deg, cohesion_pa: mc.cohesion_pa };
  return box;
}

async function wireSection(body, tests, summary) {
  const section = el('div', { id: 'wire-section' });
  body.append(el('h2', {}, 'Wire strain'), section);
  const options = [];
  tests.forEach((t, ti) => t.snapshots.forEach((s) => options.push({ ti, s, label: `${kPaLabel(t.attributes.confining_pressure_pa)}, ε₁ = ${num(s.axial_strain, 3)}` })));
  // Default: the last snapshot of the highest pressure, the one summary.wire's lag is read from.
  const select = el('select', { id: 'wire-snapshot', 'aria-label': 'snapshot' }, options.map((o, i) => el('option', { value: i }, o.label)));
  select.value = String(options.length - 1);
  const grid = el('div', { class: 'grid' });
  section.append(el('div', { class: 'toolbar' }, el('label', {}, 'Snapshot ', select)), grid);
  async function draw() {
    const o = options[Number(select.value)];
    const [strain, nodes, ac] = await Promise.all([
      array(`${o.s.url}/wire_segment_strain`),
      array(`${o.s.url}/wire_node_position_m`),
      json(`${o.s.url}/wire_autocorrelation`)]);
    const s = [0];
    for (let k = 1; k < strain.data.length; ++k) {
      const a = nodes.data.subarray(3 * k - 3, 3 * k), b = nodes.data.subarray(3 * k, 3 * k + 3);
      s.push(s[k - 1] + Math.hypot(b[0] - a[0], b[1] - a[1], b[2] - a[2]) * 1000);
    }
    replace(grid);
    linePlot(grid, { id: 'plot-wire-strain', title: 'Segment strain along the wire', xLabel: 'distance along the wire [mm]', yLabel: 'segment strain [10⁻³]',
      series: [{ label: o.label, x: s, y: Array.from(strain.data, (e) => e * 1000) }] });
    const lag = ac.first_maximum_lag_m;
    linePlot(grid, { id: 'plot-autocorrelation', title: 'Autocorrelation of the segment strain', xLabel: 'lag [mm]', yLabel: 'R(k)',
      series: [{ label: 'R(k)', x: ac.lag_m.map((l) => l * 1000), y: ac.coefficients }],
      markers: lag != null ? [{ x: lag * 1000, label: `first maximum ${num(lag * 1000, 3)} mm` }] : [],
      note: ac.error ? `No autocorrelation: ${ac.error}` : lag == null ? 'No local maximum after lag 0.' : `First maximum at ${num(lag * 1000, 4)} mm (summary: ${summary.wire && summary.wire.autocorrelation_lag_m != null ? num(summary.wire.autocorrelation_lag_m * 1000, 4) : '—'} mm, the end of the test at the highest pressure).` });
    grid.querySelector('#plot-autocorrelation').wiredemPlot.first_maximum_lag_m = lag;
  }
  select.addEventListener('change', draw);
  await draw();
}

