// Number formatting and tiny DOM helpers shared by the page's modules.

/** Creates an element: h('p', {class: 'x', text: 'hi'}, child...). */
export function h(tag, props = {}, ...children) {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(props)) {
    if (v === undefined || v === null || v === false) continue;
    if (k === 'text') el.textContent = v;
    else if (k === 'class') el.className = v;
    else if (k.startsWith('on')) el.addEventListener(k.slice(2), v);
    else if (k in el && typeof v !== 'string') el[k] = v;
    else el.setAttribute(k, v === true ? '' : v);
  }
  el.append(...children.filter(c => c !== null && c !== undefined && c !== false));
  return el;
}

export function seconds(s) {
  if (s === null || s === undefined || !Number.isFinite(s)) return '—';
  if (s < 1) return `${(s * 1000).toFixed(s < 0.01 ? 1 : 0)} ms`;
  if (s < 60) return `${s.toFixed(s < 10 ? 2 : 1)} s`;
  const m = Math.floor(s / 60);
  if (m < 60) return `${m} min ${Math.round(s - 60 * m)} s`;
  return `${Math.floor(m / 60)} h ${m % 60} min`;
}

export function bytes(n) {
  if (!Number.isFinite(n)) return '—';
  const units = ['B', 'KiB', 'MiB', 'GiB'];
  let i = 0;
  while (n >= 1024 && i < units.length - 1) { n /= 1024; i++; }
  return `${n.toFixed(i && n < 10 ? 1 : 0)} ${units[i]}`;
}

/** 1234567 -> "1.23 M" (SI). */
export function count(n) {
  if (!Number.isFinite(n)) return '—';
  const units = [[1e9, 'G'], [1e6, 'M'], [1e3, 'k']];
  for (const [v, u] of units) if (Math.abs(n) >= v) return `${(n / v).toPrecision(3)} ${u}`;
  return String(Math.round(n));
}

export function percent(x) {
  if (x === null || x === undefined || !Number.isFinite(x)) return '—';
  return `${(100 * x).toPrecision(x < 0.001 ? 2 : 3)}%`;
}

// Names of scenes sent as objects (the server keeps none), by job id, in this browser.
const LABELS = 'caustic-scene-labels';
export function rememberSceneLabel(id, label) {
  let labels = {};
  try { labels = JSON.parse(localStorage.getItem(LABELS)) || {}; } catch { /* a fresh start */ }
  labels[id] = label;
  localStorage.setItem(LABELS, JSON.stringify(Object.fromEntries(Object.entries(labels).slice(-200))));
}
function sceneLabel(id) {
  try { return JSON.parse(localStorage.getItem(LABELS))?.[id]; } catch { return undefined; }
}

/** A job's one-line name: scene, integrator, spp. */
export function jobLabel(job) {
  const s = job.settings || {};
  const scene = job.scene_name || sceneLabel(job.id) || 'custom scene';
  return `${scene} · ${s.integrator || '?'} · ${s.spp ?? '?'} spp`;
}

export const shortId = id => id.slice(0, 6);

export const isTerminal = state => state === 'succeeded' || state === 'failed' || state === 'cancelled';

/** What a running job's ETA counts down to, when the forecast expects a rule other than the spp
 *  budget to stop it (the API's eta_reason). */
export function etaUntil(job) {
  if (job.eta_reason === 'target_error') return ' to target error';
  if (job.eta_reason === 'time_limit') return ' (time limit)';
  return '';
}
