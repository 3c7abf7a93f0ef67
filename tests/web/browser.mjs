// Helpers of the browser tests (web.test.mjs): the browser, pages that record console errors,
// screenshots, and the page's form. Environment (tests/web/run.sh sets it): CAUSTIC_WEB_URL (the
// server), CAUSTIC_WEB_NODE_MODULES (where playwright-core is installed), CAUSTIC_WEB_SCREENSHOTS
// (a folder), CHROMIUM (the browser), CAUSTIC_WEB_MAX_SPP (the server's --max-spp).
import assert from 'node:assert/strict';
import {mkdirSync} from 'node:fs';
import {createRequire} from 'node:module';
import path from 'node:path';

const require = createRequire(path.join(process.env.CAUSTIC_WEB_NODE_MODULES, 'noop.js'));
const {chromium} = require('playwright-core');

export const BASE = process.env.CAUSTIC_WEB_URL.replace(/\/$/, '');
export const MAX_SPP = Number(process.env.CAUSTIC_WEB_MAX_SPP);
export const WIDE = {width: 1280, height: 800}, NARROW = {width: 400, height: 800};
export const RENDER_TIMEOUT = 180_000;
const SHOTS = process.env.CAUSTIC_WEB_SCREENSHOTS;

let browser;

/** Starts the browser; `args` are more Chromium flags. */
export async function launch(args = []) {
  mkdirSync(SHOTS, {recursive: true});
  browser = await chromium.launch({executablePath: process.env.CHROMIUM, args: ['--no-sandbox', ...args]});
  return browser;
}

export async function closeBrowser() { await browser?.close(); }

/** A request from the test itself (not the page): status and JSON body. */
export async function api(p, init) {
  const res = await fetch(BASE + p, init);
  return {status: res.status, body: res.status === 204 ? null : await res.json()};
}

/** Records a page's console errors and uncaught exceptions, and which responses were over 400
 *  (the browser logs those as "Failed to load resource" without the address). */
export function watchErrors(page) {
  const errors = [], failed = [];
  page.on('console', m => { if (m.type() === 'error') errors.push(m.text()); });
  page.on('pageerror', e => errors.push(`uncaught: ${e.message}`));
  page.on('response', r => { if (r.status() >= 400) failed.push(`${r.status()} ${r.request().method()} ${r.url()}`); });
  /** Fails on an error not matched by one of `allowed`; returns them all. */
  return (allowed = []) => {
    const unexpected = errors.filter(e => !allowed.some(re => re.test(e)));
    assert.deepEqual(unexpected, [], `console errors (responses over 400: ${failed.join(', ') || 'none'})`);
    return errors;
  };
}

/** The page, loaded, in a fresh context (no cache); close() fails on unexpected console errors. */
export async function openPage(viewport = WIDE, hash = '') {
  const context = await browser.newContext({viewport});
  const page = await context.newPage();
  const check = watchErrors(page);
  await page.goto(`${BASE}/${hash}`);
  await page.waitForSelector('body[data-ready=true]', {timeout: 20_000});
  const close = async (allowed = []) => {
    await context.close();
    return check(allowed);
  };
  return {page, close};
}

export async function shot(page, name, fullPage = false) {
  const file = path.join(SHOTS, `${name}.png`);
  await page.screenshot({path: file, fullPage});
  console.log(`screenshot: ${file}`);
}

/** Chooses an example scene and waits until its text is in the editor (it loads asynchronously:
 *  an edit made before then would be overwritten). */
export async function selectExample(page, name) {
  await page.selectOption('#scene-name', name);
  await page.waitForSelector(`#scene-json[data-example="${name}"]`);
}

/** Edits the scene in the editor (from the chosen example) to `size`x`size` pixels. */
export async function smallScene(page, size) {
  const scene = JSON.parse(await page.inputValue('#scene-json'));
  scene.camera.width = scene.camera.height = size;
  await page.fill('#scene-json', JSON.stringify(scene, null, 2));
}

/** Clicks Render; returns the POST /api/jobs response (status, body) and its request. */
export async function submit(page) {
  const [response] = await Promise.all([
    page.waitForResponse(r => r.url() === `${BASE}/api/jobs` && r.request().method() === 'POST'),
    page.click('#submit-button'),
  ]);
  return {status: response.status(), body: await response.json(), request: response.request()};
}

/** The queue item of a job. */
export const itemOf = id => `.job[data-id="${id}"]`;
