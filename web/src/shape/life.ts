// The accuracy-life view's data: the stage table's headers (the library's labels with units)
// and rows, the spec of `[life]`, and each accuracy quantity's series against working hours
// with its spec limit and the accuracy life.
import type { Series } from '../charts';
import { fmt } from '../format';
import type { KeyDoc, QuantityDoc, QuantityName, StageSummary, StudySummary } from '../types';

/** The stage table's columns, in order. */
export const STAGE_COLUMNS: readonly QuantityName[] = ['hours', 'max_wear_um', 'lost_motion_arcmin', 'backlash_arcmin', 'angular_te_arcmin', 'ste_peak_to_peak_arcmin', 'torsional_stiffness_nm_per_arcmin', 'hysteresis_loss_arcmin', 'max_pressure_mpa'];

/** The flexible disc's columns, shown when the study ran it (`[fem]`). */
export const FLEXIBLE_COLUMNS: readonly QuantityName[] = ['flexible_lost_motion_arcmin', 'flexible_backlash_arcmin', 'flexible_ste_peak_to_peak_arcmin', 'flexible_loaded_te_peak_to_peak_arcmin', 'flexible_torsional_stiffness_nm_per_arcmin', 'max_von_mises_mpa'];

/** The quantities charted against working hours, with the chart's title. */
export const LIFE_CHARTS: readonly [QuantityName, string][] = [
  ['lost_motion_arcmin', 'Lost motion'], ['backlash_arcmin', 'Backlash'],
  ['angular_te_arcmin', 'Angular transmission error'], ['torsional_stiffness_nm_per_arcmin', 'Torsional stiffness'],
  ['max_wear_um', 'Largest disc wear'],
];

/** A quantity's label with its unit (`lost motion, arcmin`), or its name if undeclared. */
export function labelOf(name: string, docs: ReadonlyMap<string, QuantityDoc>): string {
  const q = docs.get(name);
  return q ? (q.unit ? `${q.label}, ${q.unit}` : q.label) : name;
}

/** Quantity `q` of a stage as one number (a smallest-largest pair as its range, as the
 *  library's `Value::number`), or undefined where its model did not run. */
export function stageValue(st: StageSummary, q: QuantityName): number | undefined {
  const v = st[q];
  return Array.isArray(v) ? v[1] - v[0] : v;
}

export interface StageHead { column: string; label: string; title: string }
export interface StageCell { column: string; text: string; value: number | undefined }

/** The stage table: a header a column (its label, its description as the title) and a row a
 *  stage, the flexible disc's columns after the others when the study ran it; a value the
 *  study did not produce is left blank. */
export function stageTable(stages: readonly StageSummary[], docs: ReadonlyMap<string, QuantityDoc>): { head: StageHead[]; rows: StageCell[][] } {
  // The flexible disc's columns where the study ran it.
  const columns = [...STAGE_COLUMNS, ...FLEXIBLE_COLUMNS.filter((c) => stages[0]?.[c] !== undefined)];
  const head = columns.map((c) => ({ column: c, label: labelOf(c, docs), title: docs.get(c)?.description ?? c }));
  const rows = stages.map((st) => columns.map((c) => {
    const v = stageValue(st, c);
    return { column: c, text: v === undefined ? '' : fmt(v), value: v };
  }));
  return { head, rows };
}

/** A limit of the spec: at most `limit`, or with `min` at least. */
export interface Limit { limit: number; min: boolean }

/** The spec of `[life]` by stage column: `life.lost_motion_arcmin` a maximum of the column of
 *  that name, `life.torsional_stiffness_min_nm_per_arcmin` a minimum of the stiffness. */
export function specLimits(keys: readonly KeyDoc[], columns: readonly string[]): Record<string, Limit> {
  const out: Record<string, Limit> = {};
  for (const k of keys) {
    if (k.section !== 'life' || typeof k.value !== 'number') continue;
    const name = k.key.slice('life.'.length);
    if (name === 'torsional_stiffness_min_nm_per_arcmin') out.torsional_stiffness_nm_per_arcmin = { limit: k.value, min: true };
    else if (columns.includes(name)) out[name] = { limit: k.value, min: false };
  }
  return out;
}

/** Whether the verdict is good news: no life set, or none within the horizon. */
export function withinSpec(s: StudySummary): boolean {
  return !s.accuracy_life || s.accuracy_life.accuracy_life_h == null;
}

/** Quantity `q` at each stage, then its spec limit across the stages, then, where `q` limits
 *  the life, a vertical line at the accuracy life spanning the values and the limit. */
export function lifeSeries(s: StudySummary, q: QuantityName, spec: Record<string, Limit>, docs: ReadonlyMap<string, QuantityDoc>): Series[] {
  const hours = s.stages.map((x) => x.hours);
  // A value the study did not produce leaves a gap.
  const ys = s.stages.map((x) => stageValue(x, q) ?? NaN);
  const series: Series[] = [{ label: labelOf(q, docs), data: hours.map((h, i) => ({ x: h, y: ys[i] })), points: true }];
  const lim = spec[q];
  const life = s.accuracy_life;
  // The spec line runs on to an accuracy life found beyond the last stage, so that the chart
  // shows where the quantity meets it.
  const end = Math.max(hours[hours.length - 1] ?? 0, life?.accuracy_life_h ?? 0);
  if (lim) series.push({ label: `spec: ${lim.min ? 'at least' : 'at most'} ${lim.limit}`, data: [{ x: 0, y: lim.limit }, { x: end, y: lim.limit }], dash: [8, 4], color: '#c0392b' });
  if (life?.accuracy_life_h != null && q === life.limited_by) {
    const at = life.accuracy_life_h;
    series.push({ label: `accuracy life ${fmt(at)} h`, data: [{ x: at, y: Math.min(...ys) }, { x: at, y: Math.max(...ys, lim?.limit ?? -Infinity) }], dash: [2, 3], color: '#555' });
  }
  return series;
}

/** What the charts, which end at the last stage, do not show: where the accuracy life or the
 *  search for it lies beyond the last stage, a sentence saying so (the search's points are not
 *  kept: each is a wear integration on from the last stage); otherwise none. */
export function beyondStages(s: StudySummary): string | undefined {
  const last = s.stages[s.stages.length - 1]?.hours;
  const life = s.accuracy_life;
  if (last === undefined || !life) return undefined;
  if (life.accuracy_life_h != null) {
    if (life.accuracy_life_h <= last) return undefined;
    return `The spec is met at every stage (to ${fmt(last)} h): the accuracy life, ${fmt(life.accuracy_life_h)} h, was found by integrating the wear on beyond the last stage, a wear integration per step, which is why this study took longer; the charts mark it after their last stage.`;
  }
  if (life.horizon_h <= last) return undefined;
  return `The spec is met at every stage (to ${fmt(last)} h) and on to the search's horizon, ${fmt(life.horizon_h)} h (life.max_hours): the wear was integrated on beyond the last stage step by step to look for the accuracy life, which is why this study took longer; the charts show the stages only.`;
}
