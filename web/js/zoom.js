// Zoom and pan of one element (`content`) inside a clipping `stage`: the wheel zooms about the
// pointer, dragging pans, and on the focused stage + / − zoom, 0 fits, 1 shows 1:1, arrows pan.
// The content is moved with a CSS transform; its own size is the image's size in pixels.

const MIN = 1 / 32, MAX = 64, STEP = 1.25;

export class PanZoom {
  constructor(stage, content) {
    this.stage = stage;
    this.content = content;
    this.scale = 1;
    this.x = 0;
    this.y = 0;
    this.width = 0;
    this.height = 0;
    this.fitted = true;  // refit when the stage resizes, until the user zooms or pans

    stage.addEventListener('wheel', e => {
      if (!this.width) return;
      e.preventDefault();
      const r = stage.getBoundingClientRect();
      this.zoomBy(Math.pow(STEP, -Math.sign(e.deltaY)), e.clientX - r.left, e.clientY - r.top);
    }, {passive: false});

    let drag = null;
    stage.addEventListener('pointerdown', e => {
      if (e.button !== 0 || !this.width) return;
      drag = {id: e.pointerId, x: e.clientX, y: e.clientY};
      stage.setPointerCapture(e.pointerId);
      stage.classList.add('dragging');
    });
    stage.addEventListener('pointermove', e => {
      if (!drag || e.pointerId !== drag.id) return;
      this.panBy(e.clientX - drag.x, e.clientY - drag.y);
      drag.x = e.clientX;
      drag.y = e.clientY;
    });
    const end = e => {
      if (!drag || e.pointerId !== drag.id) return;
      drag = null;
      stage.classList.remove('dragging');
    };
    stage.addEventListener('pointerup', end);
    stage.addEventListener('pointercancel', end);
    stage.addEventListener('dblclick', () => (this.fitted ? this.one() : this.fit()));

    stage.addEventListener('keydown', e => {
      if (e.altKey || e.ctrlKey || e.metaKey) return;
      const pan = 40;
      const actions = {
        '+': () => this.zoomBy(STEP), '=': () => this.zoomBy(STEP), '-': () => this.zoomBy(1 / STEP),
        '0': () => this.fit(), '1': () => this.one(),
        ArrowLeft: () => this.panBy(pan, 0), ArrowRight: () => this.panBy(-pan, 0),
        ArrowUp: () => this.panBy(0, pan), ArrowDown: () => this.panBy(0, -pan),
      };
      if (actions[e.key]) {
        e.preventDefault();
        actions[e.key]();
      }
    });
    new ResizeObserver(() => { if (this.fitted) this.fit(); }).observe(stage);
  }

  /** The content's natural size changed (a new image); refits unless the size is the same. */
  setSize(width, height) {
    const same = width === this.width && height === this.height;
    this.width = width;
    this.height = height;
    if (!same || this.fitted) this.fit();
  }

  fit() {
    const w = this.stage.clientWidth, h = this.stage.clientHeight;
    if (!this.width || !w || !h) return;
    this.scale = Math.min(w / this.width, h / this.height);
    this.x = (w - this.width * this.scale) / 2;
    this.y = (h - this.height * this.scale) / 2;
    this.fitted = true;
    this.apply();
  }

  one() {
    const w = this.stage.clientWidth, h = this.stage.clientHeight;
    this.zoomBy(1 / this.scale, w / 2, h / 2);
  }

  /** Multiplies the scale, keeping the stage point (cx, cy) in place (default: the centre). */
  zoomBy(factor, cx = this.stage.clientWidth / 2, cy = this.stage.clientHeight / 2) {
    if (!this.width) return;
    const scale = Math.min(MAX, Math.max(MIN, this.scale * factor));
    this.x = cx - (cx - this.x) * (scale / this.scale);
    this.y = cy - (cy - this.y) * (scale / this.scale);
    this.scale = scale;
    this.fitted = false;
    this.apply();
  }

  panBy(dx, dy) {
    this.x += dx;
    this.y += dy;
    this.fitted = false;
    this.apply();
  }

  apply() {
    // Keep some of the image in view.
    const w = this.stage.clientWidth, h = this.stage.clientHeight, margin = 32;
    const sw = this.width * this.scale, sh = this.height * this.scale;
    this.x = Math.min(w - margin, Math.max(margin - sw, this.x));
    this.y = Math.min(h - margin, Math.max(margin - sh, this.y));
    this.content.style.transform = `translate(${this.x}px, ${this.y}px) scale(${this.scale})`;
    this.stage.classList.toggle('pixelated', this.scale >= 2);
    this.stage.dataset.scale = this.scale.toFixed(4);
  }
}
