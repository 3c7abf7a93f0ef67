// The Caustic page: wires the scene editor, the settings form and the scheduling fields (submit),
// the queue, the viewer, the comparison, the uploaded meshes and the workers together. Validation errors from the server
// (problem+json) are shown where their `pointer` says: a setting's message beside its input, a
// scene path under the editor.
import {api, ApiError, setToken} from './api.js';
import {AssetsPanel} from './assets.js';
import {Compare} from './compare.js';
import {h, rememberSceneLabel} from './format.js';
import {Jobs} from './jobs.js';
import {QueueView} from './queue.js';
import {locate} from './locate.js';
import {meshShapeFor} from './placement.js';
import {SchedulingFields} from './scheduling.js';
import {SettingsForm} from './settings.js';
import {Viewer} from './viewer.js';
import {WorkersPanel} from './workers.js';

const $ = sel => document.querySelector(sel);

// Messages that belong to no field.
const notice = $('#notice');
function showNotice(message) {
  $('#notice-text').textContent = message;
  notice.hidden = false;
}
$('#notice-close').addEventListener('click', () => { notice.hidden = true; });
function reportError(e) {
  if (e.status === 401) askForToken();
  showNotice(e instanceof ApiError || e instanceof Error ? e.message : String(e));
}

// A server started with --token wants it on every POST and DELETE.
function askForToken() {
  $('#token-field').hidden = false;
  $('#token').focus();
}
$('#token').addEventListener('change', () => setToken($('#token').value.trim()));

const jobs = new Jobs();
const viewer = new Viewer($('#viewer'), jobs);
const compare = new Compare($('#compare'), jobs, reportError);
const queue = new QueueView($('#jobs'), $('#jobs-empty'), jobs, {onOpen: openJob, onError: reportError});
const assets = new AssetsPanel($('#assets-panel'),
  {onInsert: insertAsset, onUseModel: useModel, onUnauthorized: askForToken});
const workers = new WorkersPanel($('#workers-panel'), {onOpen: openJob});
const scheduling = new SchedulingFields($('#job-options'));
const OFFLINE = 'The server does not answer';
jobs.addEventListener('offline', e => showNotice(`${OFFLINE} (${e.detail.message}); retrying.`));
jobs.addEventListener('online', () => {
  if ($('#notice-text').textContent.startsWith(OFFLINE)) notice.hidden = true;
});

function openJob(id, tab = true) {
  viewer.show(id);
  queue.setCurrent(id);
  if (tab) selectTab('viewer');
  history.replaceState(null, '', id ? `#job=${id}` : location.pathname);
}
// The job shown was deleted (here or elsewhere).
jobs.addEventListener('list', () => { if (viewer.id && !jobs.get(viewer.id)) openJob(null, false); });

// Tabs: Viewer and Compare (arrow keys, Home and End move between them).
const tabs = [$('#tab-viewer'), $('#tab-compare')];
function selectTab(name, focus = false) {
  for (const tab of tabs) {
    const on = tab.getAttribute('aria-controls') === name;
    tab.setAttribute('aria-selected', String(on));
    tab.tabIndex = on ? 0 : -1;
    document.getElementById(tab.getAttribute('aria-controls')).hidden = !on;
    if (on && focus) tab.focus();
  }
  compare.setActive(name === 'compare');
}
for (const tab of tabs) {
  tab.addEventListener('click', () => selectTab(tab.getAttribute('aria-controls')));
  tab.addEventListener('keydown', e => {
    const i = tabs.indexOf(tab);
    const to = {ArrowRight: i + 1, ArrowLeft: i - 1, Home: 0, End: tabs.length - 1}[e.key];
    if (to === undefined) return;
    e.preventDefault();
    selectTab(tabs[(to + tabs.length) % tabs.length].getAttribute('aria-controls'), true);
  });
}

