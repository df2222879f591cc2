// Several finished jobs side by side: their Mohr–Coulomb envelopes and q–ε
// curves overlaid, and φ and c in one table (how wire patterns are compared).
// A job is named by its name, the start of its id and when it finished (two
// jobs of one name stay apart); in the curves each job has a colour and each
// confining pressure a dash, both in the legend.
import { json } from './api.js';
import { el, replace, num, kpa } from './dom.js';
import { linePlot, palette } from './plots.js';
import { loadingRows, kPaLabel, fitCaveats } from './results_view.js';

/// Dash per confining pressure, by rank (solid, dashed, dotted, dash-dot, long dash).
const dashes = [undefined, [10, 5], [2, 4], [12, 4, 2, 4], [20, 6]];

/// "name · 0123abcd · 2026-12-06 04:31": what tells two jobs of one name apart.
export function jobLabel(job) {
  const when = (job.finished_at || job.created_at || '').replace('T', ' ').slice(0, 16);
  return [job.name || '(no name)', job.id.slice(0, 8), when].filter(Boolean).join(' · ');
}

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
      const boxes = page.jobs.map((j) => el('label', { class: 'pick', title: j.id },
        el('input', { type: 'checkbox', value: j.id, checked: chosen.has(j.id) }), ` ${jobLabel(j)} `));
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
  // φ, c and R² of a fit with caveats are marked ⚠, the caveats in the cell's title.
  const fitCell = (mc, key, text) => {
    const caveats = fitCaveats(mc);
    return el('td', { class: caveats.length ? 'num flagged' : 'num', 'data-key': key, 'data-caveats': caveats.map((c) => c.code).join(' ') || undefined,
      title: caveats.map((c) => c.message).join('\n') || undefined }, caveats.length ? `${text} ⚠` : text);
  };
  out.append(el('table', { id: 'compare-table' },
    el('thead', {}, el('tr', {}, ['job', 'pattern', 'φ [°]', 'c [kPa]', 'R²', 'φ, c with c ≥ 0', 'φ with c = 0 [°]', 'α [°]', 'φ max q [°]', 'c max q [kPa]', 'grain fraction', 'warnings'].map((h) => el('th', {}, h)))),
    el('tbody', {}, jobs.map(({ job, summary }) => {
      const mc = summary.mohr_coulomb || {}, mq = summary.mohr_coulomb_max_q || {};
      const nn = mc.nonnegative || {}, c0 = mc.cohesionless || {};
      return el('tr', { 'data-id': job.id },
        el('td', {}, el('a', { href: `#/jobs/${job.id}` }, jobLabel(job))),
        el('td', {}, summary.wire?.pattern ?? '—'),
        fitCell(mc, 'friction_angle_deg', num(mc.friction_angle_deg, 4)),
        fitCell(mc, 'cohesion_pa', kpa(mc.cohesion_pa)),
        fitCell(mc, 'r_squared', num(mc.r_squared, 4)),
        el('td', { class: 'num', 'data-key': 'nonnegative' }, `${num(nn.friction_angle_deg, 4)}°, ${kpa(nn.cohesion_pa)} kPa`),
        el('td', { class: 'num', 'data-key': 'cohesionless_friction_angle_deg' }, num(c0.friction_angle_deg, 4)),
        el('td', { class: 'num' }, num(mc.paper_top_line_angle_deg, 4)),
        fitCell(mq, 'max_q_friction_angle_deg', num(mq.friction_angle_deg, 4)),
        fitCell(mq, 'max_q_cohesion_pa', kpa(mq.cohesion_pa)),
        el('td', { class: 'num' }, num(summary.specimen?.grain_volume_fraction, 4)),
        el('td', { class: 'num' }, (summary.warnings || []).length));
    }))));

  const grid = el('div', { class: 'grid' });
  out.append(el('h2', {}, 'Envelopes and curves'), grid);
  const sigmaMax = Math.max(1, ...jobs.flatMap(({ summary }) => (summary.tests || []).map((t) => (t.yield?.sigma1_pa ?? t.sigma1_pa ?? 0) / 1000))) * 1.05;
  const envelopes = jobs.map((j, i) => ({ ...j, colour: palette[i % palette.length] }))
    .filter(({ summary }) => summary.mohr_coulomb?.friction_angle_deg != null).map(({ job, summary, colour }) => {
      const mc = summary.mohr_coulomb;
      const c = mc.cohesion_pa / 1000, tanPhi = Math.tan((mc.friction_angle_deg * Math.PI) / 180);
      return { label: `${jobLabel(job)}: φ = ${num(mc.friction_angle_deg, 3)}°, c = ${num(c, 3)} kPa${fitCaveats(mc).length ? ' ⚠' : ''}`,
        x: [0, sigmaMax], y: [c, c + sigmaMax * tanPhi], color: colour };
    });
  linePlot(grid, { id: 'compare-envelopes', title: 'Mohr–Coulomb envelopes (yield; ⚠ an unconstrained fit with caveats)', xLabel: 'σ [kPa]', yLabel: 'τ [kPa]', series: envelopes, swatches: true });
  // The pressures of all jobs by rank, one dash each: the same σ₃ has the same dash in every job.
  const pressures = [...new Set(jobs.flatMap(({ tests }) => tests.map((t) => t.attributes.confining_pressure_pa)))].sort((a, b) => a - b);
  const curves = [];
  jobs.forEach(({ job, tests, series }, j) => tests.forEach((t, i) => {
    const rows = loadingRows(series[i]);
    const rank = pressures.indexOf(t.attributes.confining_pressure_pa);
    curves.push({ label: `${jobLabel(job)}, ${kPaLabel(t.attributes.confining_pressure_pa)}`, color: palette[j % palette.length], dash: dashes[rank % dashes.length],
      width: 2, x: rows.map((r) => series[i].columns.axial_strain[r]), y: rows.map((r) => series[i].columns.deviatoric_stress_pa[r] / 1000) });
  }));
  linePlot(grid, { id: 'compare-q', title: 'q against axial strain (loading): colour per job, dash per σ₃', xLabel: 'axial strain ε₁', yLabel: 'q [kPa]', series: curves, swatches: true });
}
