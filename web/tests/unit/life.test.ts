// The accuracy-life view's data: the stage table with the library's labels and units, the
// spec of [life], and the series against working hours.
import { describe, expect, it } from 'vitest';
import { LIFE_CHARTS, STAGE_COLUMNS, beyondStages, labelOf, lifeSeries, specLimits, stageTable, withinSpec } from '../../src/shape/life';
import type { KeyDoc, QuantityDoc, StageSummary, StudySummary } from '../../src/types';

const doc = (name: string, label: string, unit: string): QuantityDoc =>
  ({ name, label, unit, description: `${label} (${unit})`, models: 'static', columns: [name] });
const docs = new Map([
  doc('hours', 'working hours', 'h'), doc('max_wear_um', 'largest disc wear', 'um'),
  doc('lost_motion_arcmin', 'lost motion', 'arcmin'), doc('backlash_arcmin', 'backlash', 'arcmin'),
  doc('angular_te_arcmin', 'angular TE', 'arcmin'), doc('ste_peak_to_peak_arcmin', 'STE peak to peak', 'arcmin'),
  doc('torsional_stiffness_nm_per_arcmin', 'torsional stiffness', 'N m/arcmin'),
  doc('hysteresis_loss_arcmin', 'hysteresis loss', 'arcmin'), doc('max_pressure_mpa', 'largest Hertz pressure', 'MPa'),
  doc('pins_in_contact', 'pins in contact', ''),
].map((d) => [d.name, d]));

// Every quantity of the static analysis, zero: a stage's record always has them.
const zero = Object.fromEntries(['pin_max_wear_um', 'ste_mean_arcmin', 'ste_reverse_mean_arcmin', 'backlash_max_arcmin',
  'angular_te_assembly_arcmin', 'angular_te_bearing_wear_arcmin', 'angular_te_pin_wear_arcmin', 'angular_te_disc_wear_arcmin',
  'lost_motion_elastic_arcmin', 'lost_motion_assembly_arcmin', 'lost_motion_bearing_wear_arcmin', 'lost_motion_pin_wear_arcmin',
  'lost_motion_disc_wear_arcmin', 'loaded_te_mean_arcmin', 'loaded_te_peak_to_peak_arcmin', 'max_force_n', 'pins_in_contact',
  'pins_in_contact_max', 'disc_load_share', 'crank_disc_clearance_um', 'crank_carrier_clearance_um',
  'tangent_stiffness_nm_per_arcmin'].map((k) => [k, 0]));

const stage = (hours: number, lost: number, stiffness: number): StageSummary => ({
  ...zero, hours, max_wear_um: hours / 1000, lost_motion_arcmin: lost, backlash_arcmin: lost / 2, angular_te_arcmin: 0.4,
  ste_peak_to_peak_arcmin: 0.12345678, torsional_stiffness_nm_per_arcmin: stiffness, hysteresis_loss_arcmin: 0.2,
  max_pressure_mpa: 1234.5678,
} as StageSummary);

const summary: StudySummary = {
  rvlife_version: '0', ratio: 81, rated_torque_nm: 412, wear_model: 'flodin', archard_coefficient_mm3_per_n_m: 1e-8,
  loaded_te_torque_nm: 412, mesh_cycles_per_hour: 1e5, wear_rate_evaluations: 10, twist_shares: [],
  stages: [stage(0, 0.5, 120), stage(3750, 0.8, 110), stage(7500, 1.2, 100)],
  accuracy_life: { accuracy_life_h: 5625, limited_by: 'lost_motion_arcmin', horizon_h: 7500 },
};

const lifeKey = (name: string, value: number): KeyDoc =>
  ({ section: 'life', key: `life.${name}`, value, commented: null, comment: '', unit: '', allowed: null });

describe('the stage table', () => {
  it('heads each column with the library\'s label and unit, its description as the title', () => {
    const { head } = stageTable(summary.stages, docs);
    expect(head.map((h) => h.column)).toEqual(STAGE_COLUMNS);
    expect(head.map((h) => h.label)).toContain('lost motion, arcmin');
    expect(head.find((h) => h.column === 'torsional_stiffness_nm_per_arcmin')!.label).toBe('torsional stiffness, N m/arcmin');
    expect(head[0].title).toBe('working hours (h)');
    expect(head.every((h) => !h.label.includes('_'))).toBe(true);
  });
  it('names an undeclared quantity by its key, and a unitless one by its label alone', () => {
    expect(labelOf('flexible_backlash_arcmin', docs)).toBe('flexible_backlash_arcmin');
    expect(labelOf('pins_in_contact', docs)).toBe('pins in contact');
  });
  it('has a row a stage in order, each cell the number as written and the number itself', () => {
    const { rows } = stageTable(summary.stages, docs);
    expect(rows.map((r) => r[0].value)).toEqual([0, 3750, 7500]);
    const pressure = rows[1].find((c) => c.column === 'max_pressure_mpa')!;
    expect(pressure).toEqual({ column: 'max_pressure_mpa', text: '1234.6', value: 1234.5678 });
    expect(rows[0].find((c) => c.column === 'ste_peak_to_peak_arcmin')!.text).toBe('0.12346');
  });
  it('adds the flexible disc\'s columns after the others when the study ran it', () => {
    const flexible = { ...stage(0, 0.5, 120), flexible_lost_motion_arcmin: 0.61, max_von_mises_mpa: 55.3 } as StageSummary;
    const { head, rows } = stageTable([flexible], docs);
    expect(head.map((h) => h.column).slice(STAGE_COLUMNS.length)).toEqual(['flexible_lost_motion_arcmin', 'max_von_mises_mpa']);
    expect(rows[0].at(-1)).toEqual({ column: 'max_von_mises_mpa', text: '55.3', value: 55.3 });
    expect(stageTable(summary.stages, docs).head.length).toBe(STAGE_COLUMNS.length);
  });
  it('leaves blank a value the study did not produce', () => {
    const partial = { ...stage(0, 0.5, 120), hysteresis_loss_arcmin: undefined } as unknown as StageSummary;
    const cell = stageTable([partial], docs).rows[0].find((c) => c.column === 'hysteresis_loss_arcmin')!;
    expect(cell).toEqual({ column: 'hysteresis_loss_arcmin', text: '', value: undefined });
  });
});

