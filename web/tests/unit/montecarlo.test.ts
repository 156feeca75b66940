// The Monte Carlo view's data: the reliability curve, the numbers under the verdict and what
// limited the lives.
import { describe, expect, it } from 'vitest';
import { analysed, limitedByText, mcNumbers, reliabilitySeries } from '../../src/shape/montecarlo';
import type { MonteCarloView } from '../../src/types';

const run: MonteCarloView = {
  samples_csv: 'sample,...\n', stages_csv: 'sample,hours,...\n',
  life: { n: 3, censored_fraction: 1 / 3, b10_h: 4200, b50_h: 5600, limited_by: { lost_motion_arcmin: 2 }, failures: 2, horizon_h: 75000 },
  percentiles: [],
  records: [
    { sample: 0, status: 'ok', accuracy_life_h: 4000, limited_by: 'lost_motion_arcmin' },
    { sample: 1, status: 'failed: no equilibrium at 3750 h', accuracy_life_h: null, limited_by: null },
    { sample: 2, status: 'ok', accuracy_life_h: 6000, limited_by: 'lost_motion_arcmin' },
    { sample: 3, status: 'ok', accuracy_life_h: null, limited_by: null },
  ],
  horizon_h: 7500,
  verdict: 'B10 4200 h, B50 5600 h; 3 of 4 samples analysed',
  reliability: [[0, 1], [4000, 1], [4000, 2 / 3], [6000, 2 / 3], [6000, 1 / 3], [7500, 1 / 3]],
};

describe('Monte Carlo', () => {
  it('counts the samples analysed (status ok) out of those drawn', () => {
    expect(analysed(run)).toBe(3);
  });
  it('draws the reliability as the library gives it: a step curve from (0, 1) to the horizon', () => {
    const [s] = reliabilitySeries(run);
    expect(s.label).toBe('reliability: fraction within spec (3 of 4 samples analysed)');
    expect(s.data[0]).toEqual({ x: 0, y: 1 });
    expect(s.data.map((p) => p.x)).toEqual([0, 4000, 4000, 6000, 6000, 7500]);
    // Never rising: a fraction within spec only falls with the hours.
    expect(s.data.every((p, i) => i === 0 || p.y <= s.data[i - 1].y)).toBe(true);
  });
  it('lists the numbers in order, leaving out the percentiles the distribution lacks', () => {
    expect(mcNumbers(run)).toEqual([
      ['samples', 4], ['analysed', 3], ['censored_fraction', 1 / 3], ['b10_h', 4200], ['b50_h', 5600],
    ]);
  });
  it('adds the Weibull fit with its bounds, leaving out an upper bound the samples do not fix', () => {
    const weibull = {
      shape: 2, scale_h: 6000, confidence: 0.9, b10_h: 2000, b10_lower_h: 900, b50_h: 5000,
      b50_lower_h: 3500, b50_upper_h: 7000,
    };
    const fitted = { ...run, life: { ...run.life, km_b10_h: 4000, weibull } };
    expect(mcNumbers(fitted).slice(5)).toEqual([
      ['km_b10_h', 4000], ['weibull_shape', 2], ['weibull_b10_lower_h', 900], ['weibull_b10_h', 2000],
      ['weibull_b50_lower_h', 3500], ['weibull_b50_h', 5000], ['weibull_b50_upper_h', 7000],
    ]);
  });
  it('says what limited the lives, or that none ended within the horizon', () => {
    expect(limitedByText(run.life)).toBe('limited by: lost_motion_arcmin 2');
    expect(limitedByText({ ...run.life, limited_by: {} })).toBe('limited by: none within the horizon');
  });
});
