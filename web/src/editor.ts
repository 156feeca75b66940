// The config editor: every key by section with its unit, range and note, the command line's
// message at the key it names, and each edit made by the module (`setKey`, which keeps the
// text's comments and layout) and validated (`inspect`).
import { callJson, quick } from './engines';
import { OPEN_SECTIONS, keyNote, keyOf, placeholder, sections, shortKey, toleranceMeaning, typed, valueText } from './keys';
import { encodeConfig } from './share';
import { renderTab, state } from './state';
import { showError } from './status';
import type { KeyDoc } from './types';
import { $ } from './ui';

/** The views whose results came from the previous config. */
const RESULT_VIEWS = ['profile', 'life', 'montecarlo', 'optimize'];

/** Makes `text` the config: validates it, marks the key its message names, puts it in the
 *  address and drops the results of the previous one. `rebuild` (a new text: a preset, an
 *  import) rebuilds the editor and forgets the refused values. */
export async function setText(text: string, rebuild: boolean) {
  state.text = text;
  // One validation gives both the message and the keys with their ranges.
  const r = await callJson(quick, 'inspect', [text]);
  const message = r.message;
  if (rebuild) state.refused.clear();
  state.valid = state.refused.valid(message);
  if (r.keys && (rebuild || state.keys.length === 0)) {
    state.keys = r.keys;
    buildEditor();
  } else if (r.keys && state.valid) {
    // Ranges of keys the last validation did not reach.
    for (const k of r.keys) {
      const row = document.querySelector<HTMLElement>(`.key[data-key="${CSS.escape(k.key)}"] .range`);
      if (row && k.allowed) row.textContent = k.allowed;
    }
  }
  showError(message);
  document.querySelectorAll('.key .msg').forEach((e) => { e.textContent = ''; });
  document.querySelectorAll('.key.bad').forEach((e) => e.classList.remove('bad'));
  if (message) {
    const k = keyOf(message);
    const row = k ? document.querySelector<HTMLElement>(`.key[data-key="${CSS.escape(k)}"]`) : null;
    if (row) { row.classList.add('bad'); row.querySelector('.msg')!.textContent = message; }
  }
  for (const [key, why] of state.refused.entries()) markRefused(key, why);
  history.replaceState(null, '', `#config=${await encodeConfig(text)}`);
  state.study = null; state.montecarlo = null; state.optimize = null;
  document.body.dataset.configValid = String(state.valid);
  if (RESULT_VIEWS.includes(state.tab)) renderTab();
}

/** Loads the built-in reducer `name` into the editor. */
export async function loadPreset(name: string) {
  const text = await quick.call('presetText', [name]);
  await setText(text, true);
}

/** A row of the editor: the key's short name, its box (a checkbox for a boolean), unit, a
 *  tolerance's meaning, range, note and message. */
function keyRow(k: KeyDoc): HTMLElement {
  const row = document.createElement('div');
  row.className = 'key';
  row.dataset.key = k.key;
  const label = document.createElement('label');
  label.textContent = shortKey(k);
  label.title = k.comment;
  const input = document.createElement('input');
  if (typeof k.value === 'boolean') {
    input.type = 'checkbox';
    input.checked = k.value;
    input.onchange = () => edit(k, JSON.stringify(input.checked));
  } else {
    input.type = 'text';
    input.value = valueText(k.value);
    input.placeholder = placeholder(k);
    input.onchange = () => edit(k, typed(input.value, k.value));
  }
  input.name = k.key;
  input.setAttribute('aria-label', k.key);
  label.htmlFor = input.id = `key-${k.key}`;
  const unit = document.createElement('span');
  unit.className = 'unit';
  unit.textContent = k.unit;
  const range = document.createElement('div');
  range.className = 'range';
  range.textContent = k.allowed ?? '';
  // A tolerance's distribution in words (its box holds the TOML, `normal = 1`).
  const meaning = document.createElement('div');
  meaning.className = 'meaning';
  meaning.textContent = toleranceMeaning(k.value, k.unit) ?? '';
  const note = document.createElement('div');
  note.className = 'note';
  note.textContent = keyNote(k);
  const msg = document.createElement('div');
  msg.className = 'msg';
  row.append(label, input, unit, meaning, range, note, msg);
  return row;
}

function buildEditor() {
  const root = $('editor');
  root.replaceChildren();
  for (const [name, keys] of sections(state.keys)) {
    const det = document.createElement('details');
    det.dataset.section = name;
    det.open = OPEN_SECTIONS.includes(name);
    const sum = document.createElement('summary');
    sum.textContent = `[${name}]`;
    det.append(sum, ...keys.map(keyRow));
    root.append(det);
  }
}

/** Shows the refusal `why` at `key`'s row and the page's error box. */
function markRefused(key: string, why: string) {
  showError(why);
  const row = document.querySelector<HTMLElement>(`.key[data-key="${CSS.escape(key)}"]`);
  if (row) { row.classList.add('bad'); row.querySelector('.msg')!.textContent = why; }
}

/** Sets `k` to the JSON `json` in the text. */
async function edit(k: KeyDoc, json: string) {
  try {
    const text = await quick.call('setKey', [state.text, k.key, json]);
    k.value = JSON.parse(json);
    const meaning = document.querySelector<HTMLElement>(`.key[data-key="${CSS.escape(k.key)}"] .meaning`);
    if (meaning) meaning.textContent = toleranceMeaning(k.value, k.unit) ?? '';
    state.refused.accept(k.key);
    await setText(text, false);
  } catch (e) {
    // A value of the wrong type (`2.5` pins, `abc`, blank): the config cannot hold it, so the
    // page holds nothing to run or export until the box is mended.
    const message = (e as Error).message;
    state.refused.refuse(k.key, message);
    state.valid = false;
    document.body.dataset.configValid = 'false';
    markRefused(k.key, message);
    renderTab();
  }
}
