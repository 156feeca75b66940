// The Monte Carlo view: reducers drawn from `[tolerances]`, their accuracy lives' distribution
// and reliability curve, the report's verdict, and the samples' tables.
import { lineChart } from '../charts';
import { downloadList } from '../downloads';
import { jobs } from '../engines';
import { montecarlo } from '../montecarlo-run';
import { job } from '../job';
import { limitedByText, mcNumbers, reliabilitySeries } from '../shape/montecarlo';
import { state } from '../state';
import type { MonteCarloView } from '../types';
import { declaredDefault, declaredField } from '../declared';
import { chartBox, form, noteOf, numbersTable, wrap } from '../ui';

export function renderMonteCarlo(panel: HTMLElement) {
  const out = document.createElement('div');
  out.id = 'mc-results';
  const c = chartBox('chart-reliability');
  const show = (m: MonteCarloView) => {
    // The verdict and the reliability curve as the library gives them (the report's).
    const verdict = noteOf(m.verdict);
    verdict.id = 'mc-verdict';
    const summary = numbersTable(mcNumbers(m));
    summary.id = 'mc-numbers';
    const lim = document.createElement('p');
    lim.textContent = limitedByText(m.life);
    out.replaceChildren(verdict, summary, lim, wrap(c), downloadList({ 'samples.csv': m.samples_csv, 'stages.csv': m.stages_csv }));
    lineChart(c, reliabilitySeries(m), { x: 'working hours, h', y: 'fraction within spec', title: 'Reliability of the accuracy life' });
  };
  panel.append(form([
    declaredField('montecarlo', 'samples', { id: 'samples', label: 'samples' }),
    declaredField('montecarlo', 'seed', { id: 'seed', label: 'seed' }),
  ], 'Run Monte Carlo', async (v) => {
    state.montecarlo = null;
    out.replaceChildren();
    // Spread over the analysis workers, merged by the library: the same bytes as one worker.
    const m = await job('Monte Carlo', async (p) =>
      JSON.parse(await montecarlo(jobs, state.text, v.samples ?? Number(declaredDefault('montecarlo', 'samples')), v.seed ?? Number(declaredDefault('montecarlo', 'seed')), p)) as MonteCarloView);
    if (!m) return;
    state.montecarlo = m;
    show(m);
  }), out);
  if (state.montecarlo) show(state.montecarlo);
}
