// rvlife's web page: the config editor, the analysis views and the downloads. Every number
// comes from rvlife's WebAssembly module in a Web Worker (rvlife.ts, worker.ts); the page only
// lays out, plots (Chart.js) and saves.
import './style.css';
import { keepOffline } from './offline';
import { Cancelled, Engine, study } from './rvlife';
import { lineChart, Series, destroyCharts } from './charts';
import { decodeConfig, encodeConfig } from './share';

type KeyDoc = {
  section: string; key: string; value: unknown; commented: string | null;
  comment: string; unit: string; allowed: string | null;
};
type Preset = { name: string; summary: string };

const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T;

/** Config work (quick) and analyses (long, cancellable) run in separate workers, so that
 *  editing stays live while a study runs; the study's stages run on one analysis worker per
 *  core (up to four). */
const quick = new Engine();
const jobs = new Engine(Math.max(1, Math.min(navigator.hardwareConcurrency || 1, 4)), true);

const state = {
  text: '',
  valid: false,
  keys: [] as KeyDoc[],
  tab: 'life',
  study: null as null | { summary: any; verdict: string; files: string[] },
  montecarlo: null as null | any,
  optimize: null as null | any,
  /** Keys whose typed value the config refused (the box keeps what the user wrote; the
   *  config keeps its last value, so nothing runs or exports until it is mended). */
  refused: new Map<string, string>(),
};

// ---------------------------------------------------------------- status and progress

function status(text: string) { $('status').textContent = text; }

let jobGeneration = 0;

/** Cancels what runs. The first worker keeps the last study's results (its downloads): if it
 *  was restarted they are gone, so the study's view is cleared rather than left offering
 *  files that no longer exist. */
function cancelJobs() {
  if (jobs.cancel().includes(0) && state.study) {
    state.study = null;
    if (state.tab === 'life') renderTab();
  }
}

async function job<T>(label: string, run: (p: (d: number, t: number) => void) => Promise<T>): Promise<T | undefined> {
  const bar = $<HTMLProgressElement>('progress');
  const cancel = $('cancel');
  // One analysis at a time: a new one replaces the one running.
  if (jobs.busy) cancelJobs();
  const mine = ++jobGeneration;
  const current = () => mine === jobGeneration;
  bar.hidden = false; cancel.hidden = false; bar.removeAttribute('value');
  status(`${label}...`);
  const t0 = performance.now();
  try {
    const v = await run((d, t) => { if (current()) { bar.max = t; bar.value = d; status(`${label}: ${d} / ${t}`); } });
    if (current()) {
      status(`${label}: done in ${((performance.now() - t0) / 1000).toFixed(2)} s`);
      document.body.dataset.lastJobMs = String(performance.now() - t0);
    }
    return v;
  } catch (e) {
    if (!current()) return undefined;
    if (e instanceof Cancelled) status(`${label}: cancelled`);
    else { status(`${label}: failed`); showError((e as Error).message); }
    return undefined;
  } finally {
    if (current()) { bar.hidden = true; cancel.hidden = true; }
  }
}

function showError(message: string | null) {
  const box = $('config-error');
  box.hidden = !message;
  box.textContent = message ?? '';
}

// ---------------------------------------------------------------- the config

/** The dotted key an error message names (`invalid cycloid.pins = ...`, "at `a.b`"). */
function keyOf(message: string): string | null {
  const m = /invalid ([a-z0-9_.]+)/.exec(message) ?? /at `([a-z0-9_.\[\]]+)`/.exec(message);
  return m ? m[1].replace(/\[\d+\]$/, '') : null;
}

async function setText(text: string, rebuild: boolean) {
  state.text = text;
  // One validation gives both the message and the keys with their ranges.
  const r: { message: string | null; keys: KeyDoc[] | null } = JSON.parse(await quick.call('inspect', [text]));
  const message = r.message;
  if (rebuild) state.refused.clear();
  state.valid = message === null && state.refused.size === 0;
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
  for (const [key, why] of state.refused) markRefused(key, why);
  history.replaceState(null, '', `#config=${await encodeConfig(text)}`);
  state.study = null; state.montecarlo = null; state.optimize = null;
  document.body.dataset.configValid = String(state.valid);
  // The views whose results came from the previous config.
  if (['profile', 'life', 'montecarlo', 'optimize'].includes(state.tab)) renderTab();
}

function valueText(v: unknown): string {
  if (v === null || v === undefined) return '';
  return typeof v === 'string' ? v : JSON.stringify(v);
}

/** What the user typed as the JSON value of a key: a number, true/false, JSON, or a string. */
function typed(raw: string, like: unknown): string {
  const t = raw.trim();
  if (t === '') return 'null';
  if (typeof like === 'string') return JSON.stringify(raw);
  try { return JSON.stringify(JSON.parse(t)); } catch { return JSON.stringify(raw); }
}

