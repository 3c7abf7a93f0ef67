// The viewer: one job's live preview while it renders (preview.png, fetched again after each pass),
// then its result (image.png), on a canvas with zoom, pan and an exposure slider applied in linear
// light; PNG and EXR downloads; and what the render cost and how accurate it is.
import {bytes, count, etaUntil, h, isTerminal, jobLabel, percent, seconds, shortId} from './format.js';
import {exposed, loadImageData, paint} from './image.js';
import {PanZoom} from './zoom.js';

const PREVIEW_MS = 500;

export class Viewer {
  constructor(root, jobs) {
    this.jobs = jobs;
    this.title = root.querySelector('#viewer-title');
    this.canvas = root.querySelector('#viewer-canvas');
    this.empty = root.querySelector('#viewer-empty');
    this.stats = root.querySelector('#stats');
    this.downloads = root.querySelector('#downloads');
    this.exposure = root.querySelector('#exposure');
    this.exposureOut = root.querySelector('#exposure-out');
    const stage = root.querySelector('#viewer-stage');
    this.zoom = new PanZoom(stage, stage.querySelector('.content'));
    root.querySelector('.toolbar').addEventListener('click', e => {
      const action = e.target.closest('[data-zoom]')?.dataset.zoom;
      if (action === 'in') this.zoom.zoomBy(1.25);
      else if (action === 'out') this.zoom.zoomBy(0.8);
      else if (action === 'fit') this.zoom.fit();
      else if (action === 'one') this.zoom.one();
    });
    this.exposure.addEventListener('input', () => this.repaint());
    this.id = null;
    this.source = null;    // ImageData as loaded
    this.loaded = null;    // the key of what is loaded ("preview:<passes>" or "image")
    this.loading = null;   // the key being loaded
    this.lastPreview = -Infinity;
    jobs.addEventListener('job', e => { if (e.detail.id === this.id) this.update(e.detail); });
  }

  show(id) {
    if (id === this.id) return;
    this.id = id;
    this.source = null;
    this.loaded = this.loading = this.failed = null;
    this.abort?.abort();
    this.canvas.width = this.canvas.height = 0;
    this.canvas.removeAttribute('data-src');
    this.zoom.setSize(0, 0);
    this.empty.hidden = false;
    this.jobs.setPriority(id);
    const job = id && this.jobs.get(id);
    if (job) this.update(job);
    else {
      this.title.textContent = 'No job selected: submit a render or pick one in the queue.';
      this.stats.replaceChildren();
      this.downloads.replaceChildren();
    }
  }

  update(job) {
    this.title.replaceChildren(h('strong', {text: jobLabel(job)}), ` · job ${shortId(job.id)} · ${job.state}` +
      (job.error ? `: ${job.error}` : ''));
    this.renderStats(job);
    this.renderDownloads(job);
    // The result once it exists, else the film so far. The server announces a pass a moment
    // before it writes that pass's preview, so a running job's preview is certain to exist only
    // from the second pass on (the first pass always writes one).
    const passes = job.passes_done || 0;
    if (job.state === 'succeeded') this.load(job, 'image', job.links.image_png);
    else if (job.links.preview_png && (passes >= 2 || (passes >= 1 && isTerminal(job.state))))
      this.loadPreview(job);
  }

  // The server rewrites preview.png at most twice a second: fetch it no more often than that.
  loadPreview(job) {
    const wait = this.lastPreview + PREVIEW_MS - performance.now();
    if (wait > 0) {
      clearTimeout(this.previewTimer);
      this.previewTimer = setTimeout(() => {
        const latest = this.jobs.get(job.id);
        if (latest && this.id === job.id) this.update(latest);
      }, wait);
      return;
    }
    if (this.loading || this.loaded === `preview:${job.passes_done}`) return;
    this.lastPreview = performance.now();
    this.load(job, `preview:${job.passes_done}`, `${job.links.preview_png}?pass=${job.passes_done}&t=${Date.now()}`);
  }

