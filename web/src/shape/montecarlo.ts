// The Monte Carlo view's data: the samples analysed, the life distribution's numbers, what
// limited the lives, and the reliability curve as the library gives it.
import type { Series } from '../charts';
import { namedNumbers } from '../format';
import type { LifeDistribution, MonteCarloView } from '../types';
import { pairs } from './series';

/** The samples whose analysis went through (status `ok`). */
export function analysed(m: MonteCarloView): number {
  return m.records.filter((r) => r.status === 'ok').length;
}

/** The numbers under the verdict: the samples drawn and analysed, the censored fraction and
 *  the B10, B50, 5th and 95th percentile lives (h) the distribution has. */
export function mcNumbers(m: MonteCarloView): [string, number][] {
  return namedNumbers({ samples: m.records.length, analysed: analysed(m), ...m.life },
    ['samples', 'analysed', 'censored_fraction', 'b10_h', 'b50_h', 'p5_h', 'p95_h']);
}

/** `limited by: lost_motion_arcmin 3, ...`: how many lives each threshold limited. */
export function limitedByText(life: LifeDistribution): string {
  return `limited by: ${Object.entries(life.limited_by).map(([k, v]) => `${k} ${v}`).join(', ') || 'none within the horizon'}`;
}

/** The fraction within spec against working hours, labelled with the samples it counts. */
export function reliabilitySeries(m: MonteCarloView): Series[] {
  return [{ label: `reliability: fraction within spec (${analysed(m)} of ${m.records.length} samples analysed)`, data: pairs(m.reliability) }];
}
