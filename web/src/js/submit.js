// Submitting a job spec: a JSON editor (or a file), and beside it a form of
// every field, made from the job spec's JSON Schema (GET /v1/job-spec/schema,
// the reader's own description): the path the server names the field by, an
// input holding what the JSON gives (empty: the default, shown greyed), its
// unit, the allowed range or choices, and what it means (the schema's
// x-unit and description). An object-or-null field with fields of its own
// (a grain-size curve, a grain shape) is a group: a row of its own (its
// meaning, its errors, "leave out") and a row per field; a group that takes
// one field only (maxProperties 1: a template or spheres) keeps the last one
// given. Form and editor stay in step. A 400's details are shown next to the
// field they name; problems with no such field are listed above the form.
import { json, submitJob } from './api.js';
import { el, replace } from './dom.js';

const starter = {
  name: 'new job',
  seed: 1,
  specimen: { grain_count: 150, membrane_radius_m: 0.008, membrane_height_m: 0.025, wire: { pattern: 'none' } },
  triaxial: { confining_pressures_pa: [10000, 20000], target_axial_strain: 0.05 },
};

/// An object-or-null field with fields of its own (specimen.grain_sizes,
/// specimen.grain_shape): a group in the form, null (left out) by default.
export const isGroup = (f) => Array.isArray(f.type) && f.type.includes('object') && !!f.properties;

/// The form's rows of a schema, in document order: [path, schema, group]
/// for every leaf field, and for each object-or-null group a row of its own
/// (group = true: its meaning, its errors, a button that leaves it out)
/// followed by its fields' rows.
export function schemaLeaves(schema, prefix = '', out = []) {
  for (const [key, field] of Object.entries(schema.properties || {})) {
    const path = prefix ? `${prefix}.${key}` : key;
    if (field.type === 'object') schemaLeaves(field, path, out);
    else if (isGroup(field)) {
      out.push([path, field, true]);
      schemaLeaves(field, path, out);
    } else out.push([path, field, false]);
  }
  return out;
}

/// A number's interval, "(0, 1]", or '' when the schema gives none.
function interval(s) {
  if (s.minimum === undefined && s.exclusiveMinimum === undefined) return '';
  const lo = s.exclusiveMinimum !== undefined ? `(${s.exclusiveMinimum}` : `[${s.minimum}`;
  const hi = s.exclusiveMaximum !== undefined ? `${s.exclusiveMaximum})` : `${s.maximum}]`;
  return `${lo}, ${hi}`;
}

/// What a field allows, for people: "(0, 1]", "none | helix", "≤ 200 characters",
/// "1–16 numbers in (0, 1e7], increasing", "2–32 entries of 4 numbers".
function allowed(f, group = false) {
  if (group) {
    const one = f.maxProperties === 1 ? `one of ${Object.keys(f.properties).join(', ')}` : 'the fields below';
    return `${one}, or null`;
  }
  const s = f.oneOf ? f.oneOf[0] : f.items || f;
  let text = '';
  if (s.enum) text = s.enum.join(' | ');
  else if (interval(s)) text = interval(s);
  else if (s.maxLength) text = `≤ ${s.maxLength} characters`;
  if (f.oneOf) text += ` or "${f.oneOf[1].const}"`;
  if (f.items) {
    const count = `${f.minItems}–${f.maxItems}`;
    text = f.items.type === 'array' ? `${count} entries of ${f.items.minItems} numbers`
      : `${count} numbers${text ? ` in ${text}` : ''}${f['x-order'] ? `, ${f['x-order']}` : ''}`;
  }
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
/// Sets (undefined: removes) the field at `path`, making the objects on the
/// way. In a group (`groups`: path → schema) a value replaces the group's
/// other fields when it takes one field only (a grain shape: a template or
/// spheres), and a group left with no field is left out (null, its default).
function setPath(root, path, value, groups = new Map()) {
  const keys = keysOf(path);
  let node = root;
  const chain = [];
  for (const k of keys.slice(0, -1)) {
    if (!node[k] || typeof node[k] !== 'object' || Array.isArray(node[k])) node[k] = {};
    chain.push([node, k]);
    node = node[k];
  }
  const parent = keys.slice(0, -1).join('.');
  const group = groups.get(parent);
  if (value === undefined) delete node[keys.at(-1)];
  else {
    if (group && group.maxProperties === 1) for (const k of Object.keys(node)) delete node[k];
    node[keys.at(-1)] = value;
  }
  if (group && Object.keys(node).length === 0) {
    const [above, k] = chain.at(-1);
    delete above[k];
  }
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
  const groupStates = new Map();

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
    for (const [path, state] of groupStates) {
      const v = getPath(spec, path);
      state.textContent = v === undefined || v === null ? 'null (the default)' : 'given';
    }
    return true;
  }

  function buildForm(schema) {
    leaves = schemaLeaves(schema);
    const groups = new Map(leaves.filter(([, , g]) => g).map(([path, f]) => [path, f]));
    const edit = (change) => {
      const spec = parsed();
      if (spec === null) return;
      change(spec);
      editor.value = JSON.stringify(spec, null, 2);
      fill();  // a group's other fields may have gone with this one
    };
    replace(fields, leaves.map(([path, f, group]) => {
      const meaning = el('td', { class: 'meaning' }, f.description ?? '');
      const errors = el('div', { class: 'field-error' });
      if (group) {
        // The group itself: null (left out) until one of its fields is given.
        const state = el('span', { class: 'group-state', 'data-group': path });
        const clear = el('button', { type: 'button', class: 'group-clear', 'data-group': path,
          onclick: () => edit((spec) => setPath(spec, path, undefined)) }, 'leave out (null)');
        groupStates.set(path, state);
        return el('tr', { 'data-field': path, class: 'group' }, el('td', { class: 'path' }, path),
          el('td', {}, state, ' ', clear, errors), el('td', { class: 'unit' }, ''),
          el('td', { class: 'muted' }, allowed(f, true)), meaning);
      }
      let input;
      if (f.enum) {
        const none = f.default === undefined ? '(not given)' : `(default: ${f.default})`;
        input = el('select', { 'data-path': path, 'aria-label': path },
          el('option', { value: '' }, none), f.enum.map((v) => el('option', { value: v }, v)));
      } else {
        input = el('input', { 'data-path': path, 'aria-label': path, placeholder: shown(f.default) });
      }
      input.addEventListener('change', () => {
        let v = input.value.trim();
        if (v === '') v = undefined;
        else if (f.type !== 'string' && !f.enum) { try { v = JSON.parse(v); } catch { /* a word such as "auto": kept as text */ } }
        edit((spec) => setPath(spec, path, v, groups));
      });
      inputs.set(path, input);
      const inGroup = groups.has(keysOf(path).slice(0, -1).join('.'));
      return el('tr', { 'data-field': path, class: inGroup ? 'in-group' : undefined }, el('td', { class: 'path' }, path),
        el('td', {}, input, errors), el('td', { class: 'unit' }, f['x-unit'] ?? ''),
        el('td', { class: 'muted' }, allowed(f)), meaning);
    }));
    fill();
  }

  function showProblems(err) {
    const problems = err.details.length ? err.details : [{ field: err.field || '', message: err.message }];
    const unplaced = [];
    for (const p of problems) {
      // triaxial.confining_pressures_pa[2] belongs to the array's row, and
      // specimen.grain_shape.spheres[1][3] to the spheres' row.
      const row = p.field ? p.field.replace(/(\[\d+\])+$/, '') : '';
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