  async load(job, key, url) {
    if (this.loaded === key || this.loading === key || this.failed === key) return;
    if (this.loaded === 'image') return;
    // One load at a time; a newer pass waits for the next event rather than queueing up.
    if (this.loading && key !== 'image') return;
    this.abort?.abort();
    this.abort = new AbortController();
    this.loading = key;
    const id = job.id;
    try {
      const image = await loadImageData(url, this.abort.signal);
      if (this.id !== id) return;
      this.source = image;
      this.loaded = key;
      this.canvas.dataset.src = url.split('?')[0];
      this.canvas.dataset.kind = key.split(':')[0];
      this.repaint();
      this.zoom.setSize(image.width, image.height);
      this.empty.hidden = true;
    } catch (e) {
      if (e.name !== 'AbortError') {
        this.failed = key;  // not again until there is something new to load
        this.empty.textContent = `Could not load the image (${e.message})`;
      }
    } finally {
      if (this.loading === key) this.loading = null;
    }
    // Events that came while loading may have brought a newer pass.
    const latest = this.jobs.get(id);
    if (this.id === id && latest && this.loaded !== 'image') this.update(latest);
  }

  repaint() {
    const ev = Number(this.exposure.value);
    this.exposureOut.textContent = `${ev > 0 ? '+' : ''}${ev.toFixed(1)} EV`;
    if (this.source) paint(this.canvas, ev === 0 ? this.source : exposed(this.source, ev));
  }

  renderDownloads(job) {
    const links = [];
    if (job.links.image_png) links.push(h('a', {href: job.links.image_png, download: `caustic-${shortId(job.id)}.png`, text: 'PNG'}));
    if (job.links.image_exr) links.push(h('a', {href: job.links.image_exr, download: `caustic-${shortId(job.id)}.exr`, text: 'EXR'}));
    if (links.length) links.unshift(h('span', {class: 'visually-hidden', text: 'Download:'}));
    this.downloads.replaceChildren(...links);
  }

  renderStats(job) {
    const s = job.stats, set = job.settings || {};
    const rows = [];
    const row = (name, value, key) => rows.push(h('dt', {text: name}), h('dd', {text: value, 'data-stat': key}));
    if (s) {
      row('Time', `${seconds(s.total_seconds)} (setup ${seconds(s.setup_seconds)}, render ${seconds(s.render_seconds)})`, 'time');
      row('Rays per second', `${count(s.rays_per_second)} rays/s (${count(s.rays)} rays on ${s.threads} threads)`, 'rays_per_second');
      if (set.integrator === 'photon' || set.integrator === 'ppm') {
        const per = (set.photons || 0) + (set.caustic_photons || 0);
        row('Photons', `${count(per * s.passes)} photon paths (${count(per)} a pass); maps ${bytes(s.memory?.photon_maps)}`, 'photons');
      }
      row('Relative error', `${percent(s.relative_error)} (estimated RMS${s.relative_bias > 0 ? `: noise ${percent(s.relative_noise)}, bias ${percent(s.relative_bias)}` : ''})`, 'relative_error');
      row('Passes', `${s.passes} (stopped by ${String(s.stop_reason).replace('_', ' ')})`, 'passes');
      row('Samples per pixel', String(s.spp), 'spp');
      const parts = Object.entries(s.memory || {}).filter(([k, v]) => k !== 'total' && v > 0)
        .map(([k, v]) => `${k.replace('_', ' ')} ${bytes(v)}`);
      row('Memory', `${bytes(s.memory?.total)}${parts.length ? ` (${parts.join(', ')})` : ''}`, 'memory');
      if (s.dropped_samples) row('Dropped samples', String(s.dropped_samples), 'dropped');
    } else {
      const started = job.started_at ? Date.parse(job.started_at) : null;
      const end = job.finished_at ? Date.parse(job.finished_at) : Date.now();
      row('State', job.state, 'state');
      if (started) row('Elapsed', seconds((end - started) / 1000), 'time');
      row('Passes', `${job.passes_done ?? 0} of ${job.passes_total || '?'}`, 'passes');
      row('Relative error', percent(job.relative_error), 'relative_error');
      if (!isTerminal(job.state)) row('ETA', `${seconds(job.eta_seconds)}${etaUntil(job)}`, 'eta');
    }
    row('Settings', Object.entries(set).filter(([k]) => ['integrator', 'accelerator', 'spp', 'max_depth', 'seed'].includes(k))
      .map(([k, v]) => `${k} ${v}`).join(', '), 'settings');
    this.stats.replaceChildren(...rows);
  }
}
