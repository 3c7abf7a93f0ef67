// Browser tests of the web page (web/), against the real `caustic serve` that tests/web/run.sh
// starts: Debian's Chromium, headless, driven by playwright-core. Every test opens its own page
// and fails on any console error or uncaught exception it did not expect. Screenshots go to
// $CAUSTIC_WEB_SCREENSHOTS; the page weight of a first load is printed.
import assert from 'node:assert/strict';
import {readFileSync} from 'node:fs';
import path from 'node:path';
import {after, before, test} from 'node:test';
import {fileURLToPath} from 'node:url';

import {api, BASE, closeBrowser, itemOf, launch, MAX_SPP, NARROW, openPage, RENDER_TIMEOUT,
  selectExample, shot, smallScene, submit, watchErrors, WIDE} from './browser.mjs';

let browser;
const shared = {};  // jobs made by one test for later ones

before(async () => { browser = await launch(); });
after(closeBrowser);

test('page weight on first load (an empty server, no cache)', async () => {
  const context = await browser.newContext({viewport: WIDE});
  const page = await context.newPage();
  const check = watchErrors(page);
  // Every response's transferred bytes (headers and body), from the browser's network log.
  const cdp = await context.newCDPSession(page);
  await cdp.send('Network.enable');
  const sizes = new Map(), paths = new Map();
  cdp.on('Network.responseReceived', e => paths.set(e.requestId, new URL(e.response.url).pathname));
  cdp.on('Network.loadingFinished', e => sizes.set(e.requestId, e.encodedDataLength));
  await page.goto(`${BASE}/`, {waitUntil: 'networkidle'});
  await page.waitForSelector('body[data-ready=true]');
  const total = [...sizes.values()].reduce((a, b) => a + b, 0);
  const statics = [...sizes].filter(([id]) => !(paths.get(id) || '').startsWith('/api/'))
    .reduce((a, [, n]) => a + n, 0);
  console.log(`page weight: ${total} bytes transferred in ${sizes.size} responses (static files ` +
    `${statics} bytes): ${[...sizes].map(([id, n]) => `${paths.get(id)} ${n}`).join(', ')}`);
  assert.ok(total < 120_000, `page weight ${total} bytes`);
  await context.close();
  check();
});

test('the settings form follows /api/settings: only the integrator\'s options, API ranges and defaults', async () => {
  const schema = (await api('/api/settings')).body;
  const {page, close} = await openPage();
  const firstSelects = await page.$$eval('#settings fieldset', sets => sets.slice(0, 2).map(s => s.querySelector('select').id));
  assert.deepEqual(firstSelects, ['s-preset', 's-integrator'], 'the preset comes first, then the integrator');
  for (const integrator of schema.integrator.enum) {
    await page.selectOption('#s-integrator', integrator);
    const fields = await page.$$eval('[data-setting]', els => els.map(el => {
      const input = el.querySelector('input, select');
      return {name: el.dataset.setting, shown: !el.hidden && !el.closest('[hidden]'), tag: input.tagName,
        type: input.type, min: input.getAttribute('min'), max: input.getAttribute('max'),
        step: input.getAttribute('step'), value: input.type === 'checkbox' ? input.checked : input.value,
        disabled: input.disabled, options: input.tagName === 'SELECT' ? [...input.options].map(o => o.value) : null,
        label: input.labels.length > 0};
    }));
    assert.deepEqual(fields.map(f => f.name).sort(), Object.keys(schema).sort(), 'one field per setting');
    // The form starts at the API's defaults, with the default preset's (auto) settings over them.
    const presetSets = schema.preset.presets[schema.preset.default].settings;
    for (const f of fields) {
      const spec = {...schema[f.name]};
      if (f.name in presetSets) spec.default = presetSets[f.name];
      // With every setting at its default: path's caustics and indirect light are path traced, so
      // its photon settings (only_with one of caustics or indirect = photon_map) stay hidden.
      const alternatives = (spec.only_with || {})[integrator];
      const used = (spec.integrators.length === 0 || spec.integrators.includes(integrator)) &&
        (!alternatives || alternatives.some(needs => Object.entries(needs).every(
          ([name, value]) => schema[name].default === value)));
      assert.equal(f.shown, used, `${integrator}: ${f.name} shown`);
      assert.equal(f.disabled, !used, `${integrator}: ${f.name} disabled when hidden`);
      assert.ok(f.label, `${f.name} has a label`);
      if (spec.type === 'boolean') {
        assert.equal(f.type, 'checkbox', f.name);
        assert.equal(f.value, spec.default, `${f.name} default`);
      } else if (spec.enum) {
        assert.equal(f.tag, 'SELECT', f.name);
        assert.deepEqual(f.options, spec.enum, `${f.name} options`);
        if (f.name !== 'integrator') assert.equal(f.value, spec.default, `${f.name} default`);
      } else {
        assert.equal(f.type, 'number', f.name);
        assert.equal(Number(f.min), spec.minimum, `${f.name} min`);
        assert.equal(Number(f.max), spec.maximum, `${f.name} max`);
        assert.equal(f.step, spec.type === 'integer' ? '1' : 'any', `${f.name} step`);
        // The example scene (cornell-box) sets spp; the rest start at the API's default.
        if (f.name !== 'spp') assert.equal(Number(f.value), spec.default, `${f.name} default`);
      }
    }
  }
  const spp = await page.inputValue('#s-spp');
  assert.equal(spp, '64', 'the example scene\'s own settings fill the form');
  await page.selectOption('#s-integrator', 'photon');
  await page.$eval('[data-group=options]', el => el.scrollIntoView());
  await shot(page, 'settings-photon');
  // Path shows its caustic map's settings once its caustics come from a photon map.
  const shown = sel => page.$eval(sel, el => !el.closest('[hidden]') && !el.disabled);
  await page.selectOption('#s-integrator', 'path');
  assert.equal(await shown('#s-photons'), false, 'path tracing alone reads no photons');
  await page.selectOption('#s-caustics', 'photon_map');
  for (const name of ['photons', 'radius', 'alpha', 'kernel', 'photon_lookup'])
    assert.equal(await shown(`#s-${name}`), true, `${name} with photon_map caustics`);
  assert.equal(await shown('#s-caustic_photons'), false, 'caustic_photons is not path\'s');
  assert.equal(await shown('#s-indirect_photons'), false, 'the indirect map\'s only with it');
  await page.selectOption('#s-caustics', 'paths');
  assert.equal(await shown('#s-photons'), false, 'hidden again with paths');
  // The indirect map shows its own settings and those both maps read, not the caustic map's.
  await page.selectOption('#s-indirect', 'photon_map');
  for (const name of ['indirect_photons', 'indirect_radius', 'alpha', 'kernel', 'photon_lookup'])
    assert.equal(await shown(`#s-${name}`), true, `${name} with a photon_map for indirect light`);
  for (const name of ['photons', 'radius'])
    assert.equal(await shown(`#s-${name}`), false, `${name} is the caustic map's`);
  await page.selectOption('#s-indirect', 'paths');
  assert.equal(await shown('#s-alpha'), false, 'hidden again without photon maps');
  await close();
});

