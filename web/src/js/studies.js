// Parameter studies (docs/studies.md): the list (#/studies), and one study
// (#/studies/{id}): its points with their jobs' states and progress, the
// summary table — per point φ, c and R², per group of seeds φ and c as
// mean ± sd (n) — with links to each job, cancel, and the compare view
// pre-filled with its succeeded jobs. Polled while any of its jobs runs.
import { json } from './api.js';
import { el, replace, num, kpa } from './dom.js';

const finalStates = new Set(['succeeded', 'failed', 'cancelled']);
const stateNames = ['queued', 'preparing', 'running', 'succeeded', 'failed', 'cancelled'];

/// "3 queued · 1 running · 2 succeeded": the non-zero counts of jobs_by_state.
const countsText = (byState) => stateNames.filter((s) => byState[s]).map((s) => `${byState[s]} ${s}`).join(' · ') || 'no jobs';

/// Polls `refresh` every `ms` until stop() or until it returns false.
function poller(refresh, ms) {
  let timer = null;
  let stopped = false;
  const tick = async () => {
    let again = true;
    try { again = await refresh(() => stopped); } catch (e) { console.warn(e); }
    if (!stopped && again !== false) timer = setTimeout(tick, ms);
  };
  tick();
  return () => { stopped = true; clearTimeout(timer); };
}

export function showList(main) {
  const body = el('tbody');
  const error = el('div');
  main.append(el('h1', {}, 'Studies'),
    el('p', { class: 'muted' }, 'A study is one job per point of a grid or list of job fields (submitted with wiredem study submit, or POST /v1/studies).'),
    error,
    el('table', { id: 'studies' }, el('thead', {}, el('tr', {}, ['name', 'points', 'jobs', 'created'].map((h) => el('th', {}, h)))), body));
  return poller(async (stopped) => {
    try {
      const page = await json('/v1/studies?limit=100');
      if (stopped()) return false;
      replace(body, page.studies.length ? page.studies.map((s) => el('tr', { 'data-id': s.id },
        el('td', { class: 'name' }, el('a', { href: `#/studies/${s.id}` }, s.name || s.id)),
        el('td', { class: 'num' }, s.points),
        el('td', { class: 'counts' }, countsText(s.jobs_by_state)),
        el('td', {}, new Date(s.created_at).toLocaleString()))) : el('tr', {}, el('td', { colspan: 4, class: 'muted' }, 'No studies.')));
      replace(error);
    } catch (e) {
      replace(error, el('div', { class: 'error-box' }, `Cannot list studies: ${e.message}`));
    }
    return true;
  }, 2000);
}

export function show(main, id) {
  const head = el('div');
  const body = el('div');
  main.append(head, body);
  const base = `/v1/studies/${encodeURIComponent(id)}`;
  return poller(async (stopped) => {
    let study, summary;
    try {
      [study, summary] = await Promise.all([json(base), json(`${base}/summary`)]);
    } catch (e) {
      if (!stopped()) replace(head, el('h1', {}, 'Study'), el('div', { class: 'error-box' }, e.message));
      return false;
    }
    if (stopped()) return false;
    const running = study.jobs.some((p) => p.job && !finalStates.has(p.job.state));
    renderHead(head, study, running);
    renderBody(body, study, summary);
    return running;
  }, 1000);
}

function renderHead(head, study, running) {
  const succeeded = study.jobs.filter((p) => p.job && p.job.state === 'succeeded').map((p) => p.job.id);
  const error = el('div');
  const cancel = running ? el('button', { id: 'cancel-study', onclick: async (ev) => {
    ev.target.disabled = true;
    try { await json(`/v1/studies/${encodeURIComponent(study.id)}`, { method: 'DELETE' }); } catch (e) {
      replace(error, el('div', { class: 'error-box' }, e.message));
    }
  } }, 'Cancel the study') : '';
  replace(head,
    el('h1', { id: 'study-name' }, study.name || study.id),
    el('div', { class: 'toolbar' },
      el('span', { id: 'study-counts' }, countsText(study.jobs_by_state)),
      succeeded.length ? el('a', { id: 'study-compare', href: `#/compare/${succeeded.join(',')}` }, `Compare its ${succeeded.length} succeeded jobs`) : '',
      cancel),
    error,
    el('p', { class: 'muted' }, `id ${study.id} · ${study.points} points · created ${new Date(study.created_at).toLocaleString()}`));
}

