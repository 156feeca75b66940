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

/** The numbers under the verdict: the samples drawn and analysed, the censored fraction, the
 *  B10, B50, 5th and 95th percentile lives (h) the distribution has, the Kaplan-Meier B10 and
 *  B50 (at most these where the interpolated ones are absent) and the Weibull fit's shape,
 *  B10 and B50 with their 90 % likelihood-ratio bounds (h) where there is a fit. */
export function mcNumbers(m: MonteCarloView): [string, number][] {
  const w = m.life.weibull;
  const weibull = {
    weibull_shape: w?.shape,
    weibull_b10_h: w?.b10_h, weibull_b10_lower_h: w?.b10_lower_h, weibull_b10_upper_h: w?.b10_upper_h,
    weibull_b50_h: w?.b50_h, weibull_b50_lower_h: w?.b50_lower_h, weibull_b50_upper_h: w?.b50_upper_h,
  };
  return namedNumbers({ samples: m.records.length, analysed: analysed(m), ...m.life, ...weibull },
    ['samples', 'analysed', 'censored_fraction', 'b10_h', 'b50_h', 'p5_h', 'p95_h', 'km_b10_h',
      'km_b50_h', 'weibull_shape', 'weibull_b10_lower_h', 'weibull_b10_h', 'weibull_b10_upper_h',
      'weibull_b50_lower_h', 'weibull_b50_h', 'weibull_b50_upper_h']);
}

/** `limited by: lost_motion_arcmin 3, ...`: how many lives each threshold limited. */
export function limitedByText(life: LifeDistribution): string {
  return `limited by: ${Object.entries(life.limited_by).map(([k, v]) => `${k} ${v}`).join(', ') || 'none within the horizon'}`;
}

/** The fraction within spec against working hours, labelled with the samples it counts. */
export function reliabilitySeries(m: MonteCarloView): Series[] {
  return [{ label: `reliability: fraction within spec (${analysed(m)} of ${m.records.length} samples analysed)`, data: pairs(m.reliability) }];
}
