// One job: its state (polled while it runs) and its curves growing as its
// tests run, then the summary, the plots, the 3D view and the downloads, all
// from the result data routes (docs/api.md).
import { json, blob, array, cancelJob } from './api.js';
import { el, replace, num, seconds, saveBlob } from './dom.js';
import { renderSummary, renderCurves, renderWire, renderFreeStanding, renderWireParts, renderGrainSizes, kPaLabel, curveColumns, freeStandingColumns } from './results_view.js';
import { View3d } from './view3d.js';

const finalStates = new Set(['succeeded', 'failed', 'cancelled']);

export function show(main, id) {
  const head = el('div');
  const body = el('div');
  main.append(head, body);
  let timer = null;
  let stopped = false;
  let view = null;
  let live = null;
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
    if (job.state === 'preparing' || job.state === 'running') {
      if (!live) live = new LiveCurves(body, job.id);
      try { await live.update(); } catch (e) { console.warn('live curves:', e.message); }
      if (stopped) return;
    }
    // A job cancelled or failed while its tests ran: its partial curves
    // stay (the routes answer 409 from now on), saying where the tests stopped.
    if (live && (job.state === 'cancelled' || job.state === 'failed')) live.ended(job.state);
    if (job.state === 'succeeded' && !shownResults) {
      shownResults = true;
      if (live) { live.dispose(); live = null; }
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
      finalStates.has(job.state) ? '' : el('p', { class: 'muted' }, 'The curves grow here as the tests run; the other results appear when the job has succeeded.'));
  }

  poll();
  return () => { stopped = true; clearTimeout(timer); if (view) view.dispose(); if (live) live.dispose(); };
}

/// The curves of a job that runs, from what its tests have recorded so far
/// (the data routes read the runner's per-test files: a running test's last
/// checkpoint, a finished test's file; marked partial), redrawn when they grew.
class LiveCurves {
  constructor(body, id) {
    this.id = id;
    this.box = el('div', { id: 'live-curves' });
    this.drawn = '';
    body.append(this.box);
  }

  async update() {
    const { tests } = await json(`/v1/jobs/${encodeURIComponent(this.id)}/tests`);
    const key = tests.map((t) => `${t.state}:${t.rows}`).join(',');
    if (key === this.drawn) return;
    // A running test has no volumetric strain yet (it is derived at the end): ask only for what it has.
    const series = await Promise.all(tests.map((t) => {
      const columns = curveColumns.split(',').filter((c) => t.columns.some((k) => k.name === c));
      return json(`${t.series_url}?max_points=1000&columns=${columns.join(',')}`);
    }));
    this.clear();
    this.drawn = key;
    this.tests = tests;
    this.box.append(this.note(null));
    renderCurves(this.box, null, tests, series);
  }

  /// What the curves are: the tests' states, or where they stopped if the job
  /// ended (`jobState` cancelled or failed; null while it runs).
  note(jobState) {
    const state = (t) => {
      if (jobState && t.state === 'waiting') return 'not started';
      if (t.state !== 'running') return t.state || 'finished';
      const at = t.reached ? ` t = ${num(t.reached.time_s, 3)} s, ε₁ = ${num(t.reached.axial_strain, 3)}` : '';
      return jobState ? `stopped${at ? ` at${at}` : ''}` : `running${at ? `, reached${at}` : ''}`;
    };
    return el('p', { class: 'muted', id: 'live-note', 'data-partial': this.tests.some((t) => t.partial) },
      jobState ? `Partial results: the job was ${jobState}; its tests had recorded this much: `
        : 'Partial results, as the tests have recorded them so far: ',
      this.tests.map((t) => `${kPaLabel(t.attributes.confining_pressure_pa)} ${state(t)}`).join('; '), '.');
  }

  ended(jobState) {
    const shown = this.box.querySelector('#live-note');
    if (shown && this.tests) shown.replaceWith(this.note(jobState));
  }

  clear() {
    for (const p of this.box.querySelectorAll('.plot')) if (p.uplot) p.uplot.destroy();
    replace(this.box);
  }

  dispose() {
    this.clear();
    this.box.remove();
  }
}

async function download(path, name) {
  saveBlob(await blob(path), name);
}

async function renderResults(body, job) {
  const base = `/v1/jobs/${job.id}`;
  const [summary, { tests }] = await Promise.all([json(`${base}/summary`), json(`${base}/tests`)]);
  const series = await Promise.all(tests.map((t) => json(`${t.series_url}?max_points=1000&columns=${curveColumns}`)));

  renderSummary(body, summary);
  renderGrainSizes(body, summary);

  body.append(el('h2', {}, 'Downloads'), el('div', { class: 'toolbar', id: 'downloads' },
    el('button', { onclick: () => download(`${base}/summary`, 'summary.json') }, 'summary.json'),
    el('button', { onclick: () => download(`${base}/result.h5`, 'result.h5') }, 'result.h5'),
    el('button', { onclick: () => download(`${base}/result.xdmf`, 'result.xdmf') }, 'result.xdmf (ParaView, beside result.h5)'),
    el('button', { id: 'download-report', onclick: () => download(`${base}/report.html`, 'report.html') }, 'report.html (offline report)')));

  renderCurves(body, summary, tests, series);
  if (summary.free_standing) {
    const fs = await json(`${base}/free_standing`);
    renderFreeStanding(body, summary, fs, await json(`${fs.series_url}?max_points=2000&columns=${freeStandingColumns}`));
  }
  renderWireParts(body, summary);

  const withWire = (summary.specimen && summary.specimen.wire_nodes > 1) && tests.some((t) => t.snapshots.length);
  const view = new View3d(body, job, tests, summary);
  if (withWire) await wireSection(body, tests, summary);
  await view.ready;
  return view;
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
    replace(grid);
    renderWire(grid, summary, o.label, nodes.data, strain.data, ac);
  }
  select.addEventListener('change', draw);
  await draw();
}

