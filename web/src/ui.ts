// The building blocks of the page's views: an element by id, a note, a canvas and its box,
// a table of named numbers, and the form a view runs its command from.
import { fmt, namedNumbers } from './format';
import { state } from './state';

export const $ = <T extends HTMLElement>(id: string) => document.getElementById(id) as T;

/** A paragraph of explanation under a view's controls. */
export function noteOf(text: string): HTMLElement {
  const p = document.createElement('p');
  p.className = 'note';
  p.textContent = text;
  return p;
}

export function chartBox(id: string): HTMLCanvasElement {
  const c = document.createElement('canvas');
  c.id = id;
  return c;
}

/** `c` in the box that sizes it (`square` for the profile's equal axes). */
export function wrap(c: HTMLCanvasElement, cls = ''): HTMLElement {
  const d = document.createElement('div');
  d.className = `chart ${cls}`;
  d.append(c);
  return d;
}

/** A table of named numbers, a row each: its name, then the number as written with the
 *  number itself in `data-value`. */
export function numbersTable(rows: readonly [string, number][]): HTMLTableElement {
  const t = document.createElement('table');
  t.className = 'numbers';
  for (const [k, v] of rows) {
    const tr = t.insertRow();
    tr.insertCell().textContent = k;
    const c = tr.insertCell();
    c.textContent = fmt(v);
    c.dataset.value = String(v);
  }
  return t;
}

/** The numbers of `obj` at `keys` as a table (those that are numbers). */
export function numbers<T extends object>(obj: T, keys: readonly (keyof T & string)[]): HTMLTableElement {
  return numbersTable(namedNumbers(obj, keys));
}

/** A number to enter, or with `choices` one of them (its index); `help` its tooltip. */
export type Field = { id: string; label: string; value: string; unit: string; choices?: string[]; help?: string };

/** The numbers entered, by field id; a blank field is undefined. */
export type FormValues = Record<string, number | undefined>;

/** A form of `fields` whose button (`run-<view>`) hands the numbers entered to `run`. */
export function form(fields: Field[], action: string, run: (v: FormValues) => void): HTMLElement {
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
    if (x.help) l.title = x.help;
    f.append(l);
  }
  const b = document.createElement('button');
  b.type = 'submit'; b.textContent = action; b.id = `run-${state.tab}`;
  f.append(b);
  f.onsubmit = (ev) => {
    ev.preventDefault();
    const v: FormValues = {};
    for (const x of fields) {
      const s = (f.querySelector<HTMLInputElement | HTMLSelectElement>(`#${x.id}`)!).value.trim();
      v[x.id] = s === '' ? undefined : Number(s);
    }
    run(v);
  };
  return f;
}
