// The job list: live (polled every second), filtered by state, with a
// progress bar, cancel, and a choice of finished jobs to compare.
import { json, cancelJob } from './api.js';
import { el, replace, seconds } from './dom.js';

const states = ['', 'queued', 'preparing', 'running', 'succeeded', 'failed', 'cancelled'];
const finalStates = new Set(['succeeded', 'failed', 'cancelled']);

export function show(main) {
  const chosen = new Set();
  const filter = el('select', { id: 'state-filter', 'aria-label': 'state' },
    states.map((s) => el('option', { value: s }, s || 'all states')));
  const compareButton = el('button', { id: 'compare-button', disabled: true,
    onclick: () => { location.hash = `#/compare/${[...chosen].join(',')}`; } }, 'Compare chosen');
  const body = el('tbody');
  const error = el('div');
  main.append(el('h1', {}, 'Jobs'),
    el('div', { class: 'toolbar' }, el('label', {}, 'Show ', filter), compareButton, el('a', { href: '#/submit' }, 'Submit a job')),
    error,
    el('table', { id: 'jobs' }, el('thead', {}, el('tr', {}, ['', 'name', 'state', 'stage', 'progress', 'ETA', 'message', 'created', ''].map((h) => el('th', {}, h)))), body));

  const row = (j) => {
    const pick = el('input', { type: 'checkbox', 'aria-label': 'compare', checked: chosen.has(j.id), disabled: j.state !== 'succeeded',
      onchange: (ev) => { if (ev.target.checked) chosen.add(j.id); else chosen.delete(j.id); compareButton.disabled = chosen.size < 1; } });
    const cancel = finalStates.has(j.state) ? '' : el('button', { class: 'cancel', onclick: async (ev) => {
      ev.target.disabled = true;
      try { await cancelJob(j.id); } catch (e) { replace(error, el('div', { class: 'error-box' }, e.message)); }
      refresh();
    } }, 'Cancel');
    return el('tr', { 'data-id': j.id, 'data-state': j.state },
      el('td', {}, pick),
      el('td', { class: 'name' }, el('a', { href: `#/jobs/${j.id}` }, j.name || j.id)),
      el('td', {}, el('span', { class: `state state-${j.state}` }, j.state)),
      el('td', {}, j.stage || ''),
      el('td', {}, el('progress', { max: 1, value: j.progress ?? 0 }), ` ${Math.round((j.progress ?? 0) * 100)} %`),
      el('td', { class: 'num' }, finalStates.has(j.state) ? '' : seconds(j.eta_s)),
      el('td', { class: 'message' }, j.error || j.message || ''),
      el('td', {}, new Date(j.created_at).toLocaleString()),
      el('td', {}, cancel));
  };

  let timer = null;
  let stopped = false;
  async function refresh() {
    clearTimeout(timer);
    try {
      const state = filter.value;
      const page = await json(`/v1/jobs?limit=100${state ? `&state=${state}` : ''}`);
      if (stopped) return;
      replace(body, page.jobs.length ? page.jobs.map(row) : el('tr', {}, el('td', { colspan: 9, class: 'muted' }, 'No jobs.')));
      replace(error);
    } catch (e) {
      if (!stopped) replace(error, el('div', { class: 'error-box' }, `Cannot list jobs: ${e.message}`));
    }
    if (!stopped) timer = setTimeout(refresh, 1000);
  }
  filter.addEventListener('change', refresh);
  refresh();
  return () => { stopped = true; clearTimeout(timer); };
}
