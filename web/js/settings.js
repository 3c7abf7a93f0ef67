// The render settings form, generated from GET /api/settings: the preset first (choosing one fills
// in what it sets, from the API's `presets`; the fields stay editable), the integrator, then only
// the options it reads (a setting's `integrators`, empty = every integrator, and its `only_with`:
// path shows its photon maps' settings only with caustics or indirect = photon_map), the stopping rule, the
// image size, the accelerator, and the rest. Number inputs carry the API's minimum, maximum and step, enums are
// selects, booleans checkboxes, and every field starts at the API's default.
import {h} from './format.js';

// Where a setting goes; a setting the API adds later lands in "More settings" (or, when only some
// integrators read it, in the integrator's options), so the form always shows all of them.
const STOP = ['spp', 'time_limit', 'target_error', 'spp_per_pass'];
const IMAGE = ['width', 'height'];
const ORDER = ['max_depth', 'rr_depth', 'light_sampling', 'mis', 'caustics', 'photons', 'caustic_photons', 'k',
  'radius', 'indirect', 'indirect_photons', 'indirect_radius', 'kernel', 'alpha', 'final_gather', 'follow_roughness', 'photon_lookup'];

const byOrder = list => (a, b) => {
  const ia = list.indexOf(a), ib = list.indexOf(b);
  return (ia < 0 ? 1e9 : ia) - (ib < 0 ? 1e9 : ib) || a.localeCompare(b);
};

export class SettingsForm {
  /** @param schema GET /api/settings: {name: {type, default, minimum, maximum, enum, unit,
   *  description, integrators, only_with}} */
  constructor(container, schema) {
    this.schema = schema;
    this.container = container;
    this.fields = new Map();  // name -> {wrap, input, error, spec}
    const names = Object.keys(schema);
    const options = names.filter(n => n !== 'integrator' && schema[n].integrators.length > 0)
      .sort(byOrder(ORDER));
    const stop = STOP.filter(n => n in schema);
    const image = IMAGE.filter(n => n in schema);
    const accel = names.filter(n => n === 'accelerator');
    const rest = names.filter(n => n !== 'integrator' && n !== 'preset' && !options.includes(n) &&
      !stop.includes(n) && !image.includes(n) && !accel.includes(n)).sort();

    this.sceneSettings = {};
    container.replaceChildren(
      ...('preset' in schema ? [this.group('Preset', ['preset'], 'preset',
        'Settings measured to trade time for accuracy well; every field below stays editable.')] : []),
      this.group('Integrator', ['integrator']),
      this.optionsGroup = this.group('Integrator options', options, 'options'),
      this.group('Stopping rule', stop, 'stop',
        'The render stops at whichever limit it reaches first; 0 turns a limit off.'),
      this.group('Image size', image, 'image',
        'Over the scene camera\'s: 0 keeps its size, and one side alone keeps its aspect ratio.'),
      this.group('Accelerator', accel),
      this.more(rest));
    this.fields.get('integrator').input.addEventListener('change', () => this.showIntegrator());
    // A setting that others are read only beside (only_with) shows or hides them too.
    const conditions = new Set(Object.values(schema).flatMap(s =>
      Object.values(s.only_with || {}).flat().flatMap(Object.keys)));
    for (const name of conditions)
      this.fields.get(name)?.input.addEventListener('change', () => this.showIntegrator());
    this.fields.get('preset')?.input.addEventListener('change', () => this.applyPreset());
    this.fields.get('target_error')?.input.addEventListener('input', () => this.followTarget());
    this.showIntegrator();
  }

  group(title, names, id, note) {
    return h('fieldset', {class: 'group', 'data-group': id},
      h('legend', {text: title}),
      note && h('p', {class: 'hint', text: note}),
      ...names.map(n => this.field(n)));
  }

  more(names) {
    const details = h('details', {class: 'group', 'data-group': 'more'},
      h('summary', {text: 'More settings'}), ...names.map(n => this.field(n)));
    details.addEventListener('keydown', e => {
      if (e.key === 'Escape' && details.open) {
        details.open = false;
        details.querySelector('summary').focus();
        e.stopPropagation();
      }
    });
    return details;
  }

  field(name) {
    const spec = this.schema[name];
    const id = `s-${name}`;
    const error = h('p', {class: 'field-error', id: `${id}-error`, 'aria-live': 'polite'});
    const desc = h('p', {class: 'desc', id: `${id}-desc`, text: describe(spec)});
    const describedBy = `${id}-desc ${id}-error`;
    let input;
    if (spec.type === 'boolean') {
      input = h('input', {type: 'checkbox', id, name, 'aria-describedby': describedBy});
    } else if (spec.enum) {
      input = h('select', {id, name, 'aria-describedby': describedBy},
        ...spec.enum.map(v => h('option', {value: v, text: v})));
    } else if (spec.type === 'integer' || spec.type === 'number') {
      input = h('input', {type: 'number', id, name, inputmode: spec.type === 'integer' ? 'numeric' : 'decimal',
        step: spec.type === 'integer' ? '1' : 'any', 'aria-describedby': describedBy});
      if (spec.minimum !== undefined) input.min = String(spec.minimum);
      if (spec.maximum !== undefined) input.max = String(spec.maximum);
    } else {
      input = h('input', {type: 'text', id, name, 'aria-describedby': describedBy});
    }
    const unit = spec.unit ? h('span', {class: 'unit', text: ` (${spec.unit})`}) : null;
    const label = h('label', {for: id}, ...(spec.type === 'boolean' ? [input, name] : [name, unit]));
    const wrap = h('div', {class: spec.type === 'boolean' ? 'field check' : 'field', 'data-setting': name},
      label, spec.type === 'boolean' ? null : input, error, desc);
    input.addEventListener('input', () => this.clearError(name));
    this.fields.set(name, {wrap, input, error, spec});
    this.set(name, spec.default);
    return wrap;
  }