// Enlarged results; Escape returns (after closing a message first).
const view = $('#view'), expand = $('#expand');
function setEnlarged(on) {
  view.classList.toggle('enlarged', on);
  expand.setAttribute('aria-pressed', String(on));
  expand.textContent = on ? 'Restore' : 'Enlarge';
}
expand.addEventListener('click', () => setEnlarged(!view.classList.contains('enlarged')));
document.addEventListener('keydown', e => {
  if (e.key !== 'Escape' || e.defaultPrevented || $('#help').open) return;
  if (!notice.hidden) notice.hidden = true;
  else if (view.classList.contains('enlarged')) { setEnlarged(false); expand.focus(); }
});
$('#help-open').addEventListener('click', () => $('#help').showModal());

// The scene: an example (sent by name while its text is unchanged) or edited JSON.
const sceneSelect = $('#scene-name'), sceneText = $('#scene-json'), sceneErrors = $('#scene-errors');
let exampleText = '';
let sceneSettingsKey = '';

async function loadExample(name) {
  // Set again once the example's text is in the editor: tests wait for it, as an edit made before
  // then would be overwritten.
  delete sceneText.dataset.example;
  try {
    exampleText = await api.sceneText(name);
  } catch (e) {
    return reportError(e);
  }
  sceneText.value = exampleText;
  sceneText.dataset.example = name;
  clearErrors();
  const settings = sceneSettings();
  sceneSettingsKey = JSON.stringify(settings);
  form.reset(settings);
}

/** The `settings` of the scene in the editor, or undefined if it does not parse. */
function sceneSettings() {
  try {
    return JSON.parse(sceneText.value)?.settings;
  } catch {
    return undefined;
  }
}

sceneSelect.addEventListener('change', () => loadExample(sceneSelect.value));
sceneText.addEventListener('input', () => {
  sceneErrors.replaceChildren();
  sceneText.removeAttribute('aria-invalid');
});
// Settings typed into the scene's JSON fill the form (the form's values are what is sent).
sceneText.addEventListener('change', () => {
  const settings = sceneSettings();
  const key = JSON.stringify(settings);
  if (settings && typeof settings === 'object' && key !== sceneSettingsKey) {
    for (const [name, value] of Object.entries(settings)) form.set(name, value);
    form.showIntegrator();
  }
  if (key !== undefined) sceneSettingsKey = key;
});

function showSceneError(pointer, message) {
  sceneErrors.append(h('li', {}, pointer ? h('code', {text: pointer}) : null, pointer ? ` ${message}` : message));
  sceneText.setAttribute('aria-invalid', 'true');
  // Select the value the pointer names, when the editor holds that scene.
  selectInEditor(pointer.startsWith('/scene') ? pointer.slice('/scene'.length) : null);
}

/** Focuses the editor and selects the value at `pointer` (a path inside the scene), if any. */
function selectInEditor(pointer) {
  const at = pointer === null ? null : locate(sceneText.value, pointer);
  sceneText.focus({preventScroll: true});
  sceneText.closest('fieldset').scrollIntoView({block: 'nearest'});
  if (at) {
    sceneText.setSelectionRange(at[0], at[1]);
    // Scroll the selection into view: put the caret line near the top.
    const line = sceneText.value.slice(0, at[0]).split('\n').length - 1;
    sceneText.scrollTop = Math.max(0, line - 2) * parseFloat(getComputedStyle(sceneText).lineHeight || '16');
  }
}

