// The analysis views' series: hysteresis, transmission error, profile, contact, dynamics.
import { describe, expect, it } from 'vitest';
import { pinForceSeries } from '../../src/shape/contact';
import { DISCS, dteSeries } from '../../src/shape/dynamics';
import { catalogueMarks, hysteresisSeries } from '../../src/shape/hysteresis';
import { flankWearSeries, outlineSeries } from '../../src/shape/profile';
import { meshCyclePoints, teSeries } from '../../src/shape/te';
import type { ContactResult, DynamicsView, HysteresisView, ProfilePoints, TeView, TwistCurve } from '../../src/types';

const curve = (torque: number[], twist: number[]): TwistCurve => ({
  torque_nm: torque, twist_arcmin: twist, backlash_arcmin: 0.1, lost_motion_arcmin: 0.5,
  hysteresis_loss_arcmin: 0.2, torsional_stiffness_nm_per_arcmin: 100,
});

describe('hysteresis', () => {
  const mean = curve([0, 412, 0, -412, 0, 412], [0, 4, 0.3, -4, -0.3, 4]);
  const x: HysteresisView = {
    ...mean, max_wear_um: 0, support: 'bearings', rated_torque_nm: 412, measuring_torque_fraction: 0.03,
    torsional_stiffness_definition: 'b/a', crank_deg: 15, at_crank_angle: curve([0, 412, -412], [0, 4.1, -4.1]),
    samples_per_mesh_cycle: 8, mesh_cycle_mean: mean, twist_shares: [],
    catalogue_points: { lost_motion: [[-12.36, -0.25], [12.36, 0.25]], torsional_stiffness: [[12.36, 0.26], [412, 2.6]] },
  };
  it('gives the mean curve, then the curve at the crank angle, twist against torque in sweep order', () => {
    const [m, at] = hysteresisSeries(x);
    expect(m.label).toBe('mean over a mesh cycle');
    expect(m.data.map((p) => p.x)).toEqual([0, 412, 0, -412, 0, 412]);
    expect(m.data[3]).toEqual({ x: -412, y: -4 });
    expect(at.label).toBe('at crank 15 deg');
    expect(at.data).toEqual([{ x: 0, y: 0 }, { x: 412, y: 4.1 }, { x: -412, y: -4.1 }]);
    expect(at.dash).toBeDefined();
  });
  it('marks the lost motion and the torsional stiffness at the library\'s points, labelled with their values', () => {
    const [lm, ba] = catalogueMarks(x);
    expect(lm.label).toBe('lost motion 0.5 arcmin');
    expect(lm.data).toEqual([{ x: -12.36, y: -0.25 }, { x: 12.36, y: 0.25 }]);
    expect(ba.label).toBe('torsional stiffness b/a = 100 N m/arcmin');
    expect(ba.data).toEqual([{ x: 12.36, y: 0.26 }, { x: 412, y: 2.6 }]);
    // Drawn as joined points, apart from the curves' colours.
    expect(lm.points && ba.points && lm.color !== ba.color).toBe(true);
  });
});