  get integrator() { return this.fields.get('integrator').input.value; }

  /** Shows only the chosen integrator's options (hidden ones are disabled: never sent). */
  showIntegrator() {
    const integrator = this.integrator;
    for (const [, f] of this.fields) {
      // only_with: the alternative settings of which the integrator needs one to read it (path's
      // photon maps), each an object of values.
      const alternatives = (f.spec.only_with || {})[integrator];
      const used = (f.spec.integrators.length === 0 || f.spec.integrators.includes(integrator)) &&
        (!alternatives || alternatives.some(needs => Object.entries(needs).every(
          ([name, value]) => this.fields.get(name)?.input.value === value)));
      f.wrap.hidden = !used;
      f.input.disabled = !used;
    }
    for (const group of this.container.querySelectorAll('fieldset[data-group]'))
      group.hidden = !group.querySelector('.field:not([hidden])');
  }

  set(name, value) {
    const f = this.fields.get(name);
    if (!f) return false;
    if (f.spec.type === 'boolean') f.input.checked = Boolean(value);
    else f.input.value = String(value);
    return true;
  }

  /** API defaults, then `overrides` (a scene's own settings) over them. */
  reset(overrides = {}) {
    this.sceneSettings = overrides || {};
    for (const [name, f] of this.fields) this.set(name, f.spec.default);
    for (const [name, value] of Object.entries(this.sceneSettings)) this.set(name, value);
    this.applyPreset();
    this.clearErrors();
  }

  /** The chosen preset's settings over the scene's (as the API merges them); `none`: the scene's. */
  applyPreset() {
    const preset = this.fields.get('preset');
    if (!preset) return;
    const name = preset.input.value;
    for (const [n, f] of this.fields) if (n !== 'preset') this.set(n, f.spec.default);
    const sets = this.schema.preset.presets?.[name]?.settings || {};
    // A scene's own preset is under the scene's values; one chosen here is over them.
    const merged = name === this.sceneSettings.preset ? {...sets, ...this.sceneSettings}
      : {...this.sceneSettings, ...sets};
    for (const [n, value] of Object.entries(merged)) this.set(n, value);
    preset.input.value = name;
    this.followTarget();
    this.showIntegrator();
  }

  /** A preset's settings for the target error (its `under_target` rung, as the API merges them)
   *  in place of its own while the fields hold values the preset sets: auto's smaller passes
   *  under a target. */
  followTarget() {
    const preset = this.schema.preset?.presets?.[this.fields.get('preset')?.input.value];
    const target = this.fields.get('target_error');
    if (!preset?.under_target?.length || !target) return;
    const value = Number(target.input.value);
    const rung = value > 0 ? preset.under_target.find(r => value >= r.target_error) : undefined;
    const chosen = {...preset.settings, ...(rung?.settings || {})};
    for (const n of Object.keys(chosen)) {
      const f = this.fields.get(n);
      const presetValues = [preset.settings[n], ...preset.under_target.map(r => r.settings[n])];
      if (f && presetValues.some(v => v !== undefined && f.input.value === String(v)))
        this.set(n, chosen[n]);
    }
  }

  /** The visible settings as JSON, or null after marking the fields the browser finds invalid. */
  values() {
    const out = {};
    let ok = true;
    // A preset that takes the photon maps the scene needs chooses them on the server (the job's
    // preset_choice says what and why): path's map settings are sent only when changed.
    const sceneMaps = this.schema.preset?.presets?.[this.fields.get('preset')?.input.value]?.scene_maps;
    for (const [name, f] of this.fields) {
      if (f.input.disabled) continue;
      if (sceneMaps && (name === 'caustics' || name === 'indirect') &&
          f.input.value === String(f.spec.default) && !(name in this.sceneSettings)) continue;
      if (f.spec.type === 'boolean') out[name] = f.input.checked;
      else if (f.spec.type === 'integer' || f.spec.type === 'number') {
        if (f.input.value.trim() === '' || !f.input.checkValidity()) {
          this.showError(name, f.input.validationMessage || 'Enter a number.');
          ok = false;
        } else out[name] = Number(f.input.value);
      } else out[name] = f.input.value;
    }
    return ok ? out : null;
  }

  /** Shows a message beside a setting's input; false if no visible field has that name. */
  showError(name, message) {
    const f = this.fields.get(name);
    if (!f || f.wrap.hidden) return false;
    f.error.textContent = message;
    f.input.setAttribute('aria-invalid', 'true');
    const details = f.wrap.closest('details');
    if (details) details.open = true;
    return true;
  }

  focusFirstError() {
    for (const [, f] of this.fields) {
      if (!f.error.textContent) continue;
      f.input.focus({preventScroll: true});
      f.wrap.scrollIntoView({block: 'center'});
      return;
    }
  }

  clearError(name) {
    const f = this.fields.get(name);
    f.error.textContent = '';
    f.input.removeAttribute('aria-invalid');
  }

  clearErrors() { for (const name of this.fields.keys()) this.clearError(name); }
}

function describe(spec) {
  const parts = [spec.description];
  const fmt = v => (Math.abs(v) >= 1e6 && Number.isInteger(v) ? v.toExponential().replace('e+', 'e') : String(v));
  if (spec.minimum !== undefined && spec.maximum !== undefined)
    parts.push(`Range ${fmt(spec.minimum)} – ${fmt(spec.maximum)}.`);
  if (spec.type !== 'boolean') parts.push(`Default ${typeof spec.default === 'number' ? +spec.default.toPrecision(6) : spec.default}.`);
  return parts.join(' ');
}