// Insert (Assets panel): the mesh goes into the scene in the editor, which is then sent as an
// object; the new shape is selected in the editor.
function insertAsset(asset) {
  let scene;
  try {
    scene = JSON.parse(sceneText.value);
  } catch (e) {
    throw new Error(`The scene in the editor is not valid JSON (${e.message}); fix it first.`);
  }
  if (!scene || typeof scene !== 'object' || Array.isArray(scene)) throw new Error('The editor holds no scene object.');
  const {shape, materials} = meshShapeFor(scene, asset);
  if (Object.keys(materials).length) scene.materials = {...(scene.materials || {}), ...materials};
  if (!Array.isArray(scene.shapes)) scene.shapes = [];
  scene.shapes.push(shape);
  sceneText.value = JSON.stringify(scene, null, 2);
  sceneText.dispatchEvent(new Event('input'));
  const pointer = `/shapes/${scene.shapes.length - 1}`;
  selectInEditor(pointer);
  return `Inserted ${asset.name || 'the mesh'} as ${pointer} (material "${shape.material}", scale ${shape.transform.scale}).`;
}

// Use as scene (Assets panel, a .glb): the model's scene object replaces the editor's scene.
function useModel(scene) {
  sceneText.value = JSON.stringify(scene, null, 2);
  sceneText.dispatchEvent(new Event('input'));
  return 'The model is the scene: Render renders it (docs/gltf.md lists the overrides a scene may add).';
}

function clearErrors() {
  sceneErrors.replaceChildren();
  sceneText.removeAttribute('aria-invalid');
  form.clearErrors();
  scheduling.clearErrors();
  $('#form-error').textContent = '';
}

function showProblem(e) {
  const problem = e.problem || {};
  const pointer = problem.pointer || '';
  let message = problem.detail || e.message;
  if (pointer && message.startsWith(`${pointer}: `)) message = message.slice(pointer.length + 2);
  if (e.status === 401) askForToken();
  if (pointer.startsWith('/settings/') && form.showError(pointer.split('/')[2], message)) {
    form.focusFirstError();
    return;
  }
  if (pointer === '/scene' || pointer.startsWith('/scene/')) return showSceneError(pointer, message);
  if (scheduling.showError(pointer, message)) return;
  $('#form-error').textContent = pointer ? `${pointer}: ${message}` : message;
}

// Submit.
const formEl = $('#job-form');
let form;
formEl.addEventListener('keydown', e => {
  if (e.key === 'Enter' && (e.ctrlKey || e.metaKey)) {
    e.preventDefault();
    formEl.requestSubmit();
  }
});
formEl.addEventListener('submit', async e => {
  e.preventDefault();
  clearErrors();
  let scene = sceneSelect.value;
  if (sceneText.value !== exampleText || !scene) {
    try {
      scene = JSON.parse(sceneText.value);
    } catch (err) {
      return showSceneError('', `The scene is not valid JSON: ${err.message}`);
    }
  }
  const settings = form.values();
  if (!settings) return form.focusFirstError();
  const jobFields = scheduling.values();
  if (!jobFields) return;
  const button = $('#submit-button');
  button.disabled = true;
  try {
    const job = await api.submit({scene, settings, ...jobFields});
    if (typeof scene === 'object' && sceneSelect.value) rememberSceneLabel(job.id, `${sceneSelect.value} (edited)`);
    jobs.add(job);
    openJob(job.id);
  } catch (err) {
    showProblem(err);
  } finally {
    button.disabled = false;
  }
});

// Start: the settings and the scenes from the API, then the jobs.
try {
  const [schema, scenes] = await Promise.all([api.settings(), api.scenes()]);
  form = new SettingsForm($('#settings'), schema);
  sceneSelect.replaceChildren(...scenes.map(n => new Option(n, n)));
  sceneSelect.value = scenes.includes('cornell-box') ? 'cornell-box' : scenes[0] || '';
  if (sceneSelect.value) await loadExample(sceneSelect.value);
} catch (e) {
  reportError(e);
}
const [, , store] = await Promise.all([jobs.refresh(), assets.refresh(), workers.refresh()]);
scheduling.setStore(store);
const fromHash = /^#job=([0-9a-f]{32})$/.exec(location.hash)?.[1];
const first = (fromHash && jobs.get(fromHash)) || jobs.list()[0];
if (first) openJob(first.id);
document.body.dataset.ready = 'true';
