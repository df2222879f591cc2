// Submitting a job spec: a JSON editor (or a file), and beside it a form of
// every field, made from the job spec's JSON Schema (GET /v1/job-spec/schema,
// the reader's own description): the path the server names the field by, an
// input holding what the JSON gives (empty: the default, shown greyed), its
// unit, the allowed range or choices, and what it means (the schema's
// x-unit and description). Form and editor stay in step. A 400's details are
// shown next to the field they name; problems with no such field are listed
// above the form.
import { json, submitJob } from './api.js';
import { el, replace } from './dom.js';

const starter = {
  name: 'new job',
  seed: 1,
  specimen: { grain_count: 150, membrane_radius_m: 0.008, membrane_height_m: 0.025, wire: { pattern: 'none' } },
  triaxial: { confining_pressures_pa: [10000, 20000], target_axial_strain: 0.05 },
};

/// Leaf fields of a schema: [path, schema] in document order.
export function schemaLeaves(schema, prefix = '', out = []) {
  for (const [key, field] of Object.entries(schema.properties || {})) {
    const path = prefix ? `${prefix}.${key}` : key;
    if (field.type === 'object') schemaLeaves(field, path, out);
    else out.push([path, field]);
  }
  return out;
}

/// What a field allows, for people: "(0, 1]", "none | helix", "≤ 200 characters".
function allowed(f) {
  const s = f.oneOf ? f.oneOf[0] : f.items || f;
  let text = '';
  if (s.enum) text = s.enum.join(' | ');
  else if (s.minimum !== undefined || s.exclusiveMinimum !== undefined) {
    const lo = s.exclusiveMinimum !== undefined ? `(${s.exclusiveMinimum}` : `[${s.minimum}`;
    const hi = s.exclusiveMaximum !== undefined ? `${s.exclusiveMaximum})` : `${s.maximum}]`;
    text = `${lo}, ${hi}`;
  } else if (s.maxLength) text = `≤ ${s.maxLength} characters`;
  if (f.oneOf) text += ` or "${f.oneOf[1].const}"`;
  if (f.items) text = `${f.minItems}–${f.maxItems} numbers in ${text}, increasing`;
  if (Array.isArray(f.type) && f.type.includes('null')) text += ' or null';
  return text;
}

const keysOf = (path) => path.split('.');
function getPath(root, path) {
  let node = root;
  for (const k of keysOf(path)) {
    if (!node || typeof node !== 'object' || !(k in node)) return undefined;
    node = node[k];
  }
  return node;
}
function setPath(root, path, value) {
  const keys = keysOf(path);
  let node = root;
  for (const k of keys.slice(0, -1)) {
    if (!node[k] || typeof node[k] !== 'object' || Array.isArray(node[k])) node[k] = {};
    node = node[k];
  }
  if (value === undefined) delete node[keys.at(-1)];
  else node[keys.at(-1)] = value;
}

const shown = (v) => (v === undefined ? '' : typeof v === 'string' ? v : JSON.stringify(v));

export function show(main) {
  const editor = el('textarea', { id: 'spec-editor', spellcheck: 'false', 'aria-label': 'job spec (JSON)' });
  editor.value = JSON.stringify(starter, null, 2);
  const file = el('input', { type: 'file', id: 'spec-file', accept: '.json,application/json' });
  const general = el('div', { id: 'submit-errors' });
  const fields = el('tbody');
  const button = el('button', { class: 'primary', id: 'submit-button' }, 'Submit');
  main.append(el('h1', {}, 'Submit a job'),
    el('p', { class: 'muted' }, 'Fields left empty take their defaults (greyed); {} is a valid job. Units are SI ("1": none).'),
    el('div', { class: 'toolbar' }, el('label', {}, 'Load a file ', file), button),
    general,
    el('div', { class: 'submit-layout' },
      el('div', {}, el('h2', {}, 'JSON'), editor),
      el('div', {}, el('h2', {}, 'Fields'), el('table', { class: 'fields', id: 'spec-fields' },
        el('thead', {}, el('tr', {}, ['field', 'value', 'unit', 'allowed', 'meaning'].map((h) => el('th', {}, h)))), fields))));

  let leaves = [];
  const inputs = new Map();

  function parsed() {
    try { return JSON.parse(editor.value); } catch (e) {
      replace(general, el('div', { class: 'error-box' }, `The JSON does not parse: ${e.message}`));
      return null;
    }
  }

  /// Shows the editor's values in the form.
  function fill() {
    const spec = parsed();
    if (spec === null) return false;
    replace(general);
    for (const [path, input] of inputs) input.value = shown(getPath(spec, path));
    return true;
  }

  function buildForm(schema) {
    leaves = schemaLeaves(schema);
    replace(fields, leaves.map(([path, f]) => {
      let input;
      if (f.enum) {
        input = el('select', { 'data-path': path, 'aria-label': path },
          el('option', { value: '' }, `(default: ${f.default})`), f.enum.map((v) => el('option', { value: v }, v)));
      } else {
        input = el('input', { 'data-path': path, 'aria-label': path, placeholder: shown(f.default) });
      }
      input.addEventListener('change', () => {
        const spec = parsed();
        if (spec === null) return;
        let v = input.value.trim();
        if (v === '') v = undefined;
        else if (f.type !== 'string' && !f.enum) { try { v = JSON.parse(v); } catch { /* a word such as "auto": kept as text */ } }
        setPath(spec, path, v);
        editor.value = JSON.stringify(spec, null, 2);
      });
      inputs.set(path, input);
      return el('tr', { 'data-field': path }, el('td', { class: 'path' }, path),
        el('td', {}, input, el('div', { class: 'field-error' })), el('td', { class: 'unit' }, f['x-unit'] ?? ''),
        el('td', { class: 'muted' }, allowed(f)), el('td', { class: 'meaning' }, f.description ?? ''));
    }));
    fill();
  }

  function showProblems(err) {
    const problems = err.details.length ? err.details : [{ field: err.field || '', message: err.message }];
    const unplaced = [];
    for (const p of problems) {
      // triaxial.confining_pressures_pa[2] belongs to the array's row.
      const row = p.field ? p.field.replace(/\[\d+\]$/, '') : '';
      const cell = row ? fields.querySelector(`tr[data-field="${CSS.escape(row)}"] .field-error`) : null;
      if (cell) cell.append(el('div', {}, row === p.field ? p.message : `${p.field.slice(row.length)}: ${p.message}`));
      else unplaced.push(p);
    }
    replace(general, el('div', { class: 'error-box', id: 'submit-error' },
      el('strong', {}, `Rejected (${err.code || err.status}): `), err.message,
      unplaced.length ? el('ul', {}, unplaced.map((p) => el('li', {}, p.field ? `${p.field}: ${p.message}` : p.message))) : ''));
  }

  editor.addEventListener('change', fill);
  file.addEventListener('change', async () => {
    if (!file.files.length) return;
    editor.value = await file.files[0].text();
    fill();
  });
  button.addEventListener('click', async () => {
    if (parsed() === null) return;
    for (const e of fields.querySelectorAll('.field-error')) replace(e);
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
  json('/v1/job-spec/schema').then(buildForm).catch((e) =>
    replace(general, el('div', { class: 'error-box' }, `Cannot load the job spec's schema: ${e.message}`)));
  return () => {};
}