describe('transmission error', () => {
  const base: TeView = {
    max_wear_um: 0, angular_te_arcmin: 0.4, support: 'bearings', te_mean_arcmin: 0.1, te_peak_to_peak_arcmin: 0.05,
    te_reverse_mean_arcmin: -0.1, backlash_arcmin: 0.2, backlash_max_arcmin: 0.25, lost_motion_arcmin: 0.6,
    measuring_torque_nm: 12.36, torsional_stiffness_nm_per_arcmin: 100, samples_per_mesh_cycle: 4,
    input_deg: [0, 1, 2, 3, 4, 5, 6, 7, 8], te_arcmin: [0, 0.1, 0.2, 0.1, 0, 0.1, 0.2, 0.1, 0],
  };
  it('cuts one mesh cycle with the next cycle\'s first point, or shows the whole revolution', () => {
    expect(meshCyclePoints(base)).toBe(5);
    const [cycle] = teSeries(base, meshCyclePoints(base));
    expect(cycle.label).toBe('static TE (forward)');
    expect(cycle.data).toEqual([{ x: 0, y: 0 }, { x: 1, y: 0.1 }, { x: 2, y: 0.2 }, { x: 3, y: 0.1 }, { x: 4, y: 0 }]);
    expect(teSeries(base, base.input_deg.length)[0].data).toHaveLength(9);
  });
  it('adds the loaded TE, labelled with its torque, only when computed', () => {
    expect(teSeries(base, 9)).toHaveLength(1);
    const loaded: TeView = { ...base, torque_nm: 412, loaded_te_arcmin: base.te_arcmin.map((v) => v + 4) };
    const [, l] = teSeries(loaded, 5);
    expect(l.label).toBe('loaded TE at 412 N m');
    expect(l.data.map((p) => p.y)).toEqual([4, 4.1, 4.2, 4.1, 4]);
  });
});

describe('profile', () => {
  const points = (scale: number, wear: number[]): ProfilePoints => ({
    points_per_tooth: 2, max_wear_um: Math.max(...wear), x_mm: [1, 2, 3, 4].map((v) => v * scale),
    y_mm: [0, 1, 0, -1], mesh_angle_deg: [0, 180, 0, 180], wear_um: wear,
  });
  const r = { nominal: points(1, [0, 0, 0, 0]), modified: points(0.99, [0, 0, 0, 0]), worn: points(0.98, [3.14159, 1, 2, 0.5]) };
  it('draws nominal, modified and worn outlines, the worn one labelled with its hours and wear', () => {
    const s = outlineSeries(r, 7500);
    expect(s.map((x) => x.label)).toEqual(['nominal', 'modified', 'worn at 7500 h (max 3.1416 um)']);
    expect(s[0].data[1]).toEqual({ x: 2, y: 1 });
    expect(outlineSeries({ ...r, worn: null }, undefined)).toHaveLength(2);
  });
  it('gives the first tooth\'s wear normal to the flank against its mesh angle, one tooth only', () => {
    const s = flankWearSeries(r.worn, 7500);
    expect(s).toHaveLength(1);
    const [w] = s ?? [];
    expect(w.label).toBe('wear depth of tooth 1 at 7500 h (max 3.1416 um)');
    // x the mesh angle, y the wear depth, from the result; the second tooth left out.
    expect(w.data).toEqual([{ x: 0, y: 3.14159 }, { x: 180, y: 1 }]);
  });
  it('gives no wear chart for an unworn tooth', () => {
    expect(flankWearSeries(r.modified, 0)).toBeNull();
    // Worn elsewhere only (the second tooth): the first is unworn.
    expect(flankWearSeries(points(1, [0, 0, 2, 1]), 100)).toBeNull();
  });
});

describe('contact and dynamics', () => {
  it('gives each disc\'s pin forces against the pin index', () => {
    const disc = (f: number[]) => ({ translation_um: [0, 0] as [number, number], rotation_arcmin: 0, pin_moment_nm: 0, max_force_n: Math.max(...f), pins_in_contact: 2, pin_forces_n: f, pins: [] });
    const x = { discs: [disc([0, 10, 20]), disc([5, 0, 0])] } as unknown as ContactResult;
    const s = pinForceSeries(x);
    expect(s.map((d) => d.label)).toEqual(['disc 1', 'disc 2']);
    expect(s[0].data).toEqual([{ x: 0, y: 0 }, { x: 1, y: 10 }, { x: 2, y: 20 }]);
  });
  it('gives the DTE against time, and offers rigid discs first', () => {
    const x = { time_s: [0, 0.01], te_arcmin: [0.1, 0.2], output_speed_deg_s: [1, 1] } as DynamicsView;
    expect(dteSeries(x)[0].data).toEqual([{ x: 0, y: 0.1 }, { x: 0.01, y: 0.2 }]);
    expect(DISCS[0]).toBe('rigid');
  });
});
