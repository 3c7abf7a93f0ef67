// The Assets panel: uploads meshes (.obj, .glb) from a file picker or dropped anywhere on the page,
// with a progress bar, lists the uploaded ones (GET /api/assets, newest first) with their counts
// and bounds, and offers Insert (a mesh shape into the scene editor) and Delete for each. A .glb is
// a whole scene too (docs/gltf.md): its item offers its cameras and the automatic one, and "Use as
// scene" puts the model into the editor; an upload renders a thumbnail of it (a quick job).
import {api, meshMediaType} from './api.js';
import {h} from './format.js';

const exact = n => (Number.isFinite(n) ? n.toLocaleString('en-US') : '—');
const coord = v => String(+v.toPrecision(3));
const point = p => `[${p.map(coord).join(', ')}]`;
/** A glTF model (.glb, or .zip of a .gltf): a whole scene. */
const isModel = asset => ['glb', 'zip'].includes(asset.format);

export class AssetsPanel {
  /** @param onInsert(asset) puts the asset into the scene; returns a line saying what it did.
   *  @param onUseModel(scene) puts a glTF model's scene object into the editor; returns a line.
   *  @param onUnauthorized() asks for the token (a 401). */
  constructor(panel, {onInsert, onUseModel, onUnauthorized}) {
    this.panel = panel;
    this.onInsert = onInsert;
    this.onUseModel = onUseModel;
    this.thumbnails = new Map();  // asset id -> image URL of its thumbnail job
    this.onUnauthorized = onUnauthorized;
    this.list = panel.querySelector('#assets');
    this.empty = panel.querySelector('#assets-empty');
    this.drop = panel.querySelector('#asset-drop');
    this.progress = panel.querySelector('#asset-progress');
    this.status = panel.querySelector('#asset-status');
    this.error = panel.querySelector('#asset-error');
    const input = panel.querySelector('#asset-file');
    input.addEventListener('change', () => {
      this.uploadAll([...input.files]);
      input.value = '';
    });
    this.acceptDrops();
  }

  // Files dropped on the panel or anywhere else on the page; the panel shows where they go.
  acceptDrops() {
    const carriesFiles = e => [...(e.dataTransfer?.types || [])].includes('Files');
    let depth = 0;  // dragenter and dragleave pair up over every element crossed
    const show = on => this.drop.classList.toggle('dropping', on);
    document.addEventListener('dragenter', e => {
      if (!carriesFiles(e)) return;
      depth++;
      show(true);
    });
    document.addEventListener('dragleave', e => {
      if (carriesFiles(e) && --depth <= 0) { depth = 0; show(false); }
    });
    document.addEventListener('dragover', e => {
      if (!carriesFiles(e)) return;
      e.preventDefault();  // allows the drop; otherwise the browser opens the file
      e.dataTransfer.dropEffect = 'copy';
    });
    document.addEventListener('drop', e => {
      if (!carriesFiles(e)) return;
      e.preventDefault();
      depth = 0;
      show(false);
      this.uploadAll([...e.dataTransfer.files]);
    });
  }

  /** Lists the uploaded assets again (the newest 100). */
  async refresh() {
    try {
      const assets = await api.assets();
      this.list.replaceChildren(...assets.map(a => this.item(a)));
      this.empty.hidden = assets.length > 0;
    } catch (e) {
      this.error.textContent = `The assets could not be listed: ${e.message}`;
    }
  }

  async uploadAll(files) {
    for (const file of files) await this.upload(file);
  }

  async upload(file) {
    this.error.textContent = '';
    if (!meshMediaType(file.name)) {
      this.error.textContent = `${file.name}: not a mesh this service takes (.obj, .glb, or .zip of a .gltf)`;
      return;
    }
    this.status.textContent = `Uploading ${file.name}…`;
    this.progress.hidden = false;
    this.progress.value = 0;
    this.progress.setAttribute('aria-label', `Uploading ${file.name}`);
    try {
      const asset = await api.uploadAsset(file, fraction => {
        this.progress.value = fraction;
        this.status.textContent = `Uploading ${file.name}: ${Math.round(100 * fraction)}%`;
      });
      this.status.textContent = `${file.name}: ${exact(asset.triangles)} triangles, ` +
        `${exact(asset.vertices)} vertices.`;
      await this.refresh();
      if (isModel(asset)) this.thumbnail(asset);
    } catch (e) {
      this.status.textContent = '';
      this.error.textContent = `${file.name}: ${e.message}`;
      if (e.status === 401) this.onUnauthorized();
    } finally {
      this.progress.hidden = true;
    }
  }

