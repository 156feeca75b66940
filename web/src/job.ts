// The analysis running: one at a time (a new one replaces the one running), its progress bar,
// its status line and its cancel button.
import { jobs } from './engines';
import { renderTab, state } from './state';
import { showError, status } from './status';
import { Cancelled, type Progress } from './rvlife';
import { $ } from './ui';

let jobGeneration = 0;

/** Cancels what runs. The first worker keeps the last study's results (its downloads): if it
 *  was restarted they are gone, so the study's view is cleared rather than left offering
 *  files that no longer exist. */
export function cancelJobs() {
  if (jobs.cancel().includes(0) && state.study) {
    state.study = null;
    if (state.tab === 'life') renderTab();
  }
}

/** Runs `run` as the analysis `label`, with its progress shown; its value, or undefined if it
 *  failed (the message shown), was cancelled or was replaced by another. */
export async function job<T>(label: string, run: (p: Progress) => Promise<T>): Promise<T | undefined> {
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
