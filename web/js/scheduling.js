// The job's own fields beside its scene and settings (server/http/openapi.json, JobRequest):
// `priority` (every store claims by it) and `task_passes`, which only a PostgreSQL store uses, so
// the form shows it only there.

const FIELDS = ['priority', 'task_passes'];

export class SchedulingFields {
  constructor(fieldset) {
    this.fieldset = fieldset;
    this.inputs = new Map(FIELDS.map(n => [n, fieldset.querySelector(`#j-${n}`)]));
    for (const [name, input] of this.inputs) input.addEventListener('input', () => this.clearError(name));
  }

  /** Shown once the store is known; task_passes (shown and sent) with a PostgreSQL store only. */
  setStore(store) {
    this.fieldset.hidden = false;
    this.inputs.get('task_passes').closest('.field').hidden = store !== 'postgresql';
  }

  /** The fields to add to the job's body ({} when hidden; an empty task_passes is the server's
   *  default), or null after marking an invalid one. */
  values() {
    if (this.fieldset.hidden) return {};
    const out = {};
    for (const [name, input] of this.inputs) {
      if (input.closest('.field').hidden) continue;
      if (input.value.trim() === '') {
        if (name === 'task_passes') continue;
        input.value = '0';
      }
      if (!input.checkValidity()) {
        this.showError(`/${name}`, input.validationMessage || 'Enter a whole number.');
        return null;
      }
      out[name] = Number(input.value);
    }
    return out;
  }

  /** Shows a problem whose pointer is one of these fields beside it; false for another pointer. */
  showError(pointer, message) {
    const input = this.inputs.get(pointer.slice(1));
    if (!input || this.fieldset.hidden) return false;
    this.fieldset.querySelector(`#${input.id}-error`).textContent = message;
    input.setAttribute('aria-invalid', 'true');
    input.focus();
    return true;
  }

  clearError(name) {
    const input = this.inputs.get(name);
    this.fieldset.querySelector(`#${input.id}-error`).textContent = '';
    input.removeAttribute('aria-invalid');
  }

  clearErrors() { for (const name of this.inputs.keys()) this.clearError(name); }
}
