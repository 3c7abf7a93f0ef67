// Compare two finished renders: side by side with a split slider (A left of the line, B right of
// it), or their absolute difference in linear light, scaled; and both jobs' estimated relative
// error against time on log-log axes.
import {api} from './api.js';
import {drawChart} from './chart.js';
import {jobLabel, shortId} from './format.js';
import {difference, loadImageData, paint} from './image.js';
import {PanZoom} from './zoom.js';

export class Compare {
  constructor(root, jobs, onError) {
    this.jobs = jobs;
    this.onError = onError;
    this.selA = root.querySelector('#compare-a');
    this.selB = root.querySelector('#compare-b');
    this.split = root.querySelector('#split');
    this.scale = root.querySelector('#diff-scale');
    this.note = root.querySelector('#compare-note');
    this.canvasA = root.querySelector('#compare-a-canvas');
    this.canvasB = root.querySelector('#compare-b-canvas');
    this.canvasDiff = root.querySelector('#compare-diff');
    this.divider = root.querySelector('#divider');
    this.empty = root.querySelector('#compare-empty');
    this.chart = root.querySelector('#chart');
    const stage = root.querySelector('#compare-stage');
    this.zoom = new PanZoom(stage, stage.querySelector('.content'));
    root.querySelector('[data-zoom=fit]').addEventListener('click', () => this.zoom.fit());
    this.modes = [...root.querySelectorAll('input[name=compare-mode]')];
    for (const m of this.modes) m.addEventListener('change', () => this.draw());
    this.split.addEventListener('input', () => this.draw());
    this.scale.addEventListener('change', () => this.draw());
    this.selA.addEventListener('change', () => this.load());
    this.selB.addEventListener('change', () => this.load());
    this.images = {};      // id -> ImageData
    this.details = {};     // id -> job with its convergence log
    this.active = false;
    jobs.addEventListener('list', () => this.refreshOptions());
    jobs.addEventListener('job', e => { if (e.detail.state === 'succeeded') this.refreshOptions(); });
  }

  /** Called when the Compare tab opens or closes. */
  setActive(active) {
    this.active = active;
    if (active) this.refreshOptions(true);
  }

  finished() { return this.jobs.list().filter(j => j.state === 'succeeded'); }

  refreshOptions(force = false) {
    const done = this.finished();
    const key = done.map(j => j.id).join();
    if (key === this.optionsKey && !force) return;
    this.optionsKey = key;
    for (const [sel, fallback] of [[this.selA, done[1] || done[0]], [this.selB, done[0]]]) {
      const keep = sel.value;
      sel.replaceChildren(...done.map(j => new Option(`${jobLabel(j)} (${shortId(j.id)})`, j.id)));
      sel.value = done.some(j => j.id === keep) ? keep : fallback?.id || '';
    }
    if (this.active) this.load();
  }

  async load() {
    const a = this.selA.value, b = this.selB.value;
    if (!a || !b) {
      this.note.textContent = 'Compare needs two finished renders.';
      this.empty.hidden = false;
      this.drawChart();
      return;
    }
    const key = `${a}/${b}`;
    this.loadingKey = key;
    try {
      await Promise.all([a, b].map(async id => {
        this.images[id] ??= await loadImageData(`/api/jobs/${id}/image.png`);
        this.details[id] ??= await api.job(id);
      }));
    } catch (e) {
      this.onError(e);
      return;
    }
    if (this.loadingKey !== key) return;
    this.draw();
    this.drawChart();
  }

  draw() {
    const a = this.images[this.selA.value], b = this.images[this.selB.value];
    const diffMode = this.modes.find(m => m.checked).value === 'diff';
    this.split.disabled = diffMode;
    this.scale.disabled = !diffMode;
    if (!a || !b) return;
    this.empty.hidden = true;
    const sameSize = a.width === b.width && a.height === b.height;
    paint(this.canvasA, a);
    paint(this.canvasB, b);
    const showDiff = diffMode && sameSize;
    this.canvasA.hidden = this.canvasB.hidden = this.divider.hidden = showDiff;
    this.canvasDiff.hidden = !showDiff;
    if (showDiff) {
      const {image, mean} = difference(a, b, Number(this.scale.value));
      paint(this.canvasDiff, image);
      this.note.textContent = `|A − B| in linear light ×${this.scale.value}; mean absolute difference ${mean.toPrecision(3)}.`;
    } else {
      // B is drawn over A and clipped to the right of the split line.
      const at = Number(this.split.value);
      this.canvasB.style.clipPath = `inset(0 0 0 ${at}%)`;
      this.divider.style.left = `${(at / 100) * a.width}px`;
      this.divider.style.height = `${a.height}px`;
      this.note.textContent = sameSize
        ? `A left of the line, B right of it (split at ${at}%).`
        : `The images differ in size (${a.width}×${a.height} and ${b.width}×${b.height}): no difference view.`;
    }
    this.zoom.setSize(Math.max(a.width, b.width), Math.max(a.height, b.height));
  }

  drawChart() {
    // The colours of --a and --b in style.css.
    const series = [[this.selA.value, 'A', '#d9480f'], [this.selB.value, 'B', '#1f5fbf']]
      .filter(([id]) => id && this.details[id])
      .map(([id, name, color]) => ({name, label: jobLabel(this.details[id]), color,
        points: this.details[id].convergence}));
    drawChart(this.chart, series);
  }
}
