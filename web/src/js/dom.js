// DOM helpers. Every text goes in through textContent (never innerHTML), so a
// job named <img src=x onerror=alert(1)> shows as those characters.

/// el('td', {class: 'num'}, 'text', childNode, …): attributes are set with
/// setAttribute, except `on*` keys, which become event listeners.
export function el(tag, attrs = {}, ...children) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs)) {
    if (value === undefined || value === null || value === false) continue;
    if (key.startsWith('on')) node.addEventListener(key.slice(2), value);
    else if (key === 'value') node.value = value;
    else node.setAttribute(key, value === true ? '' : String(value));
  }
  for (const child of children.flat()) {
    if (child === undefined || child === null || child === false) continue;
    node.append(child instanceof Node ? child : document.createTextNode(String(child)));
  }
  return node;
}

/// Replaces the children of `node`.
export function replace(node, ...children) {
  node.replaceChildren();
  for (const child of children.flat()) if (child) node.append(child instanceof Node ? child : String(child));
  return node;
}

/// A number for people: 3 significant digits, or '—' when missing.
export function num(x, digits = 3) {
  if (x === null || x === undefined || !Number.isFinite(x)) return '—';
  const a = Math.abs(x);
  if (a !== 0 && (a < 1e-3 || a >= 1e6)) return x.toExponential(digits - 1);
  return Number(x.toPrecision(digits)).toString();
}

/// Pa as kPa, for people.
export const kpa = (pa, digits = 4) => (pa === null || pa === undefined ? '—' : num(pa / 1000, digits));

export function seconds(s) {
  if (s === null || s === undefined || !Number.isFinite(s)) return '—';
  if (s < 60) return `${s.toFixed(0)} s`;
  if (s < 3600) return `${Math.floor(s / 60)} min ${Math.round(s % 60)} s`;
  return `${Math.floor(s / 3600)} h ${Math.round((s % 3600) / 60)} min`;
}

/// A Pa figure with its label, as a summary tile.
export function figure(label, value, id) {
  return el('div', { class: 'figure', 'data-figure': id }, el('div', { class: 'label' }, label), el('div', { class: 'value' }, value));
}

/// Triggers a download of a Blob under `name`.
export function saveBlob(blob, name) {
  const url = URL.createObjectURL(blob);
  const a = el('a', { href: url, download: name });
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(url), 10000);
}
