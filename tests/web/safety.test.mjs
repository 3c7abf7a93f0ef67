// Browser tests of the rules against other web sites (docs/security.md), in Chromium against the
// real `caustic serve` that tests/web/run.sh starts. A page served from another origin (a static
// server on another loopback port, started here) tries what any web site the user visits could:
// a no-cors fetch of a JSON text typed text/plain, forms that post themselves (text/plain,
// urlencoded, multipart), a cross-origin fetch that needs a preflight, cancel and DELETE of a
// job. A name that resolves to 127.0.0.1 (DNS rebinding, simulated with Chromium's
// --host-resolver-rules) loads the service. Each attempt is then checked through the API: no job
// made, none cancelled or deleted. The service's own page keeps working: web.test.mjs.
import assert from 'node:assert/strict';
import http from 'node:http';
import {after, before, test} from 'node:test';

import {api, BASE, closeBrowser, launch} from './browser.mjs';

const REBOUND = 'rebound.example';  // the browser resolves it to 127.0.0.1
let browser, otherSite, OTHER;

// A job the service accepts when it is sent as JSON. A material nobody uses is named "k=v": a
// form with enctype text/plain sends `name=value`, so a field named what comes before the "="
// with the value of what follows makes exactly this text (the classic JSON-by-form trick).
const SCENE = {
  camera: {position: [0, 0, 3], look_at: [0, 0, 0], up: [0, 1, 0], fov: 40, width: 16, height: 16},
  materials: {lamp: {type: 'diffuse', albedo: [0.5, 0.5, 0.5], emission: [4, 4, 4]},
    'k=v': {type: 'diffuse', albedo: [0.5, 0.5, 0.5]}},
  shapes: [{type: 'sphere', center: [0, 0, 0], radius: 0.5, material: 'lamp'}],
};
const JOB_TEXT = JSON.stringify({scene: SCENE, settings: {spp: 1}});