describe('the spec of [life]', () => {
  it('reads maxima of the stage columns and the stiffness as a minimum', () => {
    const keys = [
      lifeKey('lost_motion_arcmin', 1), lifeKey('torsional_stiffness_min_nm_per_arcmin', 105),
      lifeKey('max_hours', 20000), { ...lifeKey('backlash_arcmin', 0), value: null },
      { ...lifeKey('angular_te_arcmin', 1), section: 'te' },
    ];
    expect(specLimits(keys, STAGE_COLUMNS)).toEqual({
      lost_motion_arcmin: { limit: 1, min: false },
      torsional_stiffness_nm_per_arcmin: { limit: 105, min: true },
    });
  });
});

describe('the series against working hours', () => {
  const spec = { lost_motion_arcmin: { limit: 1, min: false }, torsional_stiffness_nm_per_arcmin: { limit: 105, min: true } };
  it('charts each stage, the spec limit across the stages and the accuracy life where it limits', () => {
    const [values, limit, life] = lifeSeries(summary, 'lost_motion_arcmin', spec, docs);
    expect(values.label).toBe('lost motion, arcmin');
    expect(values.data).toEqual([{ x: 0, y: 0.5 }, { x: 3750, y: 0.8 }, { x: 7500, y: 1.2 }]);
    expect(limit.label).toBe('spec: at most 1');
    expect(limit.data).toEqual([{ x: 0, y: 1 }, { x: 7500, y: 1 }]);
    expect(life.label).toBe('accuracy life 5625 h');
    expect(life.data).toEqual([{ x: 5625, y: 0.5 }, { x: 5625, y: 1.2 }]);
  });
  it('draws a minimum as "at least", and no life line where another quantity limits', () => {
    const s = lifeSeries(summary, 'torsional_stiffness_nm_per_arcmin', spec, docs);
    expect(s.map((x) => x.label)).toEqual(['torsional stiffness, N m/arcmin', 'spec: at least 105']);
    expect(lifeSeries(summary, 'backlash_arcmin', spec, docs)).toHaveLength(1);
  });
  it('charts the five accuracy quantities, all of them stage columns', () => {
    expect(LIFE_CHARTS.map(([q]) => q).every((q) => STAGE_COLUMNS.includes(q))).toBe(true);
  });
  it('calls the verdict good news only without a life within the horizon', () => {
    expect(withinSpec(summary)).toBe(false);
    expect(withinSpec({ ...summary, accuracy_life: { horizon_h: 7500 } })).toBe(true);
    expect(withinSpec({ ...summary, accuracy_life: undefined })).toBe(true);
  });
});

describe('the accuracy life beyond the last stage', () => {
  const beyond = { ...summary, accuracy_life: { accuracy_life_h: 10543, limited_by: 'lost_motion_arcmin', horizon_h: 11250 } };
  it('runs the spec line on to a life found beyond the stages', () => {
    const [, limit, life] = lifeSeries(beyond, 'lost_motion_arcmin', { lost_motion_arcmin: { limit: 1, min: false } }, docs);
    expect(limit.data).toEqual([{ x: 0, y: 1 }, { x: 10543, y: 1 }]);
    expect(life.data[0].x).toBe(10543);
  });
  it('says why the study took longer and what the charts leave out', () => {
    expect(beyondStages(summary)).toBeUndefined();
    expect(beyondStages(beyond)).toContain('10543 h');
    const never = beyondStages({ ...summary, accuracy_life: { horizon_h: 75000 } });
    expect(never).toContain('75000 h');
    expect(never).toContain('took longer');
    expect(beyondStages({ ...summary, accuracy_life: { horizon_h: 7500 } })).toBeUndefined();
    expect(beyondStages({ ...summary, accuracy_life: undefined })).toBeUndefined();
  });
});