test('presets: choosing one fills in what it sets; fields stay editable and win; none restores the scene\'s', async () => {
  const schema = (await api('/api/settings')).body;
  const presets = schema.preset.presets;
  assert.deepEqual(Object.keys(presets).sort(), ['auto', 'draft', 'final', 'preview']);
  const {page, close} = await openPage();
  assert.deepEqual(await page.$$eval('#s-preset option', os => os.map(o => o.value)),
    ['none', 'auto', 'draft', 'preview', 'final'], 'the menu lists auto, then the rest fastest first');
  await selectExample(page, 'cornell-box');
  assert.equal(await page.inputValue('#s-preset'), 'auto', 'auto is the default');
  assert.equal(await page.inputValue('#s-spp'), '64', 'the scene\'s spp');
  const shown = async key => (schema[key].type === 'boolean' ? String(await page.isChecked(`#s-${key}`))
    : page.inputValue(`#s-${key}`));
  for (const name of Object.keys(presets)) {
    await page.selectOption('#s-preset', name);
    for (const [key, value] of Object.entries(presets[name].settings))
      assert.equal(await shown(key), String(value), `${name} sets ${key}`);
  }
  // Under a target error auto renders in smaller passes (its under_target), as the API merges it;
  // a pass size set by hand stays.
  await page.selectOption('#s-preset', 'auto');
  const [loose, tight] = presets.auto.under_target;
  await page.fill('#s-target_error', String(loose.target_error));
  assert.equal(await page.inputValue('#s-spp_per_pass'), String(loose.settings.spp_per_pass));
  await page.fill('#s-target_error', String(tight.target_error));
  assert.equal(await page.inputValue('#s-spp_per_pass'), String(tight.settings.spp_per_pass));
  await page.fill('#s-target_error', '0');
  assert.equal(await page.inputValue('#s-spp_per_pass'), String(presets.auto.settings.spp_per_pass));
  await page.fill('#s-spp_per_pass', '5');
  await page.fill('#s-target_error', '0.05');
  assert.equal(await page.inputValue('#s-spp_per_pass'), '5', 'a pass size set by hand stays');
  await page.selectOption('#s-preset', 'none');
  assert.equal(await page.inputValue('#s-spp'), '64', 'none restores the scene\'s spp');
  assert.equal(await page.inputValue('#s-sampler'), schema.sampler.default);

  // The draft, on a small image, with one field changed by hand: the job has the preset's settings
  // but that one. The image size group's width alone widens the 16 x 16 camera to 24 x 24.
  await smallScene(page, 16);
  await page.selectOption('#s-preset', 'draft');
  await page.fill('#s-spp', '8');
  assert.equal(await page.inputValue('[data-group=image] #s-width'), '0');
  await page.fill('#s-width', '24');
  const {status, body: job} = await submit(page);
  assert.equal(status, 202);
  assert.equal(job.settings.preset, 'draft');
  assert.equal(job.settings.spp, 8);
  assert.deepEqual([job.settings.width, job.settings.height], [24, 24]);
  for (const [key, value] of Object.entries(presets.draft.settings))
    if (key !== 'spp' && key !== 'spp_per_pass') assert.equal(job.settings[key], value, `the job's ${key}`);
  // The preset's 4 a pass, cut to leave the 8 spp asked 8 passes.
  assert.equal(job.settings.spp_per_pass, 1);
  await page.waitForSelector(`${itemOf(job.id)}[data-state=succeeded]`, {timeout: RENDER_TIMEOUT});
  const png = new DataView(await (await fetch(`${BASE}/api/jobs/${job.id}/image.png`)).arrayBuffer());
  assert.deepEqual([png.getUint32(16), png.getUint32(20)], [24, 24], 'the PNG\'s IHDR size');
  await close();
});

