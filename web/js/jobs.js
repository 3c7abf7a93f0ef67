// The page's copy of the job list, kept live: GET /api/jobs on load and every few seconds, and a
// Server-Sent Events stream (GET /api/jobs/{id}/events) per unfinished job, at most MAX_STREAMS at
// once (a browser opens only 6 connections to one server; the others wait for the next poll).
// Emits 'job' (detail: the job) on every change, 'list' when jobs come or go, and 'offline' or
// 'online' after each poll.
import {api} from './api.js';
import {isTerminal} from './format.js';

const MAX_STREAMS = 3;
const POLL_BUSY_MS = 3000, POLL_IDLE_MS = 15000;

export class Jobs extends EventTarget {
  constructor() {
    super();
    this.map = new Map();
    this.streams = new Map();
    this.priority = null;  // the job the viewer shows streams first
    this.timer = null;
  }

  /** Jobs, newest first. */
  list() {
    return [...this.map.values()].sort((a, b) => (b.created_at || '').localeCompare(a.created_at || ''));
  }

  get(id) { return this.map.get(id); }

  async refresh() {
    clearTimeout(this.timer);
    try {
      const jobs = await api.jobs();
      const seen = new Set(jobs.map(j => j.id));
      let changed = false;
      for (const id of [...this.map.keys()]) {
        if (!seen.has(id) && !this.streams.has(id)) { this.map.delete(id); changed = true; }
      }
      for (const job of jobs) {
        if (this.streams.has(job.id)) continue;  // the stream is newer
        if (!this.map.has(job.id)) changed = true;
        this.update(job, false);
      }
      if (changed) this.emit('list');
      this.ensureStreams();
      this.emit('online');
    } catch (e) {
      this.emit('offline', e);
    }
    const busy = this.list().some(j => !isTerminal(j.state));
    this.timer = setTimeout(() => this.refresh(), busy ? POLL_BUSY_MS : POLL_IDLE_MS);
  }

  /** Merges a job (from a response or an event); `announce` emits 'list' for a new one. */
  update(job, announce = true) {
    const old = this.map.get(job.id);
    // The list omits `convergence`: keep the one an event brought.
    const merged = old ? {...old, ...job, convergence: job.convergence ?? old.convergence} : job;
    this.map.set(job.id, merged);
    if (!old && announce) this.emit('list');
    this.emit('job', merged);
    if (isTerminal(merged.state)) this.closeStream(job.id);
  }

  add(job) {
    this.update(job);
    this.ensureStreams();
  }

  forget(id) {
    this.closeStream(id);
    if (this.map.delete(id)) this.emit('list');
    this.ensureStreams();
  }

  setPriority(id) {
    this.priority = id;
    this.ensureStreams();
  }

  ensureStreams() {
    const active = this.list().filter(j => !isTerminal(j.state));
    const rank = j => (j.id === this.priority ? 0 : j.state === 'running' ? 1 : 2);
    active.sort((a, b) => rank(a) - rank(b) || (a.created_at || '').localeCompare(b.created_at || ''));
    const wanted = new Set(active.slice(0, MAX_STREAMS).map(j => j.id));
    for (const id of [...this.streams.keys()]) if (!wanted.has(id)) this.closeStream(id);
    for (const id of wanted) if (!this.streams.has(id)) this.openStream(id);
  }

  openStream(id) {
    const source = new EventSource(api.eventsUrl(id));
    this.streams.set(id, source);
    const data = e => JSON.parse(e.data);
    source.addEventListener('progress', e => this.update(data(e)));
    source.addEventListener('end', e => {
      this.closeStream(id);
      this.update(data(e));
      this.ensureStreams();
    });
    source.addEventListener('deleted', () => this.forget(id));
    // A stream refused (429: too many) or cut: close it rather than let the browser retry; the
    // next poll opens it again.
    source.onerror = () => this.closeStream(id);
  }

  closeStream(id) {
    const source = this.streams.get(id);
    if (source) {
      source.close();
      this.streams.delete(id);
    }
  }

  emit(type, detail) { this.dispatchEvent(new CustomEvent(type, {detail})); }
}
