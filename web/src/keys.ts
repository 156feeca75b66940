// The config's keys as the editor shows and edits them, without the page: what a box shows
// for a value, what the user typed as the JSON the module's `setKey` takes, the key an error
// message names, the sections, and the values the config refused.
import { fmt } from './format';
import type { KeyDoc } from './types';

/** The sections open when the editor is built (the reducer, its disc and the spec). */
export const OPEN_SECTIONS = ['reducer', 'cycloid', 'cycloid.modification', 'life'];

/** The dotted key an error message names (`invalid cycloid.pins = ...`, "at `a.b`"), without a
 *  list index; null if it names none. This reads the command line's wording of its messages:
 *  a message worded otherwise is still shown in the page's error box, only not at its key. */
export function keyOf(message: string): string | null {
  const m = /invalid ([a-z0-9_.]+)/.exec(message) ?? /at `([a-z0-9_.[\]]+)`/.exec(message);
  return m ? m[1].replace(/\[\d+\]$/, '') : null;
}

/** What a text box shows for a key's value: a string as it is, a tolerance as its TOML
 *  (`normal = 1`), anything else as JSON, nothing for an unset key. */
export function valueText(v: unknown): string {
  if (v === null || v === undefined) return '';
  const t = toleranceOf(v);
  if (t) return `${t.kind} = ${t.value}`;
  return typeof v === 'string' ? v : JSON.stringify(v);
}

/** The distributions a `[tolerances]` key takes: `{ normal = sigma }`, `{ uniform = limit }`
 *  or `{ iso_grade = 5..11 }`. */
const TOLERANCE_KINDS = ['normal', 'uniform', 'iso_grade'] as const;
type ToleranceKind = typeof TOLERANCE_KINDS[number];

/** A tolerance's one distribution and its number, or null if `v` is not one. */
export function toleranceOf(v: unknown): { kind: ToleranceKind; value: number } | null {
  if (v === null || typeof v !== 'object' || Array.isArray(v)) return null;
  const entries = Object.entries(v);
  if (entries.length !== 1) return null;
  const [kind, value] = entries[0];
  return (TOLERANCE_KINDS as readonly string[]).includes(kind) && typeof value === 'number' ? { kind: kind as ToleranceKind, value } : null;
}

/** A tolerance in words with what it means for the Monte Carlo (docs/config.md `[tolerances]`:
 *  each pin and crank draws its own error about zero), `unit` the key's; null if `v` is not
 *  one. */
export function toleranceMeaning(v: unknown, unit: string): string | null {
  const t = toleranceOf(v);
  if (!t) return null;
  const u = unit ? ` ${unit}` : '';
  switch (t.kind) {
    case 'normal':
      return `normal, 1 sigma = ${t.value}${u}: each part's error drawn about zero with standard deviation ${t.value}${u} (99.7 % within +-${fmt(3 * t.value)}${u})`;
    case 'uniform':
      return `uniform within +-${t.value}${u}: each part's error drawn evenly between -${t.value} and +${t.value}${u} (1 sigma = ${fmt(t.value / Math.sqrt(3))}${u})`;
    case 'iso_grade':
      return `normal, 1 sigma = IT${t.value}/12 of the feature's size (ISO 286-1 grade ${t.value}): the process's +-3 sigma fills the diameter's tolerance zone, halved for a radius or a position`;
  }
}

/** What the user typed, as the JSON value of a key whose value is like `like`: blank removes
 *  the key (null); for a string key the text as it is; else a number, true/false or JSON if it
 *  reads as one, or the text as a string (which the config then refuses by its type). */
export function typed(raw: string, like: unknown): string {
  const t = raw.trim();
  if (t === '') return 'null';
  if (typeof like === 'string') return JSON.stringify(raw);
  // A tolerance as its box shows it (`normal = 1`, also with braces or a colon).
  const tol = /^\{?\s*(normal|uniform|iso_grade)\s*[=:]\s*([-+0-9.eE]+)\s*\}?$/.exec(t);
  if (tol && Number.isFinite(Number(tol[2]))) {
    // A deviation or a limit is a float in the file (`1.0`), a grade a whole number: the JSON
    // says which, so the TOML written is the file's.
    const x = Number(tol[2]);
    const number = tol[1] !== 'iso_grade' && Number.isInteger(x) ? x.toFixed(1) : String(x);
    return `{"${tol[1]}":${number}}`;
  }
  try { return JSON.stringify(JSON.parse(t)); } catch { return JSON.stringify(raw); }
}

/** The keys by section, in the order they come (top-level keys under `(top)`). */
export function sections(keys: readonly KeyDoc[]): Map<string, KeyDoc[]> {
  const out = new Map<string, KeyDoc[]>();
  for (const k of keys) {
    const s = k.section || '(top)';
    const list = out.get(s);
    if (list) list.push(k);
    else out.set(s, [k]);
  }
  return out;
}

/** A key's name within its section (`pins` for `cycloid.pins`). */
export function shortKey(k: KeyDoc): string {
  return k.key.slice(k.section ? k.section.length + 1 : 0);
}

/** The note under a key: its example value, if it has one, and its comment. */
export function keyNote(k: KeyDoc): string {
  return k.commented !== null ? `default / example: ${k.commented}${k.comment ? '. ' + k.comment : ''}` : k.comment;
}

/** The placeholder of a key's box: its default where the text has it commented out. */
export function placeholder(k: KeyDoc): string {
  return k.commented ? `default ${k.commented}` : '';
}

/** The value of `key` in `keys` (undefined if unset or absent). */
export function valueOf(keys: readonly KeyDoc[], key: string): unknown {
  return keys.find((k) => k.key === key)?.value;
}

/** The last working hours of `[wear]`'s stages, h (0 without stages). */
export function lastStageHours(keys: readonly KeyDoc[]): number {
  const h = valueOf(keys, 'wear.stage_hours');
  return Array.isArray(h) && h.length ? Number(h[h.length - 1]) : 0;
}

/** The reducer's rated torque, N m (0 if unset). */
export function ratedTorque(keys: readonly KeyDoc[]): number {
  return Number(valueOf(keys, 'reducer.rated_torque_nm') ?? 0);
}

/** The values the config refused (a value of the wrong type: `2.5` pins, `abc`), by key, with
 *  the message. The box keeps what the user wrote and the config its last value, so nothing
 *  runs or exports while one is held; a value the config takes lifts its key's refusal, a new
 *  text (a preset, an import) all of them. */
export class Refusals {
  private held = new Map<string, string>();

  refuse(key: string, message: string): void { this.held.set(key, message); }

  /** The config took a value of `key`. */
  accept(key: string): void { this.held.delete(key); }

  /** A new text: what was refused in the old one no longer stands. */
  clear(): void { this.held.clear(); }

  get size(): number { return this.held.size; }

  /** The first key held, which an export names. */
  first(): string | undefined {
    const [key] = this.held.keys();
    return key;
  }

  /** Whether the config can run: valid (`message` null, the validation's) and nothing held. */
  valid(message: string | null): boolean {
    return message === null && this.held.size === 0;
  }

  entries(): IterableIterator<[string, string]> { return this.held.entries(); }
}
