// The render service's REST API (server/http/openapi.json). Errors are thrown as ApiError with the
// RFC 9457 problem body, whose `pointer` names the JSON path at fault.

export class ApiError extends Error {
  constructor(status, problem) {
    super(problem.detail || problem.title || `HTTP ${status}`);
    this.status = status;
    this.problem = problem;
  }
}

let token = sessionStorage.getItem('caustic-token') || '';

/** Sets the bearer token sent with POST and DELETE (servers started with --token need it). */
export function setToken(value) {
  token = value;
  if (value) sessionStorage.setItem('caustic-token', value);
  else sessionStorage.removeItem('caustic-token');
}

async function request(method, path, body) {
  const headers = {};
  if (body !== undefined) headers['Content-Type'] = 'application/json';
  if (token && method !== 'GET') headers.Authorization = `Bearer ${token}`;
  let res;
  try {
    res = await fetch(path, {method, headers, body: body === undefined ? undefined : JSON.stringify(body)});
  } catch (e) {
    throw new ApiError(0, {detail: `the server did not answer (${e.message})`});
  }
  if (res.status === 204) return null;
  const text = await res.text();
  let data = text;
  if ((res.headers.get('Content-Type') || '').includes('json')) {
    try { data = JSON.parse(text); } catch { data = {detail: text}; }
  }
  if (!res.ok) throw new ApiError(res.status, typeof data === 'object' ? data : {detail: String(data)});
  return data;
}

const job = id => `/api/jobs/${encodeURIComponent(id)}`;
const asset = id => `/api/assets/${encodeURIComponent(id)}`;

/** The media type POST /api/assets takes for a mesh file's name, or '' for another kind of file. */
export function meshMediaType(name) {
  const ext = /\.([^.]+)$/.exec(name)?.[1]?.toLowerCase();
  return {obj: 'model/obj', glb: 'model/gltf-binary', zip: 'application/zip'}[ext] || '';
}

// The file as the raw body. XMLHttpRequest, not fetch: only it reports upload progress.
function upload(file, onProgress) {
  return new Promise((resolve, reject) => {
    const xhr = new XMLHttpRequest();
    // The service refuses a name over 200 characters (code points: Array.from splits no pair).
    xhr.open('POST', `/api/assets?name=${encodeURIComponent(Array.from(file.name).slice(0, 200).join(''))}`);
    xhr.setRequestHeader('Content-Type', meshMediaType(file.name));
    if (token) xhr.setRequestHeader('Authorization', `Bearer ${token}`);
    xhr.upload.addEventListener('progress', e => { if (e.lengthComputable) onProgress(e.loaded / e.total); });
    xhr.addEventListener('load', () => {
      let data;
      try { data = JSON.parse(xhr.responseText); } catch { data = {detail: xhr.responseText || `HTTP ${xhr.status}`}; }
      if (xhr.status >= 200 && xhr.status < 300) return resolve(data);
      const retry = xhr.getResponseHeader('Retry-After');
      if (retry && data.detail) data.detail += ` (retry in ${retry} s)`;
      reject(new ApiError(xhr.status, data));
    });
    xhr.addEventListener('error', () => reject(new ApiError(0, {detail: 'the upload did not reach the server'})));
    xhr.send(file);
  });
}

export const api = {
  settings: () => request('GET', '/api/settings'),
  scenes: () => request('GET', '/api/scenes').then(r => r.scenes),
  /** An example scene's file as text, as written. */
  sceneText: async name => {
    const res = await fetch(`/api/scenes/${encodeURIComponent(name)}`);
    if (!res.ok) throw new ApiError(res.status, {detail: `no example scene "${name}"`});
    return res.text();
  },
  jobs: () => request('GET', '/api/jobs?limit=50').then(r => r.jobs),
  job: id => request('GET', job(id)),
  submit: body => request('POST', '/api/jobs', body),
  cancel: id => request('POST', `${job(id)}/cancel`),
  remove: id => request('DELETE', job(id)),
  eventsUrl: id => `${job(id)}/events`,
  assets: () => request('GET', '/api/assets?limit=100').then(r => r.assets),
  /** Uploads a mesh File; onProgress(fraction sent). Resolves to the asset (new or known). */
  uploadAsset: (file, onProgress = () => {}) => upload(file, onProgress),
  removeAsset: id => request('DELETE', asset(id)),
  /** One asset; a .glb's has `model`: its cameras, lights, materials (docs/gltf.md). */
  asset: id => request('GET', asset(id)),
  /** {store: 'sqlite' | 'postgresql', workers: [...]}: the worker threads sharing the store. */
  workers: () => request('GET', '/api/workers'),
};
