// The Workers panel: the worker threads of every process that shares a PostgreSQL store (GET
// /api/workers), each with its host, cores and render threads, the task it renders (job and pass
// range), the seconds since its last heartbeat and its tasks done and failed, refreshed every few
// seconds while the page is visible. A SQLite server renders its jobs itself: the panel says so
// once and stops asking.
import {api} from './api.js';
import {h, shortId} from './format.js';

const REFRESH_MS = 3000;

export class WorkersPanel {
  /** @param onOpen(jobId) shows a job in the viewer. */
  constructor(panel, {onOpen}) {
    this.panel = panel;
    this.onOpen = onOpen;
    this.list = panel.querySelector('#workers');
    this.note = panel.querySelector('#workers-note');
    this.error = panel.querySelector('#workers-error');
    this.store = '';
    this.timer = 0;
    document.addEventListener('visibilitychange', () => {
      if (!document.hidden && this.store === 'postgresql') this.refresh();
    });
  }

  /** Lists the workers again; returns the store ('sqlite' or 'postgresql'), '' if unknown. */
  async refresh() {
    clearTimeout(this.timer);
    try {
      const {store, workers} = await api.workers();
      this.error.textContent = '';
      this.show(store, workers);
    } catch (e) {
      this.error.textContent = `The workers could not be listed: ${e.message}`;
    }
    if (this.store !== 'sqlite' && !document.hidden)
      this.timer = setTimeout(() => this.refresh(), REFRESH_MS);
    return this.store;
  }

  show(store, workers) {
    this.store = store;
    this.panel.dataset.store = store;
    if (store === 'sqlite') {
      this.list.replaceChildren();
      this.note.textContent = 'One process (SQLite): this server renders its jobs on its own threads.';
      return;
    }
    this.note.textContent = workers.length === 0
      ? 'No worker is alive: start one with caustic worker --store postgresql://…'
      : `${workers.length} worker thread${workers.length === 1 ? '' : 's'} on this store.`;
    this.list.replaceChildren(...workers.map(w => this.item(w)));
  }

  item(w) {
    const fact = (key, label, ...value) => [h('dt', {text: label}), h('dd', {'data-fact': key}, ...value)];
    const task = w.task
      ? [h('button', {type: 'button', class: 'link', text: `job ${shortId(w.task.job)}`,
        'aria-label': `Show job ${w.task.job}`, onclick: () => this.onOpen(w.task.job)}),
      ` passes ${w.task.first_pass}–${w.task.last_pass}`]
      : ['idle'];
    return h('li', {class: 'worker', 'data-id': w.id},
      h('div', {class: 'worker-head'}, h('span', {class: 'worker-name', text: w.host, title: w.id}),
        h('span', {class: w.task ? 'state state-running' : 'state', text: w.task ? 'rendering' : 'idle'})),
      h('dl', {class: 'worker-facts'},
        ...fact('threads', 'cores / threads', `${w.cores} / ${w.threads}`),
        ...fact('task', 'task', ...task),
        ...fact('heartbeat', 'heartbeat', `${w.seconds_since_heartbeat.toFixed(1)} s ago`),
        ...fact('tasks', 'tasks done / failed', `${w.tasks_done} / ${w.tasks_failed}`)));
  }
}