/// mean ± sd (n) of a group's figure, `scale` applied (Pa to kPa).
function spread(s, scale = 1) {
  if (!s || s.mean == null) return `— (${s ? s.n : 0})`;
  return `${num(s.mean * scale, 4)} ± ${s.sd == null ? '—' : num(s.sd * scale, 3)} (${s.n})`;
}

/// φ, c or R² of a point, marked ⚠ when its fit has caveats (the codes in the
/// title; the sentences are on the job's page).
function fitCell(row, key, text) {
  const caveats = row.fit_caveats || [];
  if (!caveats.length) return el('td', { class: 'num', 'data-key': key }, text);
  return el('td', { class: 'num flagged', 'data-key': key, 'data-caveats': caveats.join(' '),
    title: `an unconstrained fit: ${caveats.join(', ').replaceAll('_', ' ')} (the job's page says more)` }, `${text} ⚠`);
}

function renderBody(body, study, summary) {
  const rows = new Map(summary.points.map((p) => [p.index, p]));
  replace(body,
    el('h2', {}, 'Points'),
    el('table', { id: 'study-points' },
      el('thead', {}, el('tr', {}, ['#', 'point', 'job', 'state', 'progress', 'φ [°]', 'c [kPa]', 'R²', 'message'].map((h) => el('th', {}, h)))),
      el('tbody', {}, study.jobs.map((p) => {
        const job = p.job || {};
        const row = rows.get(p.index) || {};
        return el('tr', { 'data-index': p.index, 'data-state': job.state || '' },
          el('td', { class: 'num' }, p.index),
          el('td', { class: 'label' }, p.label),
          el('td', { class: 'name' }, job.id ? el('a', { href: `#/jobs/${job.id}` }, job.name || job.id) : '—'),
          el('td', {}, job.state ? el('span', { class: `state state-${job.state}` }, job.state) : '—'),
          el('td', {}, finalStates.has(job.state) ? '' : el('progress', { max: 1, value: job.progress ?? 0 })),
          fitCell(row, 'friction_angle_deg', num(row.friction_angle_deg, 4)),
          fitCell(row, 'cohesion_pa', kpa(row.cohesion_pa)),
          fitCell(row, 'r_squared', num(row.r_squared, 4)),
          el('td', { class: 'message' }, job.error || row.error || job.message || ''));
      }))),
    el('h2', {}, 'Over the seeds'),
    el('p', { class: 'muted' }, `Points equal but for seed, grouped: mean ± sample sd (n − 1; — below two) over the succeeded points, n of them. ${summary.definitions?.friction_angle_deg ?? ''}`),
    el('table', { id: 'study-groups' },
      el('thead', {}, el('tr', {}, ['group', 'points', 'succeeded', 'φ [°]', 'c [kPa]'].map((h) => el('th', {}, h)))),
      el('tbody', {}, summary.groups.map((g, i) => el('tr', { 'data-group': i },
        el('td', { class: 'label' }, Object.entries(g.values || {}).map(([k, v]) => `${k}=${JSON.stringify(v)}`).join(' ') || '(all)'),
        el('td', { class: 'num' }, g.points),
        el('td', { class: 'num' }, g.succeeded),
        el('td', { class: 'num', 'data-key': 'friction_angle_deg' }, spread(g.friction_angle_deg)),
        el('td', { class: 'num', 'data-key': 'cohesion_pa' }, spread(g.cohesion_pa, 1e-3)))))));
}
