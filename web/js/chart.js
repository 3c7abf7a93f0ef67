// A log-log line chart in inline SVG: estimated relative error against seconds, one series per
// job, from its convergence log ([{pass, seconds, relative_error}]; the first pass has no error).

const NS = 'http://www.w3.org/2000/svg';
const W = 560, H = 260, M = {left: 56, right: 14, top: 12, bottom: 40};

function el(tag, attrs = {}, text) {
  const e = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (text !== undefined) e.textContent = text;
  return e;
}

/** Decades and their 2x and 5x between lo and hi (both > 0), for ticks on a log axis. */
function logTicks(lo, hi) {
  const ticks = [];
  for (let e = Math.floor(Math.log10(lo)); e <= Math.ceil(Math.log10(hi)); e++) {
    for (const m of [1, 2, 5]) {
      const v = m * Math.pow(10, e);
      if (v >= lo * 0.999 && v <= hi * 1.001) ticks.push({v, major: m === 1});
    }
  }
  return ticks;
}

const label = v => (v >= 1e4 || v < 1e-3 ? v.toExponential(0).replace('e+', 'e') : String(+v.toPrecision(3)));

/**
 * Draws the chart into `container`.
 * @param series [{name, label, color, points: [{seconds, relative_error}]}]
 */
export function drawChart(container, series) {
  const data = series.map(s => ({...s, points: (s.points || [])
    .filter(p => p.seconds > 0 && p.relative_error > 0)
    .map(p => [p.seconds, p.relative_error])}));
  const all = data.flatMap(s => s.points);
  const svg = el('svg', {viewBox: `0 0 ${W} ${H}`, role: 'img', 'data-series': String(data.filter(s => s.points.length).length)});
  const summary = data.map(s => `${s.name} (${s.label}): ${s.points.length ? `${(100 * s.points.at(-1)[1]).toPrecision(3)}% after ${s.points.at(-1)[0].toPrecision(3)} s` : 'no error estimates'}`);
  svg.append(el('title', {}, `Relative error against time, log-log. ${summary.join('; ')}.`));
  const legend = document.createElement('ul');
  legend.className = 'legend';
  for (const s of data) {
    const li = document.createElement('li');
    li.style.setProperty('--c', s.color);
    li.textContent = `${s.name}: ${s.label}`;
    legend.append(li);
  }
  container.replaceChildren(svg, legend);
  if (!all.length) {
    svg.append(el('text', {x: W / 2, y: H / 2, 'text-anchor': 'middle'}, 'No error estimates yet (they need two passes)'));
    return;
  }
  // Axis ranges padded to whole 2-5-10 steps.
  const pad = (lo, hi) => {
    let a = Math.log10(lo), b = Math.log10(hi);
    if (b - a < 0.3) { const c = (a + b) / 2; a = c - 0.15; b = c + 0.15; }
    return [Math.pow(10, a - 0.05 * (b - a)), Math.pow(10, b + 0.05 * (b - a))];
  };
  const [x0, x1] = pad(Math.min(...all.map(p => p[0])), Math.max(...all.map(p => p[0])));
  const [y0, y1] = pad(Math.min(...all.map(p => p[1])), Math.max(...all.map(p => p[1])));
  const px = x => M.left + (Math.log10(x / x0) / Math.log10(x1 / x0)) * (W - M.left - M.right);
  const py = y => H - M.bottom - (Math.log10(y / y0) / Math.log10(y1 / y0)) * (H - M.top - M.bottom);

  const grid = el('g');
  for (const {v, major} of logTicks(x0, x1)) {
    grid.append(el('line', {class: 'grid', x1: px(v), x2: px(v), y1: M.top, y2: H - M.bottom}));
    if (major || logTicks(x0, x1).length < 8) grid.append(el('text', {x: px(v), y: H - M.bottom + 14, 'text-anchor': 'middle'}, label(v)));
  }
  for (const {v, major} of logTicks(y0, y1)) {
    grid.append(el('line', {class: 'grid', x1: M.left, x2: W - M.right, y1: py(v), y2: py(v)}));
    if (major || logTicks(y0, y1).length < 8) grid.append(el('text', {x: M.left - 5, y: py(v) + 4, 'text-anchor': 'end'}, `${label(100 * v)}%`));
  }
  svg.append(grid,
    el('line', {class: 'axis', x1: M.left, x2: M.left, y1: M.top, y2: H - M.bottom}),
    el('line', {class: 'axis', x1: M.left, x2: W - M.right, y1: H - M.bottom, y2: H - M.bottom}),
    el('text', {x: (M.left + W - M.right) / 2, y: H - 6, 'text-anchor': 'middle'}, 'seconds (log)'),
    el('text', {x: 12, y: (M.top + H - M.bottom) / 2, 'text-anchor': 'middle',
      transform: `rotate(-90 12 ${(M.top + H - M.bottom) / 2})`}, 'relative error (log)'));

  data.forEach((s, i) => {
    if (!s.points.length) return;
    const g = el('g', {class: 'series-group', 'data-name': s.name});
    g.append(el('polyline', {class: 'series', stroke: s.color,
      points: s.points.map(([x, y]) => `${px(x).toFixed(1)},${py(y).toFixed(1)}`).join(' ')}));
    for (const [x, y] of s.points) g.append(el('circle', {cx: px(x), cy: py(y), r: 2.5, fill: s.color}));
    // Legend, top right.
    const ly = M.top + 8 + 16 * i;
    g.append(el('line', {x1: W - M.right - 40, x2: W - M.right - 20, y1: ly, y2: ly, stroke: s.color, 'stroke-width': 3}),
      el('text', {x: W - M.right - 15, y: ly + 4}, s.name));
    svg.append(g);
  });
}
