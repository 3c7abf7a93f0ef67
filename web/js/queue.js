// The queue panel: one item per job with its state, a live progress bar, passes, ETA and the
// estimated error, and buttons to show it, cancel it and delete it.
import {api} from './api.js';
import {etaUntil, h, isTerminal, jobLabel, percent, seconds, shortId} from './format.js';

export class QueueView {
  constructor(list, empty, jobs, {onOpen, onError}) {
    this.list = list;
    this.empty = empty;
    this.jobs = jobs;
    this.onOpen = onOpen;
    this.onError = onError;
    this.items = new Map();  // id -> {li, ...parts}
    this.current = null;
    jobs.addEventListener('list', () => this.render());
    jobs.addEventListener('job', e => this.updateItem(e.detail));
  }

  render() {
    const jobs = this.jobs.list();
    const ids = new Set(jobs.map(j => j.id));
    for (const [id, item] of this.items) {
      if (!ids.has(id)) { item.li.remove(); this.items.delete(id); }
    }
    // Keep focus where it was while items are reordered.
    const focused = document.activeElement;
    jobs.forEach((job, i) => {
      const item = this.items.get(job.id) || this.createItem(job);
      if (this.list.children[i] !== item.li) this.list.insertBefore(item.li, this.list.children[i] || null);
      this.updateItem(job);
    });
    if (focused && focused !== document.activeElement && document.contains(focused)) focused.focus();
    this.empty.hidden = jobs.length > 0;
  }

  createItem(job) {
    const name = h('button', {type: 'button', class: 'job-open', onclick: () => this.onOpen(job.id)});
    const state = h('span', {class: 'state'});
    const progress = h('progress', {max: 1, value: 0});
    const meta = h('div', {class: 'job-meta'});
    const error = h('p', {class: 'job-error', hidden: true});
    const cancel = h('button', {type: 'button', text: 'Cancel', onclick: () => this.cancel(job.id)});
    const remove = h('button', {type: 'button', class: 'danger', text: 'Delete', onclick: () => this.remove(job.id)});
    const li = h('li', {class: 'job', 'data-id': job.id},
      h('div', {class: 'job-head'}, name, state), progress, meta, error,
      h('div', {class: 'job-actions'}, cancel, remove));
    const item = {li, name, state, progress, meta, error, cancel, remove};
    this.items.set(job.id, item);
    return item;
  }

  updateItem(job) {
    const item = this.items.get(job.id);
    if (!item) return;
    const label = jobLabel(job);
    item.name.textContent = label;
    item.name.setAttribute('aria-label', `Show ${label} (job ${shortId(job.id)}) in the viewer`);
    item.li.setAttribute('aria-current', String(job.id === this.current));
    item.li.dataset.state = job.state;
    item.state.textContent = job.cancel_requested && !isTerminal(job.state) ? 'cancelling' : job.state;
    item.state.className = `state state-${job.state}`;
    const fraction = job.state === 'succeeded' ? 1 : job.progress ?? 0;
    item.progress.value = fraction;
    item.progress.setAttribute('aria-label', `${label}: ${Math.round(100 * fraction)}% done`);
    const parts = [`pass ${job.passes_done ?? 0}/${job.passes_total || '?'}`];
    if (job.state === 'running') parts.push(`ETA ${seconds(job.eta_seconds)}${etaUntil(job)}`);
    if (job.relative_error != null)
      parts.push(`error ${percent(job.relative_error)}`);
    if (job.state === 'succeeded' && job.stats) parts.push(seconds(job.stats.total_seconds));
    item.meta.textContent = parts.join(' · ');
    item.error.hidden = !job.error;
    item.error.textContent = job.error || '';
    item.cancel.hidden = isTerminal(job.state);
    item.cancel.disabled = Boolean(job.cancel_requested);
    item.cancel.setAttribute('aria-label', `Cancel ${label}`);
    item.remove.setAttribute('aria-label', `Delete ${label}`);
  }

  setCurrent(id) {
    this.current = id;
    for (const [jid, item] of this.items) item.li.setAttribute('aria-current', String(jid === id));
  }

  async cancel(id) {
    try {
      this.jobs.update(await api.cancel(id));
    } catch (e) {
      this.onError(e);
    }
  }

  async remove(id) {
    const item = this.items.get(id);
    // Focus moves to the next job's name (or the previous), not to the page's start.
    const next = item && (item.li.nextElementSibling || item.li.previousElementSibling);
    this.jobs.closeStream(id);
    try {
      await api.remove(id);
    } catch (e) {
      if (e.status !== 404) return this.onError(e);
    }
    this.jobs.forget(id);
    if (next && document.contains(next)) next.querySelector('.job-open').focus();
  }
}