  item(asset) {
    const name = asset.name || `${asset.format} ${asset.id.slice(0, 8)}`;
    const {min, max} = asset.bounds;
    const size = max.map((v, i) => coord(v - min[i])).join(' × ');
    const fact = (key, label, value) => [h('dt', {text: label}), h('dd', {'data-fact': key, text: value})];
    const error = h('p', {class: 'asset-error', 'aria-live': 'polite'});
    const insert = h('button', {type: 'button', text: 'Insert', 'aria-label': `Insert ${name} into the scene`,
      onclick: () => {
        error.textContent = '';
        try {
          this.status.textContent = this.onInsert(asset);
        } catch (e) {
          error.textContent = e.message;
        }
      }});
    const remove = h('button', {type: 'button', class: 'danger', text: 'Delete', 'aria-label': `Delete ${name}`,
      onclick: () => this.remove(asset, error)});
    const model = isModel(asset) ? this.modelControls(asset, name, error) : [];
    return h('li', {class: 'asset', 'data-id': asset.id},
      h('div', {class: 'asset-head'}, h('span', {class: 'asset-name', text: name, title: asset.id}),
        h('span', {class: 'state', text: asset.format})),
      h('dl', {class: 'asset-facts'},
        ...fact('triangles', 'triangles', exact(asset.triangles)),
        ...fact('vertices', 'vertices', exact(asset.vertices)),
        ...fact('size', 'size', size),
        ...fact('bounds', 'bounds', `${point(min)} – ${point(max)}`)),
      ...model.slice(0, 1),
      error,
      h('div', {class: 'asset-actions'}, ...model.slice(1), insert, remove));
  }

  // A glTF model's thumbnail, camera choice (the file's cameras, from GET /api/assets/{id}, and the
  // automatic one) and "Use as scene": [thumbnail, camera select, button].
  modelControls(asset, name, error) {
    const thumb = h('img', {class: 'asset-thumb', alt: `${name}, a quick render`});
    thumb.hidden = !this.thumbnails.has(asset.id);
    if (this.thumbnails.has(asset.id)) thumb.src = this.thumbnails.get(asset.id);
    const camera = h('select', {class: 'asset-camera', 'aria-label': `Camera for ${name}`},
      h('option', {value: 'auto', text: 'automatic camera'}));
    api.asset(asset.id).then(full => {
      for (const c of full.model?.cameras || [])
        camera.append(h('option', {value: String(c.camera), text: c.name || `camera ${c.camera}`}));
      if (full.model?.cameras?.length) camera.value = String(full.model.cameras[0].camera);
      camera.dataset.ready = 'true';
    }).catch(e => { error.textContent = `The model could not be read: ${e.message}`; });
    const use = h('button', {type: 'button', text: 'Use as scene', 'aria-label': `Use ${name} as the scene`,
      onclick: () => {
        error.textContent = '';
        const view = camera.value === 'auto' ? {auto: {}} : {gltf: Number(camera.value)};
        this.status.textContent = this.onUseModel({gltf: {asset: asset.id}, camera: view});
      }});
    return [thumb, camera, use];
  }

  // A quick render of a new .glb (4 spp, 192 pixels wide, automatic camera), shown in its item.
  async thumbnail(asset) {
    try {
      const job = await api.submit({scene: {gltf: {asset: asset.id}, camera: {auto: {}, width: 192}},
                                    settings: {spp: 4, max_depth: 4}});
      for (let wait = 250; ; wait = Math.min(2 * wait, 2000)) {
        const now = await api.job(job.id);
        if (now.state === 'succeeded') break;
        if (['failed', 'cancelled'].includes(now.state)) return;
        await new Promise(resolve => setTimeout(resolve, wait));
      }
      this.thumbnails.set(asset.id, `/api/jobs/${encodeURIComponent(job.id)}/image.png`);
      const img = this.list.querySelector(`.asset[data-id="${asset.id}"] .asset-thumb`);
      if (img) {
        img.src = this.thumbnails.get(asset.id);
        img.hidden = false;
      }
    } catch (e) {
      if (e.status === 401) this.onUnauthorized();
    }
  }

  // A job that is queued or running with the asset keeps it (409): its detail says so.
  async remove(asset, error) {
    error.textContent = '';
    try {
      await api.removeAsset(asset.id);
    } catch (e) {
      if (e.status === 401) this.onUnauthorized();
      if (e.status !== 404) {
        error.textContent = e.message;
        return;
      }
    }
    await this.refresh();
    this.panel.querySelector('#asset-file').focus();
  }
}
