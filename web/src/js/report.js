// The offline report (`wiredem report OUT/`, docs/web.md): the job page's
// results drawn from the data the command embedded in the file, with no
// server. The command inlines this module with dom.js, plots.js and
// results_view.js (imports and exports stripped) and uPlot's browser build.
import { el } from './dom.js';
import { renderSummary, renderCurves, renderWire, renderFreeStanding, renderWireParts, renderGrainSizes } from './results_view.js';

const data = JSON.parse(document.getElementById('report-data').textContent);
const main = document.getElementById('main');
document.title = `wiredem report: ${data.name}`;
main.append(el('h1', { id: 'job-name' }, data.name), el('p', { class: 'muted' }, `${data.source} · ${data.written_by}`));
renderSummary(main, data.summary);
renderGrainSizes(main, data.summary);
renderCurves(main, data.summary, data.tests, data.series);
if (data.free_standing) renderFreeStanding(main, data.summary, data.free_standing.test, data.free_standing.series);
renderWireParts(main, data.summary);
if (data.wire) {
  const grid = el('div', { class: 'grid' });
  main.append(el('h2', {}, 'Wire strain'), grid);
  renderWire(grid, data.summary, data.wire.label, data.wire.node_position_m, data.wire.segment_strain, data.wire.autocorrelation);
}
main.dataset.rendered = 'true';
