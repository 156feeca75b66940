// The design search's data: its inputs as the command takes them, the table of the base and
// best designs (values, goals with their units, constraints), the note under it, its files
// and the report's plots as series.
import type { Series } from '../charts';
import { fmt } from '../format';
import type { Args } from '../protocol';
import type { CandidateSummary, OptimizeView, SearchPlot } from '../types';
import { pairs } from './series';

/** The search's inputs by field id: the example's varied keys, goal, constraint and work. */
export const SEARCH_DEFAULTS: Readonly<Record<SearchField, string>> = {
  'opt-vary': 'cycloid.modification.equidistant_mm=0.005:0.03\ncycloid.modification.offset_mm=-0.01:0.02\nreducer.bearings.crank_disc_clearance_um=0:6',
  'opt-objective': 'life',
  'opt-constraints': 'lost_motion_arcmin<=1.0',
  'opt-evaluations': '20',
  'opt-seed': '1',
};

export type SearchField = 'opt-vary' | 'opt-objective' | 'opt-constraints' | 'opt-evaluations' | 'opt-seed';

/** The non-blank lines of `s`, trimmed. */
export function lines(s: string): string[] {
  return s.split('\n').map((l) => l.trim()).filter(Boolean);
}

/** The command's arguments for the config `text` and the inputs: the ranges and constraints
 *  as JSON lists (one a line), the goals as written. */
export function searchArgs(text: string, v: Readonly<Record<SearchField, string>>): Args<'optimize'> {
  return [text, JSON.stringify(lines(v['opt-vary'])), v['opt-objective'].trim(),
    JSON.stringify(lines(v['opt-constraints'])), Number(v['opt-evaluations']), Number(v['opt-seed'])];
}

/** A goal's name with its unit: the life and B10 in hours. */
export function goalLabel(k: string): string {
  return k === 'life' ? 'accuracy life, h' : k.startsWith('b10') ? `${k.toUpperCase()} life, h` : k;
}

/** A cell of the comparison: its text and, for a number, the number. */
export interface Cell { text: string; value?: number }

/** The base and best designs side by side: a row for each varied key, goal and constraint,
 *  named as the best design (or, without one, the base) names them. A goal beyond the horizon
 *  reads so. */
export function comparisonRows(o: OptimizeView): { label: string; cells: Cell[] }[] {
  const ref = o.best ?? o.start;
  const out: { label: string; cells: Cell[] }[] = [];
  const parts: ((x: CandidateSummary) => Record<string, number | null>)[] = [(x) => x.values, (x) => x.goals, (x) => x.constraints];
  for (const pick of parts) {
    for (const k of ref ? Object.keys(pick(ref)) : []) {
      const cells = [o.start, o.best].map((x): Cell => {
        const v = x ? pick(x)[k] : undefined;
        return typeof v === 'number' ? { text: fmt(v), value: v } : { text: v === null ? 'beyond the horizon' : '' };
      });
      out.push({ label: goalLabel(k), cells });
    }
  }
  return out;
}

/** The sentence under the table: the best design and the Pareto front, or why there is none. */
export function searchNote(o: OptimizeView): string {
  const front = o.front.length > 1 ? ` The Pareto front holds ${o.front.length} designs (pareto.csv).` : '';
  return o.best
    ? `The best feasible design is candidate ${o.best.candidate} (${o.best.phase}); optimum.toml is the config with its values.${front}`
    : 'No candidate is feasible: widen the ranges or relax the constraints.';
}

/** The search's files: its tables, and the best design's config when there is one. */
export function searchFiles(o: OptimizeView): Record<string, string> {
  const files: Record<string, string> = { 'candidates.csv': o.candidates_csv, 'pareto.csv': o.pareto_csv };
  if (o.optimum_toml) files['optimum.toml'] = o.optimum_toml;
  return files;
}

/** A plot's curves as the library declares them: joined or markers alone, points shown. */
export function plotSeries(p: SearchPlot): Series[] {
  return p.curves.map((k) => ({ label: k.name, data: pairs(k.points), line: k.joined, points: true }));
}
