// A view that runs one command from a form and shows its numbers and a chart (contact, TE,
// hysteresis, dynamics).
import { callJson, jobs } from '../engines';
import { job } from '../job';
import type { Args, JsonCommand, JsonOf } from '../protocol';
import { state } from '../state';
import { chartBox, form, noteOf, wrap, type Field, type FormValues } from '../ui';

export interface AnalysisSpec<K extends JsonCommand> {
  /** The canvas's id. */
  chart: string;
  note?: string;
  fields: Field[];
  /** The button's text. */
  action: string;
  /** The analysis's name in the status line. */
  label: string;
  command: K;
  /** The command's arguments for the config `text` and the numbers entered. */
  args: (text: string, v: FormValues) => Args<K>;
  show: (x: JsonOf<K>, out: HTMLElement, chart: HTMLCanvasElement) => void;
}

export function analysisView<K extends JsonCommand>(panel: HTMLElement, spec: AnalysisSpec<K>) {
  const out = document.createElement('div');
  const c = chartBox(spec.chart);
  if (spec.note) panel.append(noteOf(spec.note));
  panel.append(form(spec.fields, spec.action, async (v) => {
    out.replaceChildren();
    const x = await job(spec.label, (p) => callJson(jobs, spec.command, spec.args(state.text, v), p));
    if (x) spec.show(x, out, c);
  }), out, wrap(c));
}
