// Browser tests of the Workers panel and the scheduling fields (web/js/workers.js,
// web/js/scheduling.js), run by tests/web/run.sh twice: against the SQLite server
// (CAUSTIC_WEB_STORE=sqlite: the panel says one process renders, the form has no scheduling
// fields), and against `caustic serve --store postgresql://... --workers 0` with one `caustic
// worker --threads 2` (CAUSTIC_WEB_STORE=postgresql: the worker is listed with its task, and the
// form sends priority and task_passes).
import assert from 'node:assert/strict';
import {after, before, test} from 'node:test';

import {api, closeBrowser, itemOf, launch, openPage, RENDER_TIMEOUT, selectExample, shot, smallScene,
  submit} from './browser.mjs';

const STORE = process.env.CAUSTIC_WEB_STORE || 'sqlite';

before(async () => { await launch(); });
after(closeBrowser);

/** The number of GET /api/workers requests the page makes from now on. */
function countWorkerRequests(page) {
  const counter = {n: 0};
  page.on('request', r => { if (new URL(r.url()).pathname === '/api/workers') counter.n++; });
  return counter;
}

test('SQLite: the Workers panel says one process renders, and the form has priority only',
  {skip: STORE !== 'sqlite'}, async () => {
    const {page, close} = await openPage();
    const panel = page.locator('#workers-panel');
    await page.waitForSelector('#workers-panel[data-store=sqlite]');
    assert.match(await panel.locator('#workers-note').textContent(), /^One process \(SQLite\)/);
    assert.equal(await panel.locator('.worker').count(), 0);
    assert.equal(await page.locator('#j-priority').isVisible(), true, 'SQLite claims by priority');
    assert.equal(await page.locator('#j-task_passes').isHidden(), true, 'no tasks with SQLite');
    // The store cannot change under a running server: the page asks once.
    const asked = countWorkerRequests(page);
    await page.waitForTimeout(4000);
    assert.equal(asked.n, 0, 'no refresh with SQLite');
    // A job submitted from the form carries its priority, no task_passes.
    await selectExample(page, 'cornell-box');
    await smallScene(page, 16);
    await page.fill('#s-spp', '1');
    const {status, body, request} = await submit(page);
    assert.equal(status, 202);
    assert.deepEqual(Object.keys(JSON.parse(request.postData())).sort(),
                     ['priority', 'scene', 'settings']);
    await page.waitForSelector(`${itemOf(body.id)}[data-state=succeeded]`, {timeout: RENDER_TIMEOUT});
    await close();
  });

test('PostgreSQL: the worker is listed, refreshed, with the task it renders and its counts',
  {skip: STORE !== 'postgresql'}, async () => {
    const {page, close} = await openPage();
    await page.waitForSelector('#workers-panel[data-store=postgresql]');
    const worker = page.locator('#workers .worker');
    await worker.first().waitFor();
    assert.equal(await worker.count(), 1, 'one caustic worker with one thread');
    const fact = name => worker.locator(`[data-fact=${name}]`).textContent();
    assert.match(await fact('threads'), /^\d+ \/ 2$/);
    assert.equal(await fact('task'), 'idle');
    assert.match(await fact('heartbeat'), /^\d+\.\d s ago$/);
    assert.equal(await fact('tasks'), '0 / 0');
    const {workers} = (await api('/api/workers')).body;
    assert.equal(await worker.locator('.worker-name').textContent(), workers[0].host);

    // A long job (cornell-box, 512x512): the panel shows the worker on it within a refresh, and
    // its link opens the job.
    const long = await api('/api/jobs', {method: 'POST', headers: {'Content-Type': 'application/json'},
      body: JSON.stringify({scene: 'cornell-box', settings: {spp: 4096, spp_per_pass: 64}, task_passes: 1})});
    assert.equal(long.status, 202, JSON.stringify(long.body));
    const link = worker.locator('[data-fact=task] button');
    await link.waitFor({timeout: 30_000});
    assert.match(await fact('task'), new RegExp(`^job ${long.body.id.slice(0, 6)} passes \\d+–\\d+$`));
    await shot(page, 'workers-rendering');
    await link.click();
    await page.waitForFunction(id => location.hash === `#job=${id}`, long.body.id);
    assert.equal((await api(`/api/jobs/${long.body.id}/cancel`, {method: 'POST'})).status, 202);
    await page.waitForSelector(`${itemOf(long.body.id)}[data-state=cancelled]`, {timeout: 60_000});

    // The scheduling fields: a bad priority is refused beside its input before anything is sent,
    // then priority and task_passes go with the job.
    assert.equal(await page.locator('#job-options').isVisible(), true);
    await selectExample(page, 'cornell-box');
    await smallScene(page, 32);
    await page.fill('#s-spp', '8');
    await page.fill('#s-spp_per_pass', '1');
    await page.fill('#j-priority', '5000');
    await page.click('#submit-button');
    assert.notEqual(await page.textContent('#j-priority-error'), '');
    assert.equal(await page.getAttribute('#j-priority', 'aria-invalid'), 'true');
    await page.fill('#j-priority', '7');
    await page.fill('#j-task_passes', '2');
    const {status, body, request} = await submit(page);
    assert.equal(status, 202, JSON.stringify(body));
    const sent = JSON.parse(request.postData());
    assert.equal(sent.priority, 7);
    assert.equal(sent.task_passes, 2);
    await page.waitForSelector(`${itemOf(body.id)}[data-state=succeeded]`, {timeout: RENDER_TIMEOUT});
    const done = (await api(`/api/jobs/${body.id}`)).body;
    assert.equal(done.stats.tasks, 4, 'passes 0-8 in tasks of 2');
    // The panel refreshes: the tasks the worker handed in show up.
    await page.waitForFunction(() => {
      const text = document.querySelector('#workers .worker [data-fact=tasks]')?.textContent || '';
      return Number(text.split(' / ')[0]) >= 4;
    }, null, {timeout: 15_000});
    await shot(page, 'workers');
    await close();
  });
