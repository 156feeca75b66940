// The accuracy-life view: the study (`rvlife run` without dynamics; the flexible disc of
// `[fem]` when ticked) on every analysis worker, its verdict against `[life]`, the stage
// table, the accuracy quantities against working hours with their spec, and the results'
// files.
import { lineChart } from '../charts';
import { type Files, downloadList } from '../downloads';
import { jobs, quick } from '../engines';
import { job } from '../job';
import { study } from '../rvlife';
import { LIFE_CHARTS, beyondStages, labelOf, lifeSeries, specLimits, stageTable, withinSpec } from '../shape/life';
import { quantityDocs, state } from '../state';
import { status } from '../status';
import type { AccuracyLife, StudyOverview } from '../types';
import { chartBox, noteOf, numbers, wrap } from '../ui';

/** The stage table: the library's labels with units as headers, a row a stage. */
function stagesTable(s: StudyOverview): HTMLTableElement {
  const { head, rows } = stageTable(s.summary.stages, quantityDocs);
  const table = document.createElement('table');
  table.id = 'stages';
  table.className = 'numbers';
  const headRow = table.createTHead().insertRow();
  for (const h of head) {
    const th = document.createElement('th');
    th.textContent = h.label;
    th.title = h.title;
    th.dataset.column = h.column;
    headRow.append(th);
  }
  const body = table.createTBody();
  for (const row of rows) {
    const tr = body.insertRow();
    for (const cell of row) {
      const td = tr.insertCell();
      td.textContent = cell.text;
      if (cell.value !== undefined) td.dataset.value = String(cell.value);
      td.dataset.column = cell.column;
    }
  }
  return table;
}

/** The study's files: each fetched from the worker that keeps the results when clicked, and
 *  the config as the study ran it. */
function studyFiles(s: StudyOverview): Files {
  const files: Files = {};
  for (const name of s.files) files[name] = () => jobs.call('studyFile', [name]);
  // The config as the study ran it: without dynamics, the FE disc as chosen (`rvlife run` on
  // this file repeats it), not the editor's text.
  const ran = state.studyConfig;
  files['config.toml'] = () => Promise.resolve(ran);
  return files;
}

export function renderLife(panel: HTMLElement) {
  const out = document.createElement('div');
  out.id = 'life-results';
  const show = (s: StudyOverview) => {
    const verdict = document.createElement('p');
    verdict.id = 'verdict';
    verdict.className = `verdict ${withinSpec(s.summary) ? 'ok' : 'bad'}`;
    verdict.textContent = s.verdict;
    const lifeBox = numbers<Partial<AccuracyLife>>(s.summary.accuracy_life ?? {}, ['accuracy_life_h', 'horizon_h']);
    lifeBox.id = 'life-numbers';
    // Beyond the last stage: why the study took longer, and what the charts leave out.
    const beyond = beyondStages(s.summary);
    const notes = beyond ? [Object.assign(noteOf(beyond), { id: 'life-beyond' })] : [];
    const spec = specLimits(state.keys, Object.keys(s.summary.stages[0] ?? {}));
    const charts: HTMLElement[] = [];
    for (const [q, title] of LIFE_CHARTS) {
      const c = chartBox(`chart-${q}`);
      const series = lifeSeries(s.summary, q, spec, quantityDocs);
      charts.push(wrap(c));
      requestAnimationFrame(() => lineChart(c, series, { x: 'working hours, h', y: labelOf(q, quantityDocs), title }));
    }
    const dl = document.createElement('div');
    dl.innerHTML = '<h3>Downloads (the files of <code>rvlife run</code>)</h3>';
    dl.append(downloadList(studyFiles(s)));
    const scroll = document.createElement('div');
    scroll.className = 'scroll';
    scroll.append(stagesTable(s));
    out.replaceChildren(verdict, lifeBox, ...notes, scroll, ...charts, dl);
  };
  const run = document.createElement('button');
  run.id = 'run-life';
  run.textContent = 'Run the study';
  const flexBox = document.createElement('label');
  const flex = document.createElement('input');
  flex.type = 'checkbox';
  flex.id = 'life-flexible';
  flexBox.append(flex, ' with the flexible disc ([fem]: the FE disc at every stage, flexible_* quantities; slower)');
  run.onclick = async () => {
    const text = state.text;
    // The old results go at once: a run cancelled leaves no result that is not its config's.
    state.study = null;
    out.replaceChildren();
    const ran = await quick.call('setKey', [
      await quick.call('setKey', [text, 'dynamics.enabled', 'false']), 'fem.enabled', String(flex.checked)]);
    // The library's line for each step of the life's search beyond the last stage, in the
    // status line while it runs.
    const r = await job('Accuracy-life study', (p) => study(jobs, ran, p, (line) => status(`Accuracy-life study: ${line}`), flex.checked));
    if (!r || text !== state.text) return;
    state.studyConfig = ran;
    const overview = JSON.parse(r) as StudyOverview;
    state.study = overview;
    show(overview);
  };
  const note = noteOf('The study of rvlife run without dynamics (and without the FE disc unless ticked): wear over the stages of [wear], the accuracy quantities at each, the accuracy life against [life].');
  panel.append(run, flexBox, note, out);
  if (state.study) show(state.study);
}
