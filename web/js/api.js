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
};
