// Several finished jobs side by side: their Mohr–Coulomb envelopes and q–ε
// curves overlaid, and φ and c in one table (how wire patterns are compared).
import { json } from './api.js';
import { el, replace, num, kpa } from './dom.js';
import { linePlot, palette } from './plots.js';
import { loadingRows, kPaLabel } from './results_view.js';

export function show(main, ids) {
  main.append(el('h1', {}, 'Compare jobs'));
  const picker = el('div');
  const out = el('div');
  main.append(picker, out);
  let stopped = false;

  (async () => {
    // The choice: every succeeded job, the ones in the address ticked.
    try {
      const page = await json('/v1/jobs?state=succeeded&limit=500');
      if (stopped) return;
      const chosen = new Set(ids);
      const boxes = page.jobs.map((j) => el('label', { class: 'pick' },
        el('input', { type: 'checkbox', value: j.id, checked: chosen.has(j.id) }), ` ${j.name || j.id} `));
      replace(picker, el('div', { class: 'toolbar' }, boxes.length ? boxes : el('span', { class: 'muted' }, 'No succeeded jobs yet.'),
        el('button', { class: 'primary', onclick: () => {
          const picked = [...picker.querySelectorAll('input:checked')].map((b) => b.value);
          location.hash = `#/compare/${picked.join(',')}`;
        } }, 'Compare')));
    } catch (e) {
      replace(picker, el('div', { class: 'error-box' }, e.message));
    }
    if (!ids.length) return;
    try {
      const jobs = await Promise.all(ids.map(async (id) => {
        const base = `/v1/jobs/${encodeURIComponent(id)}`;
        const [job, summary, { tests }] = await Promise.all([json(base), json(`${base}/summary`), json(`${base}/tests`)]);
        const series = await Promise.all(tests.map((t) => json(`${t.series_url}?max_points=500&columns=axial_strain,deviatoric_stress_pa,phase`)));
        return { job, summary, tests, series };
      }));
      if (stopped) return;
      render(out, jobs);
    } catch (e) {
      replace(out, el('div', { class: 'error-box' }, `Cannot compare: ${e.message}`));
    }
  })();
  return () => { stopped = true; };
}

function render(out, jobs) {
  out.append(el('table', { id: 'compare-table' },
    el('thead', {}, el('tr', {}, ['job', 'pattern', 'φ [°]', 'c [kPa]', 'R²', 'α [°]', 'φ max q [°]', 'c max q [kPa]', 'grain fraction', 'warnings'].map((h) => el('th', {}, h)))),
    el('tbody', {}, jobs.map(({ job, summary }) => {
      const mc = summary.mohr_coulomb || {}, mq = summary.mohr_coulomb_max_q || {};
      return el('tr', { 'data-id': job.id },
        el('td', {}, el('a', { href: `#/jobs/${job.id}` }, job.name || job.id)),
        el('td', {}, summary.wire?.pattern ?? '—'),
        el('td', { class: 'num', 'data-key': 'friction_angle_deg' }, num(mc.friction_angle_deg, 4)),
        el('td', { class: 'num', 'data-key': 'cohesion_pa' }, kpa(mc.cohesion_pa)),
        el('td', { class: 'num' }, num(mc.r_squared, 4)),
        el('td', { class: 'num' }, num(mc.paper_top_line_angle_deg, 4)),
        el('td', { class: 'num' }, num(mq.friction_angle_deg, 4)),
        el('td', { class: 'num' }, kpa(mq.cohesion_pa)),
        el('td', { class: 'num' }, num(summary.specimen?.grain_volume_fraction, 4)),
        el('td', { class: 'num' }, (summary.warnings || []).length));
    }))));

  const grid = el('div', { class: 'grid' });
  out.append(el('h2', {}, 'Envelopes and curves'), grid);
  const sigmaMax = Math.max(1, ...jobs.flatMap(({ summary }) => (summary.tests || []).map((t) => (t.yield?.sigma1_pa ?? t.sigma1_pa ?? 0) / 1000))) * 1.05;
  const envelopes = jobs.filter(({ summary }) => summary.mohr_coulomb?.friction_angle_deg != null).map(({ job, summary }, i) => {
    const mc = summary.mohr_coulomb;
    const c = mc.cohesion_pa / 1000, tanPhi = Math.tan((mc.friction_angle_deg * Math.PI) / 180);
    return { label: `${job.name || job.id}: φ = ${num(mc.friction_angle_deg, 3)}°, c = ${num(c, 3)} kPa`, x: [0, sigmaMax], y: [c, c + sigmaMax * tanPhi], color: palette[i % palette.length] };
  });
  linePlot(grid, { id: 'compare-envelopes', title: 'Mohr–Coulomb envelopes (yield)', xLabel: 'σ [kPa]', yLabel: 'τ [kPa]', series: envelopes });
  const curves = [];
  jobs.forEach(({ job, tests, series }, j) => tests.forEach((t, i) => {
    const rows = loadingRows(series[i]);
    curves.push({ label: `${job.name || job.id}, ${kPaLabel(t.attributes.confining_pressure_pa)}`, color: palette[j % palette.length], dash: i ? [2 + 3 * i, 3] : undefined,
      x: rows.map((r) => series[i].columns.axial_strain[r]), y: rows.map((r) => series[i].columns.deviatoric_stress_pa[r] / 1000) });
  }));
  linePlot(grid, { id: 'compare-q', title: 'q against axial strain (loading)', xLabel: 'axial strain ε₁', yLabel: 'q [kPa]', series: curves });
}
