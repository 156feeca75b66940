// The design search view (`rvlife optimize`): the varied keys' ranges, goals, constraints and
// work entered, the base and best designs compared, the report's plots, the tables and the
// best design's config, which can be loaded into the editor.
import { lineChart } from '../charts';
import { downloadList } from '../downloads';
import { setText } from '../editor';
import { callJson, jobs } from '../engines';
import { job } from '../job';
import { SEARCH_DEFAULTS, type SearchField, comparisonRows, plotSeries, searchArgs, searchFiles, searchNote } from '../shape/optimize';
import { state } from '../state';
import type { OptimizeView } from '../types';
import { $, chartBox, noteOf, wrap } from '../ui';

/** The search's inputs as the user last wrote them, kept while the page is open. */
const searchInputs: Record<SearchField, string> = { ...SEARCH_DEFAULTS };

/** The base and best designs side by side. */
function comparisonTable(o: OptimizeView): HTMLTableElement {
  const t = document.createElement('table');
  t.className = 'numbers';
  const head = t.insertRow();
  for (const h of ['', 'base design', 'best design']) head.insertCell().textContent = h;
  for (const row of comparisonRows(o)) {
    const tr = t.insertRow();
    tr.insertCell().textContent = row.label;
    for (const cell of row.cells) {
      const td = tr.insertCell();
      td.textContent = cell.text;
      if (cell.value !== undefined) td.dataset.value = String(cell.value);
    }
  }
  return t;
}

/** An input of the search (a text area for the lists). */
function field(id: SearchField, label: string, multi: boolean): HTMLElement {
  const l = document.createElement('label');
  const i = multi ? document.createElement('textarea') : document.createElement('input');
  i.id = id; i.name = id; i.value = searchInputs[id];
  if (i instanceof HTMLTextAreaElement) { i.rows = 3; i.cols = 60; } else i.size = 24;
  i.oninput = () => { searchInputs[id] = i.value; };
  l.append(`${label} `, i);
  return l;
}

export function renderOptimize(panel: HTMLElement) {
  const out = document.createElement('div');
  out.id = 'optimize-results';
  const show = (o: OptimizeView) => {
    const load = document.createElement('button');
    load.textContent = 'Load the best design into the editor';
    load.id = 'load-optimum';
    const optimum = o.optimum_toml;
    load.hidden = !optimum;
    load.onclick = async () => {
      if (!optimum) return;
      $<HTMLSelectElement>('preset').value = '';
      await setText(optimum, true);
    };
    // The report's plots, as the library declares them.
    const charts = o.plots.map((p) => {
      const c = chartBox(`chart-${p.stem}`);
      c.setAttribute('aria-label', p.caption);
      return { p, c };
    });
    out.replaceChildren(comparisonTable(o), noteOf(searchNote(o)), load, ...charts.map(({ c }) => wrap(c)), downloadList(searchFiles(o)));
    for (const { p, c } of charts) lineChart(c, plotSeries(p), { x: p.x_label, y: p.y_label, title: p.title });
  };
  const f = document.createElement('form');
  f.className = 'args search';
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
    const args = searchArgs(state.text, searchInputs);
    state.optimize = null;
    out.replaceChildren();
    const o = await job('Design search', (p) => callJson(jobs, 'optimize', args, p));
    if (!o) return;
    state.optimize = o;
    show(o);
  };
  const note = noteOf('rvlife optimize: the values of the varied keys, each within its range, that keep the reducer in spec longest (one goal: a Latin hypercube, CMA-ES, a compass search and Nelder-Mead), or the Pareto front of several goals (NSGA-II), each candidate a study without dynamics and the FE disc; then the best and base designs\' accuracy against hours and the sensitivity at the best. The same candidates as the command line. The ranges, goals, constraints and the whole search\'s work are checked before the first study.');
  panel.append(note, f, out);
  if (state.optimize) show(state.optimize);
}
