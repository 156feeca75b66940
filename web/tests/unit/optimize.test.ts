// The design search's data: its arguments, the base and best designs compared with units, the
// note and files.
import { describe, expect, it } from 'vitest';
import { SEARCH_DEFAULTS, comparisonRows, goalLabel, plotSeries, searchArgs, searchFiles, searchNote } from '../../src/shape/optimize';
import type { CandidateSummary, OptimizeView } from '../../src/types';

const candidate = (n: number, values: Record<string, number>, life: number | null): CandidateSummary => ({
  candidate: n, phase: n ? 'simplex' : 'start', status: 'ok', feasible: true, values,
  goals: { life }, scores: { life: life === null ? null : life / 7500 }, constraints: { 'lost_motion_arcmin<=1.0': 0.8 },
  limited_by: null,
});

const result: OptimizeView = {
  candidates_csv: 'candidate,...\n', pareto_csv: 'candidate,...\n', optimum_toml: '[reducer]\n',
  start: candidate(0, { 'reducer.bearings.crank_disc_clearance_um': 3 }, 5000),
  best: candidate(17, { 'reducer.bearings.crank_disc_clearance_um': 0.5 }, null),
  front: [17], plots: [{
    stem: 'pareto', title: 't', x_label: 'x', y_label: 'y', against_hours: false, caption: 'c',
    curves: [{ name: 'front', points: [[1, 2], [3, 4]], joined: true }, { name: 'others', points: [[5, 6]], joined: false }],
  }],
};

describe('the design search', () => {
  it('passes the ranges and constraints as JSON lists of their non-blank lines', () => {
    const args = searchArgs('text', { ...SEARCH_DEFAULTS, 'opt-constraints': ' a<=1 \n\n b<=2', 'opt-objective': ' life, b10 ' });
    expect(args[0]).toBe('text');
    expect(JSON.parse(args[1])).toHaveLength(3);
    expect(args.slice(2)).toEqual(['life, b10', '["a<=1","b<=2"]', 20, 1]);
  });
  it('names the goals with their units: the lives in hours', () => {
    expect(goalLabel('life')).toBe('accuracy life, h');
    expect(goalLabel('b10:5')).toBe('B10:5 life, h');
    expect(goalLabel('max_pressure_mpa')).toBe('max_pressure_mpa');
  });
  it('compares the base and best designs key by key, a life beyond the horizon said so', () => {
    expect(comparisonRows(result)).toEqual([
      { label: 'reducer.bearings.crank_disc_clearance_um', cells: [{ text: '3', value: 3 }, { text: '0.5', value: 0.5 }] },
      { label: 'accuracy life, h', cells: [{ text: '5000', value: 5000 }, { text: 'beyond the horizon' }] },
      { label: 'lost_motion_arcmin<=1.0', cells: [{ text: '0.8', value: 0.8 }, { text: '0.8', value: 0.8 }] },
    ]);
  });
  it('leaves the best column blank when no candidate is feasible, and says so', () => {
    const none = { ...result, best: null, optimum_toml: null, front: [] };
    expect(comparisonRows(none)[0].cells).toEqual([{ text: '3', value: 3 }, { text: '' }]);
    expect(searchNote(none)).toBe('No candidate is feasible: widen the ranges or relax the constraints.');
    expect(Object.keys(searchFiles(none))).toEqual(['candidates.csv', 'pareto.csv']);
  });
  it('offers the best design\'s config and draws the plots as declared (markers alone where not joined)', () => {
    expect(searchNote(result)).toBe('The best feasible design is candidate 17 (simplex); optimum.toml is the config with its values.');
    expect(Object.keys(searchFiles(result))).toEqual(['candidates.csv', 'pareto.csv', 'optimum.toml']);
    const s = plotSeries(result.plots[0]);
    expect(s.map((x) => [x.label, x.line])).toEqual([['front', true], ['others', false]]);
    expect(s[0].data).toEqual([{ x: 1, y: 2 }, { x: 3, y: 4 }]);
  });
});
