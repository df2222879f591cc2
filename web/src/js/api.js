// The HTTP API (docs/api.md) from the page: same origin, JSON, and the bearer
// token when the server wants one. The token is asked for once (a dialog),
// kept in sessionStorage for this tab, and sent only in the Authorization
// header, never in a URL.

const tokenKey = 'wiredem-token';

/// An API error: `status`, and the error body's `code`, `message`, `field`, `details`.
export class ApiError extends Error {
  constructor(status, body) {
    const e = (body && body.error) || {};
    super(e.message || `HTTP ${status}`);
    this.status = status;
    this.code = e.code || null;
    this.field = e.field || null;
    this.details = e.details || [];
  }
}

let asking = null;

/// Shows the token dialog; resolves once a token was entered.
function askToken(message) {
  if (asking) return asking;
  const dialog = document.getElementById('token-dialog');
  const form = document.getElementById('token-form');
  const input = document.getElementById('token-input');
  document.getElementById('token-error').textContent = message || '';
  asking = new Promise((resolve) => {
    form.addEventListener('submit', (ev) => {
      ev.preventDefault();
      sessionStorage.setItem(tokenKey, input.value.trim());
      input.value = '';
      dialog.close();
      asking = null;
      resolve();
    }, { once: true });
  });
  dialog.showModal();
  return asking;
}

/// fetch() of an API path with the token; on 401 asks for a token and tries again.
export async function request(path, options = {}) {
  for (;;) {
    const headers = new Headers(options.headers || {});
    const token = sessionStorage.getItem(tokenKey);
    if (token) headers.set('Authorization', `Bearer ${token}`);
    const res = await fetch(path, { ...options, headers, credentials: 'omit', cache: 'no-store' });
    if (res.status !== 401) return res;
    await askToken(token ? 'That token was refused.' : '');
  }
}

async function failed(res) {
  let body = null;
  try { body = await res.json(); } catch { /* not JSON */ }
  return new ApiError(res.status, body);
}

/// GET (or another method) returning parsed JSON; throws ApiError.
export async function json(path, options = {}) {
  const res = await request(path, options);
  if (!res.ok) throw await failed(res);
  return res.json();
}

/// GET of a binary array route: a Float32Array or Int32Array with its shape.
export async function array(path) {
  const res = await request(path);
  if (!res.ok) throw await failed(res);
  const shape = (res.headers.get('X-Wiredem-Shape') || '').split(',').filter(Boolean).map(Number);
  const buffer = await res.arrayBuffer();
  const data = res.headers.get('X-Wiredem-Dtype') === 'int32' ? new Int32Array(buffer) : new Float32Array(buffer);
  return { shape, data };
}

/// GET as a Blob (downloads).
export async function blob(path) {
  const res = await request(path);
  if (!res.ok) throw await failed(res);
  return res.blob();
}

export const submitJob = (specText) =>
  json('/v1/jobs', { method: 'POST', headers: { 'Content-Type': 'application/json' }, body: specText });
export const cancelJob = (id) => json(`/v1/jobs/${encodeURIComponent(id)}`, { method: 'DELETE' });
