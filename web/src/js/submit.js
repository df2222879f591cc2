// Submitting a job spec: a JSON editor (or a file), and beside it the spec's
// fields as a form made from the JSON itself (every leaf, by its path, the
// way the server names fields: specimen.wire.pattern, triaxial.confining_pressures_pa[1]).
// A 400's details are shown next to the field they name; problems with no
// such field in the form are listed above it.
import { submitJob } from './api.js';
import { el, replace } from './dom.js';

const starter = {
  name: 'new job',
  seed: 1,
  specimen: { grain_count: 150, membrane_radius_m: 0.008, membrane_height_m: 0.025, wire: { pattern: 'none' } },
  triaxial: { confining_pressures_pa: [10000, 20000], target_axial_strain: 0.05 },
};

/// Leaves of a JSON value as [path, value] pairs, paths as the server writes them.
export function leaves(value, path = '', out = []) {
  if (Array.isArray(value) && value.length > 0 && value.every((v) => typeof v !== 'object' || v === null)) {
    value.forEach((v, i) => out.push([`${path}[${i}]`, v]));
  } else if (value && typeof value === 'object' && !Array.isArray(value)) {
    for (const [k, v] of Object.entries(value)) leaves(v, path ? `${path}.${k}` : k, out);
  } else {
    out.push([path, value]);
  }
  return out;
}

/// Sets the leaf at `path` (as leaves() writes it) inside `root`.
function setLeaf(root, path, value) {
  const keys = [];
  for (const part of path.split('.')) {
    const m = part.match(/^([^[]*)((\[\d+\])*)$/);
    if (m[1]) keys.push(m[1]);
    for (const idx of m[2].matchAll(/\[(\d+)\]/g)) keys.push(Number(idx[1]));
  }
  let node = root;
  for (const k of keys.slice(0, -1)) node = node[k];
  node[keys[keys.length - 1]] = value;
}

export function show(main) {
  const editor = el('textarea', { id: 'spec-editor', spellcheck: 'false', 'aria-label': 'job spec (JSON)' });
  editor.value = JSON.stringify(starter, null, 2);
  const file = el('input', { type: 'file', id: 'spec-file', accept: '.json,application/json' });
  const general = el('div', { id: 'submit-errors' });
  const fields = el('tbody');
  const button = el('button', { class: 'primary', id: 'submit-button' }, 'Submit');
  main.append(el('h1', {}, 'Submit a job'),
    el('p', { class: 'muted' }, 'Every field is in docs/job-spec.md; fields left out take their defaults, and {} is a valid job.'),
    el('div', { class: 'toolbar' }, el('label', {}, 'Load a file ', file), button),
    general,
    el('div', { class: 'submit-layout' },
      el('div', {}, el('h2', {}, 'JSON'), editor),
      el('div', {}, el('h2', {}, 'Fields'), el('table', { class: 'fields', id: 'spec-fields' },
        el('thead', {}, el('tr', {}, el('th', {}, 'field'), el('th', {}, 'value'))), fields))));

  /// Rebuilds the field table from the editor's JSON (when it parses).
  function renderFields() {
    let spec;
    try { spec = JSON.parse(editor.value); } catch (e) {
      replace(general, el('div', { class: 'error-box' }, `The JSON does not parse: ${e.message}`));
      return false;
    }
    replace(general);
    replace(fields, leaves(spec).map(([path, value]) => {
      const input = el('input', { 'data-path': path, 'aria-label': path,
        value: typeof value === 'string' ? value : JSON.stringify(value) });
      input.addEventListener('change', () => {
        let v = input.value;
        if (typeof value !== 'string') { try { v = JSON.parse(v); } catch { /* keep as text: the server will say */ } }
        const current = JSON.parse(editor.value);
        setLeaf(current, path, v);
        editor.value = JSON.stringify(current, null, 2);
      });
      return el('tr', { 'data-field': path }, el('td', { class: 'path' }, path), el('td', {}, input, el('div', { class: 'field-error' })));
    }));
    return true;
  }

  function showProblems(err) {
    const problems = err.details.length ? err.details : [{ field: err.field || '', message: err.message }];
    const unplaced = [];
    for (const p of problems) {
      const cell = p.field ? fields.querySelector(`tr[data-field="${CSS.escape(p.field)}"] .field-error`) : null;
      if (cell) cell.append(el('div', {}, p.message));
      else unplaced.push(p);
    }
    replace(general, el('div', { class: 'error-box', id: 'submit-error' },
      el('strong', {}, `Rejected (${err.code || err.status}): `), err.message,
      unplaced.length ? el('ul', {}, unplaced.map((p) => el('li', {}, p.field ? `${p.field}: ${p.message}` : p.message))) : ''));
  }

  editor.addEventListener('change', renderFields);
  file.addEventListener('change', async () => {
    if (!file.files.length) return;
    editor.value = await file.files[0].text();
    renderFields();
  });
  button.addEventListener('click', async () => {
    if (!renderFields()) return;
    button.disabled = true;
    try {
      const created = await submitJob(editor.value);
      location.hash = `#/jobs/${created.id}`;
    } catch (e) {
      if (e.status) showProblems(e);
      else replace(general, el('div', { class: 'error-box' }, e.message));
    } finally {
      button.disabled = false;
    }
  });
  renderFields();
  return () => {};
}
