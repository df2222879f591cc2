// Line plots with uPlot (small, fast on thousands of points, draws on a
// canvas and sets no inline style attributes, so it lives under a strict CSP).
// Each plot leaves what it drew on its container as `wiredemPlot`
// ({title, series: [{label, x, y}]}): the browser tests read the page's data
// from there, not from pixels.
import uPlot from '../vendor/uPlot.esm.js';
import { el } from './dom.js';

export const palette = ['#1f6feb', '#d1242f', '#1a7f37', '#9a6700', '#8250df', '#bf3989', '#0a7e8c', '#57606a'];

/// Sorts a curve by x (uPlot joins series on a common ascending x).
function sorted(x, y) {
  const order = x.map((_, i) => i).filter((i) => Number.isFinite(x[i])).sort((a, b) => x[a] - x[b]);
  return [order.map((i) => x[i]), order.map((i) => (Number.isFinite(y[i]) ? y[i] : null))];
}

/// Draws `series` ([{label, x, y, color?, dash?, width?}]) into a new box in
/// `parent`. `markers`: vertical lines [{x, label}], each label a line below the
/// previous one's (markers a few pixels apart stay readable; '' for none). `equalAspect`: one unit
/// of x as long as one of y (Mohr circles stay round), y from `yMin` (≤ 0) up,
/// with a line along y = 0 when yMin < 0.
/// `swatches`: a legend of its own below the plot, each entry a short line in
/// the series' colour, width and dash (uPlot's legend shows the colour only).
export function linePlot(parent, { id, title, xLabel, yLabel, series, markers = [], equalAspect = false, yMin = 0, note, height = 320, swatches = false }) {
  const box = el('div', { class: 'plot', id }, el('h3', {}, title));
  parent.append(box);
  box.wiredemPlot = { title, xLabel, yLabel, series: series.map((s) => ({ label: s.label, x: [...s.x], y: [...s.y] })) };
  if (series.length === 0 || series.every((s) => s.x.length === 0)) {
    box.append(el('p', { class: 'muted' }, 'Nothing to draw.'));
    return box;
  }
  const tables = series.map((s) => [...sorted(s.x, s.y)].map((a) => Float64Array.from(a, (v) => (v === null ? NaN : v))));
  const data = uPlot.join(tables.map(([x, y]) => [Array.from(x), Array.from(y, (v) => (Number.isNaN(v) ? null : v))]));
  const width = Math.max(320, (box.clientWidth || 600) - 20);  // the box is in the page already: its grid cell's width
  const scales = { x: { time: false } };
  if (equalAspect) {
    const xs = series.flatMap((s) => s.x).filter(Number.isFinite);
    const xmax = Math.max(...xs) * 1.05;
    const xmin = Math.min(0, ...xs);
    scales.x.range = () => [xmin, xmax];
    scales.y = { range: () => [yMin, yMin + ((xmax - xmin) * (height - 60)) / (width - 80)] };
  }
  const opts = {
    width, height, scales,
    legend: { live: false, show: !swatches },
    cursor: { drag: { x: true, y: true } },
    axes: [{ label: xLabel }, { label: yLabel, size: 70 }],
    series: [{ label: xLabel }, ...series.map((s, i) => ({
      label: s.label, stroke: s.color || palette[i % palette.length], width: s.width || 1.5,
      dash: s.dash, spanGaps: true, points: { show: false },
    }))],
    hooks: { draw: [(u) => {
      const ctx = u.ctx;
      if (equalAspect && yMin < 0) {  // where τ = 0 is, once the axis goes below it
        const cy = u.valToPos(0, 'y', true);
        ctx.save();
        ctx.strokeStyle = '#57606a';
        ctx.beginPath();
        ctx.moveTo(u.bbox.left, cy);
        ctx.lineTo(u.bbox.left + u.bbox.width, cy);
        ctx.stroke();
        ctx.restore();
      }
      let labelled = 0;  // markers without a label take no line
      for (const m of markers) {
        const cx = u.valToPos(m.x, 'x', true);
        ctx.save();
        ctx.strokeStyle = '#57606a';
        ctx.setLineDash([4, 4]);
        ctx.beginPath();
        ctx.moveTo(cx, u.bbox.top);
        ctx.lineTo(cx, u.bbox.top + u.bbox.height);
        ctx.stroke();
        ctx.fillStyle = '#1d2330';
        ctx.font = `${12 * devicePixelRatio}px system-ui`;
        ctx.textAlign = 'left';  // uPlot leaves the y axis's right alignment set
        ctx.textBaseline = 'alphabetic';
        if (m.label) ctx.fillText(m.label, cx + 4, u.bbox.top + (14 + 16 * labelled++) * devicePixelRatio);
        ctx.restore();
      }
    }] },
  };
  box.uplot = new uPlot(opts, data, box);
  if (swatches) box.append(swatchLegend(opts.series.slice(1)));
  box.wiredemPlot.legend = opts.series.slice(1).map((s) => ({ label: s.label, color: s.stroke, dash: s.dash ? [...s.dash] : [] }));
  if (note) box.append(el('p', { class: 'note' }, note));
  return box;
}

const svgNs = 'http://www.w3.org/2000/svg';

/// A legend of line samples (SVG with presentation attributes: no inline style, which the CSP refuses).
function swatchLegend(series) {
  return el('ul', { class: 'swatches' }, series.map((s) => {
    const svg = document.createElementNS(svgNs, 'svg');
    svg.setAttribute('width', '44');
    svg.setAttribute('height', '10');
    svg.setAttribute('aria-hidden', 'true');
    const line = document.createElementNS(svgNs, 'line');
    for (const [k, v] of Object.entries({ x1: 1, y1: 5, x2: 43, y2: 5, stroke: s.stroke, 'stroke-width': s.width }))
      line.setAttribute(k, String(v));
    if (s.dash) line.setAttribute('stroke-dasharray', s.dash.join(' '));
    svg.append(line);
    return el('li', { 'data-dash': s.dash ? s.dash.join(' ') : 'solid' }, svg, ` ${s.label}`);
  }));
}

/// Upper half of a Mohr circle through σ3 and σ1 as (σ, τ) points, σ ascending.
export function mohrSemicircle(sigma3, sigma1, n = 90) {
  const c = (sigma1 + sigma3) / 2, r = (sigma1 - sigma3) / 2;
  const x = [], y = [];
  for (let k = 0; k <= n; ++k) {
    const t = Math.PI - (Math.PI * k) / n;
    x.push(c + r * Math.cos(t));
    y.push(Math.max(0, r * Math.sin(t)));
  }
  return { x, y };
}