const attr = s => s.replace(/&/g, '&amp;').replace(/"/g, '&quot;');

/** A page of the other site whose form posts itself to the service at once. */
function formPage(enctype) {
  const [name, value] = enctype === 'text/plain'
    ? [JOB_TEXT.slice(0, JOB_TEXT.indexOf('=')), JOB_TEXT.slice(JOB_TEXT.indexOf('=') + 1)]
    : ['scene', JOB_TEXT];
  return `<!doctype html><title>another site</title>
<form method="post" action="${BASE}/api/jobs" enctype="${enctype}">
<input type="hidden" name="${attr(name)}" value="${attr(value)}"></form>
<script>document.forms[0].submit();</script>`;
}

before(async () => {
  browser = await launch([`--host-resolver-rules=MAP ${REBOUND} 127.0.0.1`]);
  otherSite = http.createServer((req, res) => {
    const url = new URL(req.url, 'http://x');
    res.setHeader('Content-Type', 'text/html');
    res.end(url.pathname === '/form' ? formPage(url.searchParams.get('enctype'))
      : '<!doctype html><title>another site</title><p>Nothing to see here.');
  });
  await new Promise(resolve => otherSite.listen(0, '127.0.0.1', resolve));
  OTHER = `http://127.0.0.1:${otherSite.address().port}`;
});

after(async () => {
  await closeBrowser();
  otherSite.close();
});

const jobIds = async () => (await api('/api/jobs?limit=100')).body.jobs.map(j => j.id).sort();

/** A page of the other site, in a fresh context; its service requests' statuses are recorded. */
async function otherPage(path = '/') {
  const context = await browser.newContext();
  const page = await context.newPage();
  const statuses = [];
  page.on('response', r => {
    if (r.url().startsWith(BASE)) statuses.push(`${r.request().method()} ${new URL(r.url()).pathname} ${r.status()}`);
  });
  await page.goto(OTHER + path);
  return {page, statuses, close: () => context.close()};
}

test('control: the form\'s text is a job the service accepts when sent as JSON', async () => {
  const res = await fetch(`${BASE}/api/jobs`, {method: 'POST', body: `${JOB_TEXT}\r\n`,
    headers: {'Content-Type': 'application/json'}});
  const text = await res.text();
  assert.equal(res.status, 202, text);
  const {id} = JSON.parse(text);
  for (let i = 0; i < 600 && (await api(`/api/jobs/${id}`)).body.state !== 'succeeded'; i++)
    await new Promise(r => setTimeout(r, 100));
  assert.equal((await api(`/api/jobs/${id}`, {method: 'DELETE'})).status, 204);
});

test('another site\'s no-cors fetch of JSON typed text/plain makes no job (415)', async () => {
  const before = await jobIds();
  const {page, statuses, close} = await otherPage();
  const types = await page.evaluate(async ({url, body}) => {
    const sent = [];
    for (const headers of [{'Content-Type': 'text/plain'}, {}, {'Content-Type': 'application/json'}]) {
      // no-cors drops a Content-Type that is not "simple": the last one goes as text/plain too.
      const res = await fetch(url, {method: 'POST', mode: 'no-cors', body, headers});
      sent.push(res.type);
    }
    return sent;
  }, {url: `${BASE}/api/jobs`, body: JOB_TEXT});
  assert.deepEqual(types, ['opaque', 'opaque', 'opaque'], 'the page cannot read the answers');
  await page.waitForTimeout(200);
  assert.deepEqual(statuses, Array(3).fill('POST /api/jobs 415'));
  assert.deepEqual(await jobIds(), before);
  await close();
});

for (const enctype of ['text/plain', 'application/x-www-form-urlencoded', 'multipart/form-data']) {
  test(`another site's form (${enctype}) that posts itself makes no job (415)`, async () => {
    const before = await jobIds();
    const context = await browser.newContext();
    const page = await context.newPage();
    const [response] = await Promise.all([
      page.waitForResponse(r => r.url() === `${BASE}/api/jobs`),
      page.goto(`${OTHER}/form?enctype=${encodeURIComponent(enctype)}`),
    ]);
    assert.equal(response.request().method(), 'POST');
    assert.equal((response.request().headers()['content-type'] || '').split(';')[0], enctype);
    assert.equal(response.status(), 415);
    assert.match((await response.json()).detail, /POST \/api\/jobs takes application\/json, not/);
    assert.deepEqual(await jobIds(), before);
    await context.close();
  });
}

test('another site\'s JSON fetch needs a preflight, which is refused (403)', async () => {
  const before = await jobIds();
  const {page, statuses, close} = await otherPage();
  const outcome = await page.evaluate(async ({url, body}) => {
    try {
      await fetch(url, {method: 'POST', body, headers: {'Content-Type': 'application/json'}});
      return 'sent';
    } catch (e) {
      return e.name;
    }
  }, {url: `${BASE}/api/jobs`, body: JOB_TEXT});
  assert.equal(outcome, 'TypeError', 'the browser stops the request');
  assert.deepEqual(statuses.filter(s => s.startsWith('POST')), [], 'the POST never went out');
  assert.deepEqual(await jobIds(), before);
  await close();
});

test('another site cannot cancel or delete a job (403)', async () => {
  const {status, body: job} = await api('/api/jobs', {method: 'POST',
    headers: {'Content-Type': 'application/json'},
    body: JSON.stringify({scene: 'cornell-box', settings: {spp: 4096, spp_per_pass: 1, time_limit: 60}})});
  assert.equal(status, 202);
  try {
    const {page, statuses, close} = await otherPage();
    const outcomes = await page.evaluate(async url => {
      const tries = [
        // A simple request: it goes out, the page cannot read the answer.
        () => fetch(`${url}/cancel`, {method: 'POST', mode: 'no-cors'}).then(r => r.type),
        // DELETE is never simple: no-cors refuses it, cors needs a preflight.
        () => fetch(url, {method: 'DELETE', mode: 'no-cors'}).then(r => r.type),
        () => fetch(url, {method: 'DELETE'}).then(r => String(r.status)),
      ];
      const out = [];
      for (const t of tries) out.push(await t().catch(e => e.name));
      return out;
    }, `${BASE}/api/jobs/${job.id}`);
    assert.deepEqual(outcomes, ['opaque', 'TypeError', 'TypeError']);
    await page.waitForTimeout(200);
    assert.ok(statuses.includes(`POST /api/jobs/${job.id}/cancel 403`), statuses.join(', '));
    assert.ok(!statuses.some(s => s.startsWith('DELETE')), statuses.join(', '));
    await close();
    const after = (await api(`/api/jobs/${job.id}`)).body;
    assert.ok(['queued', 'running'].includes(after.state), after.state);
    assert.equal(after.cancel_requested, false);
  } finally {
    // The test's own requests carry no Origin, like curl's.
    await api(`/api/jobs/${job.id}/cancel`, {method: 'POST'});
    for (let i = 0; i < 600 && ['queued', 'running'].includes((await api(`/api/jobs/${job.id}`)).body.state); i++)
      await new Promise(r => setTimeout(r, 100));
    assert.equal((await api(`/api/jobs/${job.id}`, {method: 'DELETE'})).status, 204);
  }
});

test('a foreign name that resolves to 127.0.0.1 (DNS rebinding) gets 403 for everything', async () => {
  const before = await jobIds();
  const rebound = BASE.replace('127.0.0.1', REBOUND);
  const context = await browser.newContext();
  const page = await context.newPage();
  const response = await page.goto(`${rebound}/`);
  assert.equal(response.status(), 403);
  assert.match((await response.json()).detail, new RegExp(`Host "${REBOUND}:\\d+" is not this machine's loopback`));
  // To the browser the service is now this site's own: reads and writes are same-origin.
  const answers = await page.evaluate(async body => Promise.all([
    fetch('/api/jobs').then(r => r.status),
    fetch('/api/jobs', {method: 'POST', body, headers: {'Content-Type': 'application/json'}}).then(r => r.status),
  ]), JOB_TEXT);
  assert.deepEqual(answers, [403, 403]);
  assert.deepEqual(await jobIds(), before);
  await context.close();
});