function buildEditor() {
  const root = $('editor');
  root.replaceChildren();
  const sections = new Map<string, KeyDoc[]>();
  for (const k of state.keys) {
    const s = k.section || '(top)';
    if (!sections.has(s)) sections.set(s, []);
    sections.get(s)!.push(k);
  }
  for (const [name, keys] of sections) {
    const det = document.createElement('details');
    det.dataset.section = name;
    det.open = ['reducer', 'cycloid', 'cycloid.modification', 'life'].includes(name);
    const sum = document.createElement('summary');
    sum.textContent = `[${name}]`;
    det.append(sum);
    for (const k of keys) {
      const row = document.createElement('div');
      row.className = 'key';
      row.dataset.key = k.key;
      const label = document.createElement('label');
      const short = k.key.slice(k.section ? k.section.length + 1 : 0);
      label.textContent = short;
      label.title = k.comment;
      let input: HTMLInputElement;
      if (typeof k.value === 'boolean') {
        input = document.createElement('input');
        input.type = 'checkbox';
        input.checked = k.value;
        input.onchange = () => edit(k, JSON.stringify(input.checked));
      } else {
        input = document.createElement('input');
        input.type = 'text';
        input.value = valueText(k.value);
        input.placeholder = k.commented ? `default ${k.commented}` : '';
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
      const note = document.createElement('div');
      note.className = 'note';
      note.textContent = k.commented !== null ? `default / example: ${k.commented}${k.comment ? '. ' + k.comment : ''}` : k.comment;
      const msg = document.createElement('div');
      msg.className = 'msg';
      row.append(label, input, unit, range, note, msg);
      det.append(row);
    }
    root.append(det);
  }
}

/** Shows the refusal `why` at `key`'s row and the page's error box. */
function markRefused(key: string, why: string) {
  showError(why);
  const row = document.querySelector<HTMLElement>(`.key[data-key="${CSS.escape(key)}"]`);
  if (row) { row.classList.add('bad'); row.querySelector('.msg')!.textContent = why; }
}

async function edit(k: KeyDoc, json: string) {
  try {
    const text = await quick.call('setKey', [state.text, k.key, json]);
    k.value = JSON.parse(json);
    state.refused.delete(k.key);
    await setText(text, false);
  } catch (e) {
    // A value of the wrong type (`2.5` pins, `abc`, blank): the config cannot hold it, so the
    // page holds nothing to run or export until the box is mended.
    const message = (e as Error).message;
    state.refused.set(k.key, message);
    state.valid = false;
    document.body.dataset.configValid = 'false';
    markRefused(k.key, message);
    renderTab();
  }
}

// ---------------------------------------------------------------- downloads

function download(name: string, text: string, type = 'text/plain') {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = name.replace(/\//g, '_');
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
}

/** Download buttons: each file's text, or a function that fetches it when clicked. */
function downloadList(files: Record<string, string | (() => Promise<string>)>): HTMLElement {
  const ul = document.createElement('ul');
  ul.className = 'downloads';
  for (const [name, text] of Object.entries(files)) {
    const li = document.createElement('li');
    const b = document.createElement('button');
    b.textContent = name;
    b.dataset.file = name;
    b.onclick = async () => {
      try {
        const t = typeof text === 'string' ? text : await text();
        download(name, t, name.endsWith('.json') ? 'application/json' : 'text/plain');
      } catch (e) { showError((e as Error).message); }
    };
    li.append(b);
    if (typeof text === 'string') li.append(` ${(text.length / 1024).toFixed(0)} kB`);
    ul.append(li);
  }
  return ul;
}

// ---------------------------------------------------------------- views

/** A number to enter, or with `choices` one of them (its index). */
type Field = { id: string; label: string; value: string; unit: string; choices?: string[] };

/** The disc models of the dynamics (`rvlife dynamics --disc`). */
const DISCS = ['rigid', 'flexible'];

function form(fields: Field[], action: string, run: (v: Record<string, number | undefined>) => void): HTMLElement {
  const f = document.createElement('form');
  f.className = 'args';
  for (const x of fields) {
    const l = document.createElement('label');
    let i: HTMLInputElement | HTMLSelectElement;
    if (x.choices) {
      const sel = document.createElement('select');
      x.choices.forEach((c, k) => { const o = document.createElement('option'); o.value = String(k); o.textContent = c; sel.append(o); });
      i = sel;
    } else {
      const inp = document.createElement('input');
      inp.size = 8;
      i = inp;
    }
    i.id = x.id; i.name = x.id; i.value = x.value;
    l.append(`${x.label} `, i, ` ${x.unit}`);
    f.append(l);
  }
  const b = document.createElement('button');
  b.type = 'submit'; b.textContent = action; b.id = `run-${state.tab}`;
  f.append(b);
  f.onsubmit = (ev) => {
    ev.preventDefault();
    const v: Record<string, number | undefined> = {};
    for (const x of fields) {
      const s = (f.querySelector<HTMLInputElement | HTMLSelectElement>(`#${x.id}`)!).value.trim();
      v[x.id] = s === '' ? undefined : Number(s);
    }
    run(v);
  };
  return f;
}

function numbers(obj: Record<string, unknown>, keys: string[]): HTMLElement {
  const t = document.createElement('table');
  t.className = 'numbers';
  for (const k of keys) {
    const v = obj[k];
    if (typeof v !== 'number') continue;
    const tr = t.insertRow();
    tr.insertCell().textContent = k;
    const c = tr.insertCell();
    c.textContent = fmt(v);
    c.dataset.value = String(v);
  }
  return t;
}

function fmt(v: number): string {
  if (!Number.isFinite(v)) return String(v);
  const a = Math.abs(v);
  return a !== 0 && (a < 1e-3 || a >= 1e6) ? v.toExponential(4) : Number(v.toPrecision(5)).toString();
}

/** A paragraph of explanation under a view's controls. */
function noteOf(text: string): HTMLElement {
  const p = document.createElement('p');
  p.className = 'note';
  p.textContent = text;
  return p;
}

function chartBox(id: string): HTMLCanvasElement {
  const c = document.createElement('canvas');
  c.id = id;
  return c;
}

function lastStageHours(): number {
  const h = state.keys.find((k) => k.key === 'wear.stage_hours')?.value;
  return Array.isArray(h) && h.length ? Number(h[h.length - 1]) : 0;
}

function ratedTorque(): number {
  return Number(state.keys.find((k) => k.key === 'reducer.rated_torque_nm')?.value ?? 0);
}

const tabs: Record<string, { title: string; render: (panel: HTMLElement) => void }> = {
  // The answer first: the page opens on the accuracy life, its study already running.
  life: { title: 'Accuracy life', render: renderLife },
  profile: { title: 'Profile', render: renderProfile },
  contact: { title: 'Contact', render: renderContact },
  te: { title: 'Transmission error', render: renderTe },
  hysteresis: { title: 'Hysteresis', render: renderHysteresis },
  dynamics: { title: 'Dynamics', render: renderDynamics },
  montecarlo: { title: 'Monte Carlo', render: renderMonteCarlo },
  optimize: { title: 'Design search', render: renderOptimize },
};

function buildTabs() {
  const nav = $('tabs');
  for (const [id, t] of Object.entries(tabs)) {
    const b = document.createElement('button');
    b.textContent = t.title;
    b.dataset.tab = id;
    b.onclick = () => { state.tab = id; renderTab(); };
    nav.append(b);
  }
}

function renderTab() {
  destroyCharts();
  document.querySelectorAll<HTMLElement>('#tabs button').forEach((b) => b.classList.toggle('active', b.dataset.tab === state.tab));
  const panel = $('panel');
  panel.replaceChildren();
  if (!state.valid) {
    const p = document.createElement('p');
    p.className = 'error';
    p.textContent = 'Fix the config (the message above names the key) to see this view.';
    panel.append(p);
    return;
  }
  tabs[state.tab].render(panel);
}

let profileHours = '';

function renderProfile(panel: HTMLElement) {
  const outline = chartBox('chart-profile');
  const wear = chartBox('chart-wear');
  const draw = async (hours: number | undefined) => {
    const text = state.text;
    const r = await job('Profile', async (p) => {
      const nominal = JSON.parse(await jobs.call('profile', [text, undefined, undefined, true, 60]));
      const modified = JSON.parse(await jobs.call('profile', [text, undefined, undefined, false, 60]));
      const worn = hours ? JSON.parse(await jobs.call('profile', [text, hours, undefined, false, 60], p)) : null;
      return { nominal, modified, worn };
    });
    if (!r || text !== state.text) return;
    const pts = (x: any) => x.x_mm.map((v: number, i: number) => ({ x: v, y: x.y_mm[i] }));
    const series: Series[] = [
      { label: 'nominal', data: pts(r.nominal) },
      { label: 'modified', data: pts(r.modified), dash: [6, 3] },
    ];
    if (r.worn) series.push({ label: `worn at ${hours} h (max ${fmt(r.worn.max_wear_um)} um)`, data: pts(r.worn), dash: [2, 2] });
    lineChart(outline, series, { x: 'x, mm', y: 'y, mm', equal: true, zoom: true, title: 'Disc profile (wheel or pinch to zoom, drag to pan)' });
    if (r.worn) {
      const per = r.worn.points_per_tooth;
      const w = r.worn.mesh_angle_deg.slice(0, per).map((a: number, i: number) => ({ x: a, y: r.worn.wear_um[i] }));
      lineChart(wear, [{ label: `wear depth of tooth 1 at ${hours} h`, data: w }], { x: 'mesh angle, deg (0 root, 180 tip)', y: 'wear, um', title: 'Wear along the flank' });
    }
  };
  if (!profileHours) profileHours = String(lastStageHours());
  const f = form([{ id: 'profile-hours', label: 'worn at', value: profileHours, unit: 'h' }], 'Draw', (v) => {
    profileHours = v['profile-hours'] === undefined ? '' : String(v['profile-hours']);
    draw(v['profile-hours']);
  });
  const reset = document.createElement('button');
  reset.textContent = 'Reset zoom';
  reset.onclick = () => (outline as any).chart?.resetZoom?.();
  panel.append(f, reset, wrap(outline, 'square'), wrap(wear));
  draw(profileHours === '' ? undefined : Number(profileHours));
}

function wrap(c: HTMLCanvasElement, cls = ''): HTMLElement {
  const d = document.createElement('div');
  d.className = `chart ${cls}`;
  d.append(c);
  return d;
}

/** A view that runs one command from a form and shows its numbers and one chart. */
function analysisView(panel: HTMLElement, spec: {
  chart: string; note?: string; fields: Field[]; action: string; label: string;
  call: (v: Record<string, number | undefined>) => [string, unknown[]];
  show: (x: any, out: HTMLElement, chart: HTMLCanvasElement) => void;
}) {
  const out = document.createElement('div');
  const c = chartBox(spec.chart);
  if (spec.note) panel.append(noteOf(spec.note));
  panel.append(form(spec.fields, spec.action, async (v) => {
    const [cmd, args] = spec.call(v);
    out.replaceChildren();
    const r = await job(spec.label, (p) => jobs.call(cmd, [state.text, ...args], p));
    if (r) spec.show(JSON.parse(r), out, c);
  }), out, wrap(c));
}

const curve = (xs: number[], ys: number[]) => xs.map((x, i) => ({ x, y: ys[i] }));

function renderContact(panel: HTMLElement) {
  analysisView(panel, {
    chart: 'chart-contact', action: 'Solve', label: 'Contact',
    fields: [
      { id: 'crank', label: 'crank angle', value: '0', unit: 'deg' },
      { id: 'torque', label: 'output torque', value: String(ratedTorque()), unit: 'N m' },
      { id: 'hours', label: 'worn at', value: '', unit: 'h' },
    ],
    call: (v) => ['contact', [v.crank ?? 0, v.torque ?? 0, v.hours]],
    show: (x, out, c) => {
      out.replaceChildren(numbers(x, ['twist_arcmin', 'max_force_n', 'pins_in_contact', 'max_pressure_mpa', 'torsional_stiffness_nm_per_arcmin', 'max_wear_um', 'residual']));
      lineChart(c, x.discs.map((d: any, i: number) => ({ label: `disc ${i + 1}`, data: d.pin_forces_n.map((f: number, j: number) => ({ x: j, y: f })), points: true })),
        { x: 'pin', y: 'force, N', title: 'Pin forces' });
    },
  });
}

function renderTe(panel: HTMLElement) {
  analysisView(panel, {
    chart: 'chart-te', action: 'Compute', label: 'Transmission error',
    fields: [
      { id: 'hours', label: 'worn at', value: '0', unit: 'h' },
      { id: 'torque', label: 'loaded at', value: String(ratedTorque()), unit: 'N m' },
    ],
    call: (v) => ['te', [v.hours || undefined, v.torque]],
    show: (x, out, c) => {
      out.replaceChildren(numbers(x, ['max_wear_um', 'te_mean_arcmin', 'te_peak_to_peak_arcmin', 'loaded_te_mean_arcmin', 'loaded_te_peak_to_peak_arcmin', 'backlash_arcmin', 'lost_motion_arcmin', 'angular_te_arcmin', 'torsional_stiffness_nm_per_arcmin']));
      // The curves run over the output revolution at samples_per_mesh_cycle points a mesh
      // cycle: the first mesh cycle (its last point the next one's first), then the whole.
      const series = (n: number): Series[] => {
        const cut = (a: number[]) => a.slice(0, n);
        const s: Series[] = [{ label: 'static TE (forward)', data: curve(cut(x.input_deg), cut(x.te_arcmin)) }];
        if (x.loaded_te_arcmin) s.push({ label: `loaded TE at ${x.torque_nm} N m`, data: curve(cut(x.input_deg), cut(x.loaded_te_arcmin)), dash: [6, 3] });
        return s;
      };
      lineChart(c, series(x.samples_per_mesh_cycle + 1), { x: 'input angle, deg', y: 'TE, arcmin', title: 'Transmission error over one mesh cycle' });
      const whole = chartBox('chart-te-revolution');
      out.append(wrap(whole));
      lineChart(whole, series(x.input_deg.length), { x: 'input angle, deg', y: 'TE, arcmin', title: 'Transmission error over the output revolution (angular TE)' });
    },
  });
}

function renderHysteresis(panel: HTMLElement) {
  analysisView(panel, {
    chart: 'chart-hysteresis', action: 'Compute', label: 'Hysteresis',
    fields: [
      { id: 'crank', label: 'crank angle', value: '0', unit: 'deg' },
      { id: 'levels', label: 'torque levels', value: '21', unit: '' },
      { id: 'hours', label: 'worn at', value: '0', unit: 'h' },
    ],
    call: (v) => ['hysteresis', [v.crank ?? 0, v.levels ?? 21, v.hours || undefined]],
    show: (x, out, c) => {
      out.replaceChildren(numbers(x, ['max_wear_um', 'lost_motion_arcmin', 'backlash_arcmin', 'hysteresis_loss_arcmin', 'torsional_stiffness_nm_per_arcmin']));
      lineChart(c, [
        { label: 'mean over a mesh cycle', data: curve(x.torque_nm, x.twist_arcmin) },
        { label: `at crank ${x.crank_deg} deg`, data: curve(x.at_crank_angle.torque_nm, x.at_crank_angle.twist_arcmin), dash: [6, 3] },
      ], { x: 'output torque, N m', y: 'twist, arcmin', title: 'Hysteresis curve (catalogue lost motion at +-3 % of rated torque)' });
    },
  });
}

function renderDynamics(panel: HTMLElement) {
  analysisView(panel, {
    chart: 'chart-dte', action: 'Simulate', label: 'Dynamics',
    note: 'The multibody model of the whole reducer (rvlife dynamics --disc rigid or flexible: the flexible disc is the FE disc\'s modes).',
    fields: [
      { id: 'hours', label: 'worn at', value: '0', unit: 'h' },
      { id: 'torque', label: 'constant output torque', value: String(ratedTorque()), unit: 'N m' },
      { id: 'disc', label: 'discs', value: '0', unit: '', choices: DISCS },
    ],
    call: (v) => ['dynamics', [v.hours || undefined, v.torque, DISCS[v.disc ?? 0]]],
    show: (x, out, c) => {
      out.replaceChildren(numbers(x.summary, ['max_wear_um', 'te_mean_arcmin', 'te_peak_to_peak_arcmin', 'te_rms_arcmin', 'max_pin_force_n', 'output_speed_deg_s', 'steps']));
      lineChart(c, [{ label: 'dynamic TE', data: curve(x.time_s, x.te_arcmin) }],
        { x: 'time, s', y: 'DTE, arcmin', title: 'Dynamic transmission error', zoom: true });
    },
  });
}

/** The spec of `[life]`: stage column to its limit and sense (`life.lost_motion_arcmin` is a
 *  maximum, `life.torsional_stiffness_min_nm_per_arcmin` a minimum). */
function specLimits(columns: string[]): Record<string, { limit: number; min: boolean }> {
  const out: Record<string, { limit: number; min: boolean }> = {};
  for (const k of state.keys) {
    if (k.section !== 'life' || typeof k.value !== 'number') continue;
    const name = k.key.slice('life.'.length);
    if (name === 'torsional_stiffness_min_nm_per_arcmin') out.torsional_stiffness_nm_per_arcmin = { limit: k.value, min: true };
    else if (columns.includes(name)) out[name] = { limit: k.value, min: false };
  }
  return out;
}

/** A stage quantity as the library declares it (`rvlife::api::QuantityDoc`). */
type QuantityDoc = { name: string; unit: string; label: string; description: string; models: string; columns: string[] };

/** The library's stage quantities by name, loaded when the page starts. */
const quantityDocs = new Map<string, QuantityDoc>();

/** A quantity's label with its unit (`lost motion, arcmin`), or its name if undeclared. */
function labelOf(name: string): string {
  const q = quantityDocs.get(name);
  return q ? (q.unit ? `${q.label}, ${q.unit}` : q.label) : name;
}

const STAGE_COLUMNS = ['hours', 'max_wear_um', 'lost_motion_arcmin', 'backlash_arcmin', 'angular_te_arcmin', 'ste_peak_to_peak_arcmin', 'torsional_stiffness_nm_per_arcmin', 'hysteresis_loss_arcmin', 'max_pressure_mpa'];

function renderLife(panel: HTMLElement) {
  const out = document.createElement('div');
  out.id = 'life-results';
  const show = () => {
    const s = state.study!;
    const verdict = document.createElement('p');
    verdict.id = 'verdict';
    const ok = !s.summary.accuracy_life || s.summary.accuracy_life.accuracy_life_h == null;
    verdict.className = `verdict ${ok ? 'ok' : 'bad'}`;
    verdict.textContent = s.verdict;
    const table = document.createElement('table');
    table.id = 'stages';
    table.className = 'numbers';
    const head = table.createTHead().insertRow();
    for (const c of STAGE_COLUMNS) {
      const th = document.createElement('th');
      th.textContent = labelOf(c);
      th.title = quantityDocs.get(c)?.description ?? c;
      th.dataset.column = c;
      head.append(th);
    }
    const body = table.createTBody();
    for (const st of s.summary.stages) {
      const tr = body.insertRow();
      for (const c of STAGE_COLUMNS) {
        const td = tr.insertCell();
        td.textContent = fmt(st[c]);
        td.dataset.value = String(st[c]);
        td.dataset.column = c;
      }
    }
    const life = s.summary.accuracy_life;
    const lifeBox = numbers(life ?? {}, ['accuracy_life_h', 'horizon_h']);
    lifeBox.id = 'life-numbers';
    const spec = specLimits(Object.keys(s.summary.stages[0] ?? {}));
    const hours = s.summary.stages.map((x: any) => x.hours);
    const charts: HTMLElement[] = [];
    for (const [q, title] of [['lost_motion_arcmin', 'Lost motion'], ['backlash_arcmin', 'Backlash'], ['angular_te_arcmin', 'Angular transmission error'], ['torsional_stiffness_nm_per_arcmin', 'Torsional stiffness'], ['max_wear_um', 'Largest disc wear']]) {
      const c = chartBox(`chart-${q}`);
      const series: Series[] = [{ label: labelOf(q), data: hours.map((h: number, i: number) => ({ x: h, y: s.summary.stages[i][q] })), points: true }];
      const lim = spec[q];
      if (lim) series.push({ label: `spec: ${lim.min ? 'at least' : 'at most'} ${lim.limit}`, data: [{ x: 0, y: lim.limit }, { x: hours[hours.length - 1], y: lim.limit }], dash: [8, 4], color: '#c0392b' });
      if (life?.accuracy_life_h != null && q === life.limited_by) {
        const ys = s.summary.stages.map((x: any) => x[q]);
        series.push({ label: `accuracy life ${fmt(life.accuracy_life_h)} h`, data: [{ x: life.accuracy_life_h, y: Math.min(...ys) }, { x: life.accuracy_life_h, y: Math.max(...ys, lim?.limit ?? -Infinity) }], dash: [2, 3], color: '#555' });
      }
      charts.push(wrap(c));
      requestAnimationFrame(() => lineChart(c, series, { x: 'working hours, h', y: labelOf(q), title }));
    }
    const files: Record<string, string | (() => Promise<string>)> = {};
    for (const name of s.files) files[name] = () => jobs.call('studyFile', [name]);
    // The config as the study ran it: without dynamics and the FE disc (`rvlife run` on this
    // file repeats it), not the editor's text, which may enable them.
    const ran = state.text;
    files['config.toml'] = async () => {
      const off = await quick.call('setKey', [ran, 'dynamics.enabled', 'false']);
      return quick.call('setKey', [off, 'fem.enabled', 'false']);
    };
    const dl = document.createElement('div');
    dl.innerHTML = '<h3>Downloads (the files of <code>rvlife run</code>)</h3>';
    dl.append(downloadList(files));
    const scroll = document.createElement('div');
    scroll.className = 'scroll';
    scroll.append(table);
    out.replaceChildren(verdict, lifeBox, scroll, ...charts, dl);
  };
  const run = document.createElement('button');
  run.id = 'run-life';
  run.textContent = 'Run the study (static analyses)';
  run.onclick = async () => {
    const text = state.text;
    // The old results go at once: a run cancelled leaves no result that is not its config's.
    state.study = null;
    out.replaceChildren();
    const r = await job('Accuracy-life study', (p) => study(jobs, text, p));
    if (!r || text !== state.text) return;
    state.study = JSON.parse(r);
    show();
  };
  const note = noteOf('The study of rvlife run without dynamics and the FE disc: wear over the stages of [wear], the accuracy quantities at each, the accuracy life against [life].');
  panel.append(run, note, out);
  if (state.study) show();
}

function renderMonteCarlo(panel: HTMLElement) {
  const out = document.createElement('div');
  out.id = 'mc-results';
  const c = chartBox('chart-reliability');
  const show = () => {
    const m = state.montecarlo;
    const ok = m.records.filter((r: { status: string }) => r.status === 'ok').length;
    // The verdict and the reliability curve as the library gives them (the report's).
    const verdict = noteOf(m.verdict);
    verdict.id = 'mc-verdict';
    const pts = (m.reliability as [number, number][]).map(([x, y]) => ({ x, y }));
    const summary = numbers({ samples: m.records.length, analysed: ok, ...m.life, censored_fraction: m.life.censored_fraction }, ['samples', 'analysed', 'censored_fraction', 'b10_h', 'b50_h', 'p5_h', 'p95_h']);
    summary.id = 'mc-numbers';
    const lim = document.createElement('p');
    lim.textContent = `limited by: ${Object.entries(m.life.limited_by).map(([k, v]) => `${k} ${v}`).join(', ') || 'none within the horizon'}`;
    out.replaceChildren(verdict, summary, lim, wrap(c), downloadList({ 'samples.csv': m.samples_csv, 'stages.csv': m.stages_csv }));
    lineChart(c, [{ label: `reliability: fraction within spec (${ok} of ${m.records.length} samples analysed)`, data: pts }], { x: 'working hours, h', y: 'fraction within spec', title: 'Reliability of the accuracy life' });
  };
  panel.append(form([
    { id: 'samples', label: 'samples', value: '4', unit: '' },
    { id: 'seed', label: 'seed', value: '1', unit: '' },
  ], 'Run Monte Carlo', async (v) => {
    state.montecarlo = null;
    out.replaceChildren();
    const r = await job('Monte Carlo', (p) => jobs.call('montecarlo', [state.text, v.samples ?? 4, v.seed ?? 1], p));
    if (!r) return;
    state.montecarlo = JSON.parse(r);
    show();
  }), out);
  if (state.montecarlo) show();
}

/** One plot of the design search's report (rvlife::output::candidates::Plot). */
type SearchPlot = {
  stem: string; title: string; x_label: string; y_label: string; against_hours: boolean; caption: string;
  curves: { name: string; points: [number, number][]; joined: boolean }[];
};

/** The design search's inputs as the user last wrote them (the example's keys and spec). */
const searchInputs: Record<string, string> = {
  'opt-vary': 'cycloid.modification.equidistant_mm=0.005:0.03\ncycloid.modification.offset_mm=-0.01:0.02\nreducer.bearings.crank_disc_clearance_um=0:6',
  'opt-objective': 'life',
  'opt-constraints': 'lost_motion_arcmin<=1.0',
  'opt-evaluations': '20',
  'opt-seed': '1',
};

function renderOptimize(panel: HTMLElement) {
  const out = document.createElement('div');
  out.id = 'optimize-results';
  const lines = (s: string) => s.split('\n').map((l) => l.trim()).filter(Boolean);
  const show = () => {
    const o = state.optimize;
    const t = document.createElement('table');
    t.className = 'numbers';
    const head = t.insertRow();
    for (const h of ['', 'base design', 'best design']) head.insertCell().textContent = h;
    // The goals' names with their unit (the life and B10 in hours).
    const label = (k: string) => (k === 'life' ? 'accuracy life, h' : k.startsWith('b10') ? `${k.toUpperCase()} life, h` : k);
    const rows = (pick: (x: any) => Record<string, unknown> | undefined) => {
      const keys = Object.keys(pick(o.best ?? o.start) ?? {});
      for (const k of keys) {
        const tr = t.insertRow();
        tr.insertCell().textContent = label(k);
        for (const x of [o.start, o.best]) {
          const v = x ? pick(x)?.[k] : undefined;
          const cell = tr.insertCell();
          cell.textContent = typeof v === 'number' ? fmt(v) : v === null ? 'beyond the horizon' : '';
          if (typeof v === 'number') cell.dataset.value = String(v);
        }
      }
    };
    rows((x) => x.values);
    rows((x) => x.goals);
    rows((x) => x.constraints);
    const front = o.front.length > 1 ? ` The Pareto front holds ${o.front.length} designs (pareto.csv).` : '';
    const note = noteOf(o.best
      ? `The best feasible design is candidate ${o.best.candidate} (${o.best.phase}); optimum.toml is the config with its values.${front}`
      : 'No candidate is feasible: widen the ranges or relax the constraints.');
    const files: Record<string, string> = { 'candidates.csv': o.candidates_csv, 'pareto.csv': o.pareto_csv };
    if (o.optimum_toml) files['optimum.toml'] = o.optimum_toml;
    const load = document.createElement('button');
    load.textContent = 'Load the best design into the editor';
    load.id = 'load-optimum';
    load.hidden = !o.optimum_toml;
    load.onclick = async () => { $<HTMLSelectElement>('preset').value = ''; await setText(o.optimum_toml, true); };
    // The report's plots, as the library declares them (rvlife::output::candidates::plots).
    const charts: [SearchPlot, HTMLCanvasElement][] = (o.plots as SearchPlot[]).map((p) => {
      const c = chartBox(`chart-${p.stem}`);
      c.setAttribute('aria-label', p.caption);
      return [p, c];
    });
    out.replaceChildren(t, note, load, ...charts.map(([, c]) => wrap(c)), downloadList(files));
    for (const [p, c] of charts) {
      lineChart(c, p.curves.map((k) => ({ label: k.name, data: k.points.map(([x, y]) => ({ x, y })), line: k.joined, points: true })),
        { x: p.x_label, y: p.y_label, title: p.title });
    }
  };
  const f = document.createElement('form');
  f.className = 'args search';
  const field = (id: string, label: string, multi: boolean) => {
    const l = document.createElement('label');
    const i = multi ? document.createElement('textarea') : document.createElement('input');
    i.id = id; i.name = id; i.value = searchInputs[id];
    if (i instanceof HTMLTextAreaElement) { i.rows = 3; i.cols = 60; } else i.size = 24;
    i.oninput = () => { searchInputs[id] = i.value; };
    l.append(`${label} `, i);
    return l;
  };
  const b = document.createElement('button');
  b.type = 'submit'; b.textContent = 'Search'; b.id = 'run-optimize';
  f.append(
    field('opt-vary', 'vary (KEY=LO:HI, one a line)', true),
    field('opt-objective', 'goals (life, b10, [max:]QUANTITY[@STAGE]; two or more, comma-separated: a Pareto front)', false),
    field('opt-constraints', 'constraints (QUANTITY<=VALUE, one a line)', true),
    field('opt-evaluations', 'candidates', false),
    field('opt-seed', 'seed', false),
    b,
  );
  f.onsubmit = async (ev) => {
    ev.preventDefault();
    const v = searchInputs;
    const args = [state.text, JSON.stringify(lines(v['opt-vary'])), v['opt-objective'].trim(),
      JSON.stringify(lines(v['opt-constraints'])), Number(v['opt-evaluations']), Number(v['opt-seed'])];
    state.optimize = null;
    out.replaceChildren();
    const r = await job('Design search', (p) => jobs.call('optimize', args, p));
    if (!r) return;
    state.optimize = JSON.parse(r);
    show();
  };
  const note = noteOf('rvlife optimize: the values of the varied keys, each within its range, that keep the reducer in spec longest (one goal: a Latin hypercube, CMA-ES, a compass search and Nelder-Mead), or the Pareto front of several goals (NSGA-II), each candidate a study without dynamics and the FE disc; then the best and base designs\' accuracy against hours and the sensitivity at the best. The same candidates as the command line. The ranges, goals, constraints and the whole search\'s work are checked before the first study.');
  panel.append(note, f, out);
  if (state.optimize) show();
}

// ---------------------------------------------------------------- start

async function loadPreset(name: string) {
  const text = await quick.call('presetText', [name]);
  await setText(text, true);
}

async function start() {
  buildTabs();
  const presets: Preset[] = JSON.parse(await quick.call('presets', []));
  for (const q of JSON.parse(await quick.call('quantities', [])) as QuantityDoc[]) quantityDocs.set(q.name, q);
  const sel = $<HTMLSelectElement>('preset');
  for (const p of presets) {
    const o = document.createElement('option');
    o.value = p.name; o.textContent = p.name; o.title = p.summary;
    sel.append(o);
  }
  const custom = document.createElement('option');
  custom.value = ''; custom.textContent = '(imported or shared)';
  sel.append(custom);
  sel.onchange = () => { if (sel.value) loadPreset(sel.value); };
  $('cancel').onclick = () => cancelJobs();
  $('export').onclick = () => {
    const [key] = state.refused.keys();
    if (key !== undefined) { status(`export refused: mend the value at ${key} first`); return; }
    download('rvlife.toml', state.text, 'application/toml');
  };
  $('import').onclick = () => $('import-file').click();
  $<HTMLInputElement>('import-file').onchange = async (ev) => {
    const f = (ev.target as HTMLInputElement).files?.[0];
    if (!f) return;
    sel.value = '';
    await setText(await f.text(), true);
    (ev.target as HTMLInputElement).value = '';
  };
  $('share').onclick = async () => {
    await navigator.clipboard?.writeText(location.href).catch(() => undefined);
    status('link copied: it holds the whole config');
  };
  const shared = location.hash.startsWith('#config=') ? await decodeConfig(location.hash.slice(8)).catch(() => null) : null;
  if (shared) { sel.value = ''; await setText(shared, true); } else { sel.value = 'rv-40e'; await loadPreset('rv-40e'); }
  renderTab();
  document.body.dataset.ready = 'true';
  // The verdict and its limiting quantity as soon as the page opens (any edit or other run
  // replaces this study).
  if (state.tab === 'life' && state.valid) $('run-life').click();
}

if ('serviceWorker' in navigator && location.protocol !== 'file:') {
  navigator.serviceWorker.register('./sw.js').catch(() => undefined);
  // Once loaded, the page works offline (offline.ts): `data-offline="ready"` says so.
  navigator.serviceWorker.ready
    .then(() => Promise.all([keepOffline([location.href]), quick.call('keepOffline', [])]))
    .then(() => { document.body.dataset.offline = 'ready'; })
    .catch(() => undefined);
}

start().catch((e) => showError(String(e)));