test('submit a job: live progress, the preview, then the final image with its stats', async () => {
  const {page, close} = await openPage();
  await selectExample(page, 'cornell-box');
  await smallScene(page, 64);
  await page.selectOption('#s-integrator', 'path');
  await page.fill('#s-spp', '400');
  await page.fill('#s-spp_per_pass', '1');
  const {status, body: job} = await submit(page);
  assert.equal(status, 202);
  shared.first = job.id;
  // Sample the queue item and the viewer every 40 ms until the job has succeeded.
  await page.waitForSelector(itemOf(job.id));
  await page.evaluate(sel => {
    window.samples = [];
    const tick = () => {
      const li = document.querySelector(sel);
      const canvas = document.querySelector('#viewer-canvas');
      window.samples.push({value: li.querySelector('progress').value, state: li.dataset.state,
        meta: li.querySelector('.job-meta').textContent, kind: canvas.dataset.kind || '',
        width: canvas.width});
      if (li.dataset.state !== 'succeeded') setTimeout(tick, 40);
    };
    tick();
  }, itemOf(job.id));
  await page.waitForSelector(`${itemOf(job.id)}[data-state=running]`, {timeout: RENDER_TIMEOUT});
  await shot(page, 'rendering');
  await page.waitForSelector(`${itemOf(job.id)}[data-state=succeeded]`, {timeout: RENDER_TIMEOUT});
  const samples = await page.evaluate(() => window.samples);
  const running = samples.filter(s => s.state === 'running');
  const partial = [...new Set(running.map(s => s.value).filter(v => v > 0 && v < 1))];
  assert.ok(partial.length >= 2, `progress seen at ${partial.length} values between 0 and 1`);
  for (let i = 1; i < samples.length; i++)
    assert.ok(samples[i].value >= samples[i - 1].value, 'progress never goes back');
  assert.ok(running.some(s => /pass ([1-9]\d*)\/400/.test(s.meta) && !/pass 400\//.test(s.meta)),
    'passes shown while running');
  assert.ok(running.some(s => /ETA/.test(s.meta)), 'ETA shown while running');
  assert.ok(samples.some(s => s.kind === 'preview' && s.width === 64), 'the live preview was shown');
  console.log(`progress values seen while running: ${partial.length}`);

  // The result: image.png at its natural size, downloads, stats.
  await page.waitForSelector('#viewer-canvas[data-kind=image]');
  const canvas = await page.$eval('#viewer-canvas', c => ({w: c.width, h: c.height, src: c.dataset.src}));
  assert.deepEqual(canvas, {w: 64, h: 64, src: `/api/jobs/${job.id}/image.png`});
  for (const [text, type] of [['PNG', 'image/png'], ['EXR', 'image/x-exr']]) {
    const href = await page.getAttribute(`#downloads a:text("${text}")`, 'href');
    const res = await fetch(BASE + href);
    assert.equal(res.status, 200, href);
    assert.equal(res.headers.get('content-type'), type);
    assert.ok(await page.getAttribute(`#downloads a:text("${text}")`, 'download'));
  }
  const stats = await page.$$eval('#stats dd', dds => Object.fromEntries(dds.map(d => [d.dataset.stat, d.textContent])));
  for (const key of ['time', 'rays_per_second', 'relative_error', 'passes', 'spp', 'memory'])
    assert.ok(stats[key] && stats[key] !== '—', `stat ${key}: ${stats[key]}`);
  assert.match(stats.passes, /^400 /);
  assert.equal(stats.spp, '400');
  assert.match(stats.rays_per_second, /rays\/s/);
  assert.equal(stats.photons, undefined, 'no photon count for a path tracer');
  // The time shown, in the stats and on the queue card, is the job's wall time: loading, setup,
  // passes and images, so at least its render time.
  const done = await (await fetch(`${BASE}/api/jobs/${job.id}`)).json();
  assert.ok(done.stats.render_seconds > 0 && done.stats.total_seconds >= done.stats.render_seconds,
    JSON.stringify(done.stats));
  const total = await page.evaluate(async t => (await import('/js/format.js')).seconds(t),
    done.stats.total_seconds);
  assert.ok(stats.time.startsWith(`${total} (`), `${stats.time}, expected ${total}`);
  const card = await page.textContent(`${itemOf(job.id)} .job-meta`);
  assert.ok(card.endsWith(` · ${total}`), `${card}, expected ${total}`);
  await shot(page, 'result');

  // Exposure: +1 EV doubles linear values (decode sRGB, scale, encode).
  const pixels = () => page.$eval('#viewer-canvas', c => Array.from(c.getContext('2d').getImageData(0, 0, c.width, c.height).data));
  const base = await pixels();
  await page.focus('#exposure');
  for (let i = 0; i < 10; i++) await page.keyboard.press('ArrowRight');
  assert.equal(await page.textContent('#exposure-out'), '+1.0 EV');
  const bright = await pixels();
  const lin = v => (v <= 0.04045 ? v / 12.92 : ((v + 0.055) / 1.055) ** 2.4);
  const srgb = v => (v <= 0.0031308 ? 12.92 * v : 1.055 * v ** (1 / 2.4) - 0.055);
  let worst = 0;
  for (let i = 0; i < base.length; i++) {
    if (i % 4 === 3) continue;
    const expected = Math.round(255 * srgb(Math.min(1, 2 * lin(base[i] / 255))));
    worst = Math.max(worst, Math.abs(bright[i] - expected));
  }
  assert.ok(worst <= 1, `exposure off by ${worst} codes`);
  assert.ok(bright.some((v, i) => v !== base[i]), 'exposure changed the image');

  // Zoom (buttons, wheel, keys) and pan (drag).
  const scale = () => page.$eval('#viewer-stage', s => Number(s.dataset.scale));
  const transform = () => page.$eval('#viewer-stage .content', c => c.style.transform);
  const fit = await scale();
  await page.click('#viewer [data-zoom=in]');
  assert.ok(Math.abs(await scale() - fit * 1.25) < 1e-3, 'zoom in button');
  const box = await page.locator('#viewer-stage').boundingBox();
  await page.mouse.move(box.x + box.width / 2, box.y + box.height / 2);
  await page.mouse.wheel(0, -120);
  await page.waitForFunction(s => Number(document.querySelector('#viewer-stage').dataset.scale) > s, fit * 1.25 + 1e-3);
  const before = await transform();
  await page.mouse.down();
  await page.mouse.move(box.x + box.width / 2 + 60, box.y + box.height / 2 + 30, {steps: 4});
  await page.mouse.up();
  assert.notEqual(await transform(), before, 'dragging pans');
  await page.focus('#viewer-stage');
  await page.keyboard.press('0');
  assert.ok(Math.abs(await scale() - fit) < 1e-3, '0 fits again');
  await page.keyboard.press('1');
  assert.equal(await scale(), 1, '1 shows 1:1');
  await close();
});

test('compare two finished renders: split view, difference and the error chart', async () => {
  assert.ok(shared.first, 'needs the job of the previous test');
  const {page, close} = await openPage();
  // A second job, a photon mapper (its options shown once chosen), from the page.
  await smallScene(page, 64);
  await page.selectOption('#s-integrator', 'photon');
  assert.ok(await page.isVisible('#s-photons'));
  assert.ok(!(await page.isVisible('#s-light_sampling')));
  await page.fill('#s-photons', '5000');
  await page.fill('#s-spp', '16');
  const {status, body: job} = await submit(page);
  assert.equal(status, 202);
  shared.second = job.id;
  await page.waitForSelector(`${itemOf(job.id)}[data-state=succeeded]`, {timeout: RENDER_TIMEOUT});
  await page.waitForSelector('#viewer-canvas[data-kind=image]');
  const photons = await page.textContent('#stats dd[data-stat=photons]');
  // 5000 a pass; auto's 16 a pass, cut to 2 to leave the 16 spp 8 passes.
  assert.match(photons, /40\.0 k photon paths/, 'photon integrators show their photon count');

  await page.click('#tab-compare');
  await page.selectOption('#compare-a', shared.first);
  await page.selectOption('#compare-b', shared.second);
  await page.waitForFunction(() => document.querySelector('#compare-b-canvas').width === 64 &&
    document.querySelector('#chart svg[data-series="2"]'));
  assert.equal(await page.$eval('#compare-a-canvas', c => c.width), 64);
  assert.ok(await page.isVisible('#compare-a-canvas'));
  assert.ok(await page.isVisible('#compare-b-canvas'));
  assert.equal(await page.$eval('#compare-b-canvas', c => c.style.clipPath), 'inset(0px 0px 0px 50%)');
  // The split slider, by keyboard.
  await page.focus('#split');
  for (let i = 0; i < 25; i++) await page.keyboard.press('ArrowLeft');
  assert.equal(await page.$eval('#compare-b-canvas', c => c.style.clipPath), 'inset(0px 0px 0px 25%)');
  assert.equal(await page.$eval('#divider', d => d.style.left), '16px');
  // The chart: two series, log-log, points from each job's convergence log.
  const chart = await page.$eval('#chart svg', svg => ({
    series: [...svg.querySelectorAll('polyline.series')].map(p => p.getAttribute('points').split(' ').length),
    legend: [...document.querySelectorAll('#chart .legend li')].map(li => li.textContent)}));
  const expected = [];
  for (const id of [shared.first, shared.second]) {
    const j = (await api(`/api/jobs/${id}`)).body;
    expected.push(j.convergence.filter(p => p.relative_error > 0 && p.seconds > 0).length);
  }
  assert.deepEqual(chart.series, expected, 'one polyline per job with every estimate');
  assert.equal(chart.legend.length, 2);
  assert.ok(await page.isVisible('#chart svg'));
  await shot(page, 'compare-split');
  // The difference view.
  await page.check('input[name=compare-mode][value=diff]');
  await page.waitForSelector('#compare-diff:not([hidden])');
  assert.ok(!(await page.isVisible('#compare-b-canvas')));
  const diff = await page.$eval('#compare-diff', c => {
    const d = c.getContext('2d').getImageData(0, 0, c.width, c.height).data;
    let nonzero = 0;
    for (let i = 0; i < d.length; i += 4) if (d[i] || d[i + 1] || d[i + 2]) nonzero++;
    return {w: c.width, h: c.height, nonzero};
  });
  assert.equal(diff.w, 64);
  assert.ok(diff.nonzero > 100, `the difference has ${diff.nonzero} non-black pixels`);
  assert.match(await page.textContent('#compare-note'), /mean absolute difference/);
  await shot(page, 'compare-difference');
  await close();
});

test('validation errors are shown where their pointer says', async () => {
  const schema = (await api('/api/settings')).body;
  const {page, close} = await openPage();
  await smallScene(page, 64);
  await page.selectOption('#s-integrator', 'path');

  // A setting over the server's limit: the message beside its input, which gets focus.
  await page.fill('#s-spp', String(MAX_SPP + 1));
  const {status, body, request} = await submit(page);
  assert.equal(status, 422);
  assert.equal(body.pointer, '/settings/spp');
  const sent = JSON.parse(request.postData()).settings;
  // Path's caustics are path traced by default: its caustic map's settings (only_with) stay out;
  // and under auto, which chooses the maps for the scene, so do caustics and indirect left as they
  // were.
  const shown = Object.keys(schema).filter(n => (schema[n].integrators.length === 0 ||
    schema[n].integrators.includes('path')) && !(schema[n].only_with || {}).path &&
    n !== 'caustics' && n !== 'indirect');
  assert.deepEqual(Object.keys(sent).sort(), shown.sort(), 'only the shown settings are sent');
  await page.waitForSelector('#s-spp-error:not(:empty)');
  assert.match(await page.textContent('#s-spp-error'), new RegExp(`at most ${MAX_SPP}`));
  assert.equal(await page.getAttribute('#s-spp', 'aria-invalid'), 'true');
  assert.equal(await page.evaluate(() => document.activeElement.id), 's-spp');
  assert.ok((await page.getAttribute('#s-spp', 'aria-describedby')).includes('s-spp-error'));
  await shot(page, 'error-setting');
  // Typing clears it.
  await page.fill('#s-spp', '4');
  assert.equal(await page.textContent('#s-spp-error'), '');

  // Out of the API's range: the browser's own check, at the field, with no request.
  let posted = false;
  page.on('request', r => { if (r.method() === 'POST') posted = true; });
  await page.fill('#s-max_depth', '0');
  await page.click('#submit-button');
  await page.waitForSelector('#s-max_depth-error:not(:empty)');
  assert.ok(!posted, 'nothing sent with an invalid field');
  await page.fill('#s-max_depth', '5');

  // A scene path: listed under the editor with its path, the value selected in the editor.
  const scene = JSON.parse(await page.inputValue('#scene-json'));
  scene.camera.width = 99999;
  await page.fill('#scene-json', JSON.stringify(scene, null, 2));
  const second = await submit(page);
  assert.equal(second.status, 422);
  assert.equal(second.body.pointer, '/scene/camera/width');
  await page.waitForSelector('#scene-errors li');
  assert.equal(await page.textContent('#scene-errors li code'), '/scene/camera/width');
  assert.match(await page.textContent('#scene-errors li'), /must be in \[1, \d+\], got 99999/);
  const selected = await page.$eval('#scene-json', t => t.value.slice(t.selectionStart, t.selectionEnd));
  assert.equal(selected, '99999');
  assert.equal(await page.getAttribute('#scene-json', 'aria-invalid'), 'true');
  await shot(page, 'error-scene');

  // Not JSON at all: said under the editor, nothing sent.
  posted = false;
  await page.fill('#scene-json', '{"camera": ');
  await page.click('#submit-button');
  await page.waitForSelector('#scene-errors li');
  assert.match(await page.textContent('#scene-errors li'), /not valid JSON/);
  assert.ok(!posted);
  // The browser logs the two 422 responses; nothing else.
  const errors = await close([/status of 422/]);
  assert.equal(errors.length, 2, errors.join('\n'));
});

test('queue: a running job shows its ETA, can be cancelled and deleted', async () => {
  const {page, close} = await openPage();
  await selectExample(page, 'cornell-box');
  await page.selectOption('#s-integrator', 'path');
  await page.fill('#s-spp', String(MAX_SPP));
  await page.fill('#s-spp_per_pass', '1');
  await page.fill('#s-time_limit', '60');
  const {status, body: job} = await submit(page);
  assert.equal(status, 202);
  assert.equal((await api(`/api/jobs/${job.id}`)).body.scene_name, 'cornell-box',
    'an unchanged example is sent by name');
  const item = itemOf(job.id);
  await page.waitForSelector(`${item}[data-state=running]`, {timeout: RENDER_TIMEOUT});
  await page.waitForFunction(sel => /ETA \d/.test(document.querySelector(`${sel} .job-meta`).textContent), item);
  await page.click(`${item} button:text("Cancel")`);
  await page.waitForSelector(`${item}[data-state=cancelled]`, {timeout: 60_000});
  assert.ok(!(await page.isVisible(`${item} button:text("Cancel")`)), 'no Cancel once cancelled');
  await shot(page, 'queue-cancelled');
  await page.click(`${item} button:text("Delete")`);
  await page.waitForSelector(item, {state: 'detached'});
  assert.equal((await api(`/api/jobs/${job.id}`)).status, 404);
  assert.notEqual(await page.evaluate(() => location.hash), `#job=${job.id}`);
  await close();
});

// A real mesh from the repository: small enough to upload and render in a moment.
const MESHES = fileURLToPath(new URL('../../assets/meshes/', import.meta.url));
/** Triangles and vertices of an OBJ, counted here (a face of n corners makes n - 2 triangles). */
function objCounts(text) {
  let triangles = 0, vertices = 0;
  for (const line of text.split('\n')) {
    const words = line.trim().split(/\s+/);
    if (words[0] === 'v') vertices++;
    else if (words[0] === 'f') triangles += words.length - 3;
  }
  return {triangles, vertices};
}

// The repository's glTF example (Blender's export, Draco-compressed): a whole scene.
const MODELS = fileURLToPath(new URL('../../assets/models/', import.meta.url));

test('gltf: drop a .glb, see its thumbnail, choose a camera, use it as the scene, get the render', async () => {
  const {page, close} = await openPage();
  await selectExample(page, 'cornell-box');
  await smallScene(page, 64);
  const bytes = readFileSync(path.join(MODELS, 'still-life.glb'));
  const transfer = await page.evaluateHandle(b64 => {
    const body = Uint8Array.from(atob(b64), c => c.charCodeAt(0));
    const dt = new DataTransfer();
    dt.items.add(new File([body], 'still-life.glb'));
    return dt;
  }, bytes.toString('base64'));
  const uploaded = page.waitForResponse(r => r.url().startsWith(`${BASE}/api/assets`) && r.request().method() === 'POST');
  const thumbnailJob = page.waitForResponse(r => r.url() === `${BASE}/api/jobs` && r.request().method() === 'POST');
  await page.dispatchEvent('#asset-drop', 'drop', {dataTransfer: transfer});
  const response = await uploaded;
  assert.ok([200, 201].includes(response.status()), `upload: ${response.status()}`);
  assert.equal(response.request().headers()['content-type'], 'model/gltf-binary');
  const asset = await response.json();
  assert.equal(asset.model.cameras.length, 1, 'the file has one camera');
  const item = `.asset[data-id="${asset.id}"]`;
  await page.waitForSelector(item);

  // The thumbnail: a quick job of the model through the automatic camera, shown in its item.
  const thumb = (await (await thumbnailJob).json());
  assert.deepEqual(thumb.model.camera, {auto: {azimuth: 30, elevation: 20, fov: 40}});
  await page.waitForSelector(`${item} .asset-thumb:not([hidden])`, {timeout: RENDER_TIMEOUT});
  await page.waitForFunction(sel => document.querySelector(sel).naturalWidth === 192,
    `${item} .asset-thumb`, {timeout: RENDER_TIMEOUT});

  // The camera choice: the file's camera (chosen first) and the automatic one.
  await page.waitForSelector(`${item} .asset-camera[data-ready=true]`);
  const options = await page.$$eval(`${item} .asset-camera option`, os => os.map(o => [o.value, o.textContent]));
  assert.deepEqual(options, [['auto', 'automatic camera'], ['0', 'Camera']]);
  assert.equal(await page.inputValue(`${item} .asset-camera`), '0');
  await shot(page, 'gltf-uploaded');

  // Use as scene with the automatic camera, then Render: the job renders the model.
  await page.selectOption(`${item} .asset-camera`, 'auto');
  await page.click(`${item} button:text("Use as scene")`);
  const scene = JSON.parse(await page.inputValue('#scene-json'));
  assert.deepEqual(scene, {gltf: {asset: asset.id}, camera: {auto: {}}});
  await page.selectOption('#s-integrator', 'path');
  await page.fill('#s-spp', '8');
  await page.fill('#s-width', '96');  // the height follows the automatic camera's 4:3
  const {status, body: job} = await submit(page);
  assert.equal(status, 202, JSON.stringify(job));
  assert.deepEqual(job.model.camera, {auto: {azimuth: 30, elevation: 20, fov: 40}});
  await page.waitForSelector(`${itemOf(job.id)}[data-state=succeeded]`, {timeout: RENDER_TIMEOUT});
  await page.waitForSelector('#viewer-canvas[data-kind=image]');
  assert.deepEqual(await page.$eval('#viewer-canvas', c => ({w: c.width, h: c.height, src: c.dataset.src})),
    {w: 96, h: 72, src: `/api/jobs/${job.id}/image.png`});
  const done = (await api(`/api/jobs/${job.id}`)).body;
  assert.ok(done.stats.memory.meshes > 0, 'the render loaded the model\'s meshes');
  await shot(page, 'gltf-rendered');
  await close();
});

test('assets: drop a mesh, see its counts, insert it, render it; delete refused while used, then deleted', async () => {
  const {page, close} = await openPage();
  await selectExample(page, 'cornell-box');
  await smallScene(page, 64);

  // Drag and drop the teapot onto the panel: a DataTransfer holding a File, made in the page.
  const text = readFileSync(path.join(MESHES, 'teapot.obj'), 'utf8');
  const transfer = await page.evaluateHandle(body => {
    const dt = new DataTransfer();
    dt.items.add(new File([body], 'teapot.obj'));
    return dt;
  }, text);
  const uploaded = page.waitForResponse(r => r.url().startsWith(`${BASE}/api/assets`) && r.request().method() === 'POST');
  for (const type of ['dragenter', 'dragover']) await page.dispatchEvent('#asset-drop', type, {dataTransfer: transfer});
  assert.ok(await page.$eval('#asset-drop', d => d.classList.contains('dropping')), 'the drop zone shows the drag');
  await page.dispatchEvent('#asset-drop', 'drop', {dataTransfer: transfer});
  const response = await uploaded;
  assert.equal(response.status(), 201);
  assert.equal(response.request().headers()['content-type'], 'model/obj');
  const asset = await response.json();
  assert.equal(asset.name, 'teapot.obj');
  assert.equal(asset.bytes, Buffer.byteLength(text), 'the whole file, as the raw body');
  assert.deepEqual({triangles: asset.triangles, vertices: asset.vertices}, objCounts(text));

  // Its counts and bounds in the list; the progress bar gone, the status saying what arrived.
  const item = `.asset[data-id="${asset.id}"]`;
  await page.waitForSelector(item);
  const facts = await page.$$eval(`${item} dd`, dds => Object.fromEntries(dds.map(d => [d.dataset.fact, d.textContent])));
  assert.equal(facts.triangles, asset.triangles.toLocaleString('en-US'));
  assert.equal(facts.vertices, asset.vertices.toLocaleString('en-US'));
  assert.match(facts.bounds, /^\[-3, 0, -2\] – \[3\.43, 3\.15, 2\]$/, 'the teapot\'s bounds');
  assert.ok(await page.isHidden('#asset-progress'));
  assert.match(await page.textContent('#asset-status'), /teapot\.obj: 6,320 triangles/);
  assert.ok(!(await page.$eval('#asset-drop', d => d.classList.contains('dropping'))));
  await shot(page, 'asset-uploaded');

  // Insert: a mesh shape referencing the asset, its largest side a third of the way to look_at,
  // centered there, with a material of the scene; the new shape selected in the editor.
  const before = JSON.parse(await page.inputValue('#scene-json'));
  await page.click(`${item} button:text("Insert")`);
  const scene = JSON.parse(await page.inputValue('#scene-json'));
  assert.equal(scene.shapes.length, before.shapes.length + 1);
  assert.deepEqual(scene.materials, before.materials, 'no material added: the scene has one');
  const shape = scene.shapes.at(-1);
  assert.equal(shape.type, 'mesh');
  assert.equal(shape.asset, asset.id);
  assert.equal(shape.material, 'white');
  const {position, look_at: lookAt} = scene.camera;
  const distance = Math.hypot(...lookAt.map((v, i) => v - position[i]));
  const {min, max} = asset.bounds;
  const largest = Math.max(...max.map((v, i) => v - min[i]));
  assert.ok(Math.abs(shape.transform.scale * largest - distance / 3) < 1e-3 * distance, 'a third of the distance');
  for (let i = 0; i < 3; i++) {
    const center = shape.transform.scale * (min[i] + max[i]) / 2 + shape.transform.translate[i];
    assert.ok(Math.abs(center - lookAt[i]) < 1e-3 * distance, `centered on look_at (axis ${i})`);
  }
  const selected = await page.$eval('#scene-json', t => t.value.slice(t.selectionStart, t.selectionEnd));
  assert.deepEqual(JSON.parse(selected), shape, 'the inserted shape is selected in the editor');
  assert.match(await page.textContent('#asset-status'), /Inserted teapot\.obj as \/shapes\/\d+/);

  // Render it; the result is shown, and the render holds the mesh.
  await page.selectOption('#s-integrator', 'path');
  await page.fill('#s-spp', '16');
  const {status, body: job} = await submit(page);
  assert.equal(status, 202);
  await page.waitForSelector(`${itemOf(job.id)}[data-state=succeeded]`, {timeout: RENDER_TIMEOUT});
  await page.waitForSelector('#viewer-canvas[data-kind=image]');
  assert.deepEqual(await page.$eval('#viewer-canvas', c => ({w: c.width, h: c.height, src: c.dataset.src})),
    {w: 64, h: 64, src: `/api/jobs/${job.id}/image.png`});
  const done = (await api(`/api/jobs/${job.id}`)).body;
  assert.ok(done.stats.memory.meshes > 0, 'the render loaded the mesh');
  await shot(page, 'asset-rendered');

  // Refused files: one that is no mesh (said here, nothing sent), one the server finds broken (its
  // problem detail, naming the line).
  await page.setInputFiles('#asset-file', {name: 'notes.txt', mimeType: 'text/plain', buffer: Buffer.from('hi')});
  assert.match(await page.textContent('#asset-error'), /notes\.txt: not a mesh this service takes/);
  const [refused] = await Promise.all([
    page.waitForResponse(r => r.url().startsWith(`${BASE}/api/assets`) && r.request().method() === 'POST'),
    page.setInputFiles('#asset-file', {name: 'broken.obj', mimeType: '', buffer: Buffer.from('v 0 0 0\nv 1 0 0\nf 1 2 7\n')}),
  ]);
  assert.equal(refused.status(), 422);
  await page.waitForFunction(() => /^broken\.obj: .*line 3/.test(document.querySelector('#asset-error').textContent));
  assert.ok(await page.isHidden('#asset-progress'));

  // A second mesh, from the file picker, sent at 256 KiB/s: the progress bar moves. Then Delete on
  // the teapot while a long job uses it: 409, its detail under the asset, which stays listed.
  const cdp = await page.context().newCDPSession(page);
  await cdp.send('Network.emulateNetworkConditions',
    {offline: false, latency: 0, downloadThroughput: -1, uploadThroughput: 256 * 1024});
  await page.evaluate(() => {
    const bar = document.querySelector('#asset-progress');
    window.progressSeen = [];
    const tick = () => {
      if (!bar.hidden) window.progressSeen.push(bar.value);
      if (!window.progressDone) setTimeout(tick, 20);
    };
    tick();
  });
  const [second] = await Promise.all([
    page.waitForResponse(r => r.url().startsWith(`${BASE}/api/assets`) && r.request().method() === 'POST'),
    page.setInputFiles('#asset-file', path.join(MESHES, 'spot.obj')),
  ]);
  await cdp.send('Network.emulateNetworkConditions',
    {offline: false, latency: 0, downloadThroughput: -1, uploadThroughput: -1});
  const seen = await page.evaluate(() => { window.progressDone = true; return window.progressSeen; });
  const partial = [...new Set(seen.filter(v => v > 0 && v < 1))];
  assert.ok(partial.length >= 2, `upload progress seen at ${partial.length} values between 0 and 1`);
  for (let i = 1; i < seen.length; i++) assert.ok(seen[i] >= seen[i - 1], 'upload progress never goes back');
  console.log(`upload progress values seen: ${partial.length}`);
  assert.equal(second.status(), 201);
  // (The browser keeps no big response bodies for long: the id comes from the list.)
  await page.waitForSelector('.asset .asset-name:text-is("spot.obj")');
  const spot = {id: await page.$eval('#assets .asset', li => li.dataset.id)};
  assert.equal((await api(`/api/assets/${spot.id}`)).body.name, 'spot.obj', 'newest first');
  await page.fill('#s-spp', String(MAX_SPP));
  await page.fill('#s-spp_per_pass', '1');
  await page.fill('#s-time_limit', '60');
  const long = await submit(page);
  assert.equal(long.status, 202);
  await page.click(`${item} button:text("Delete")`);
  await page.waitForSelector(`${item} .asset-error:not(:empty)`);
  assert.match(await page.textContent(`${item} .asset-error`), /job/);
  assert.equal((await api(`/api/assets/${asset.id}`)).status, 200, 'the used asset is kept');
  await shot(page, 'asset-in-use');
  assert.equal((await api(`/api/jobs/${long.body.id}/cancel`, {method: 'POST'})).status, 202);

  // The unused one goes.
  await page.click(`.asset[data-id="${spot.id}"] button:text("Delete")`);
  await page.waitForSelector(`.asset[data-id="${spot.id}"]`, {state: 'detached'});
  assert.equal((await api(`/api/assets/${spot.id}`)).status, 404);
  // The browser logs the refused upload and the refused delete; nothing else.
  const errors = await close([/status of 422/, /status of 409/]);
  assert.equal(errors.length, 2, errors.join('\n'));
});

test('layout at 1280x800 and 400x800: no horizontal overflow; columns, then stacked', async () => {
  const hash = shared.first ? `#job=${shared.first}` : '';
  const measure = page => page.evaluate(() => {
    const r = id => document.getElementById(id).getBoundingClientRect();
    const wide = [...document.querySelectorAll('body *')].filter(el => {
      if (el.closest('.stage, dialog, .visually-hidden, .skip')) return false;
      const b = el.getBoundingClientRect();
      return b.width > 0 && b.right > document.documentElement.clientWidth + 1;
    }).map(el => el.id || el.className || el.tagName);
    return {scroll: document.documentElement.scrollWidth, client: document.documentElement.clientWidth,
      height: document.documentElement.scrollHeight, wide, submit: r('submit'), view: r('view'), queue: r('queue')};
  });
  for (const [viewport, name] of [[WIDE, 'layout-1280x800'], [NARROW, 'layout-400x800']]) {
    const {page, close} = await openPage(viewport, hash);
    if (hash) await page.waitForSelector('#viewer-canvas[data-kind=image]');
    for (const tab of ['viewer', 'compare']) {
      await page.click(`#tab-${tab}`);
      if (tab === 'compare' && shared.second) await page.waitForSelector('#chart svg[data-series="2"]');
      const m = await measure(page);
      const what = `${name}, ${tab}`;
      assert.ok(m.scroll <= m.client, `${what}: page ${m.scroll} px wide in ${m.client}`);
      assert.deepEqual(m.wide, [], `${what}: elements past the right edge`);
      if (viewport === WIDE) {
        assert.ok(m.submit.right <= m.view.left && m.view.right <= m.queue.left, 'three columns');
        assert.ok(Math.abs(m.submit.top - m.queue.top) < 2);
        assert.ok(m.height <= WIDE.height, `the page fits the window (${m.height} px): its panels scroll`);
      } else {
        assert.ok(m.submit.bottom <= m.view.top && m.view.bottom <= m.queue.top, 'stacked');
      }
      await shot(page, tab === 'viewer' ? name : `${name}-compare`, viewport === NARROW);
    }
    await close();
  }
});

test('keyboard: labels, tab order, focus styles, Escape', async () => {
  const {page, close} = await openPage(WIDE, shared.first ? `#job=${shared.first}` : '');
  // Every control has an accessible name; clickable things are buttons or links.
  const unnamed = await page.$$eval('input, select, textarea, button, a[href]', els => els
    .filter(el => !el.closest('[hidden]') && !(el.labels?.length) && !el.getAttribute('aria-label') &&
      !el.textContent.trim() && !el.getAttribute('aria-labelledby'))
    .map(el => el.outerHTML.slice(0, 80)));
  assert.deepEqual(unnamed, []);
  // Tab walks the form, then the results, then the queue, in that order.
  const order = [];
  for (let i = 0; i < 120; i++) {
    await page.keyboard.press('Tab');
    const f = await page.evaluate(() => {
      const el = document.activeElement;
      return {id: el.id, region: el.closest('#submit, #view, #queue')?.id || '', outline: getComputedStyle(el).outlineStyle};
    });
    order.push(f);
    if (f.region === 'queue') break;
  }
  const ids = order.map(f => f.id);
  for (const id of ['scene-name', 'scene-json', 's-integrator', 's-spp', 'submit-button', 'tab-viewer', 'viewer-stage', 'exposure'])
    assert.ok(ids.includes(id), `Tab reaches #${id}`);
  const regions = order.map(f => f.region).filter(Boolean);
  const firstOf = r => regions.indexOf(r), lastOf = r => regions.lastIndexOf(r);
  assert.ok(lastOf('submit') < firstOf('view') && lastOf('view') < firstOf('queue'), regions.join(' '));
  assert.ok(order.every(f => f.outline !== 'none'), 'a visible focus outline on every stop');
  // Escape closes the help dialog, then leaves the enlarged view.
  await page.click('#help-open');
  assert.ok(await page.isVisible('#help'));
  await page.keyboard.press('Escape');
  assert.ok(!(await page.isVisible('#help')));
  await page.click('#expand');
  assert.equal(await page.getAttribute('#expand', 'aria-pressed'), 'true');
  await shot(page, 'enlarged');
  await page.keyboard.press('Escape');
  assert.equal(await page.getAttribute('#expand', 'aria-pressed'), 'false');
  // Tabs follow the arrow keys.
  await page.focus('#tab-viewer');
  await page.keyboard.press('ArrowRight');
  assert.equal(await page.evaluate(() => document.activeElement.id), 'tab-compare');
  assert.ok(await page.isVisible('#compare'));
  await close();
});
