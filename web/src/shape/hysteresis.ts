// The hysteresis view's series: twist against output torque, averaged over a mesh cycle and
// at one crank angle, and the catalogue quantities marked on the mean curve.
import type { Series } from '../charts';
import { fmt } from '../format';
import type { HysteresisView } from '../types';
import { curve, pairs } from './series';

/** The mean curve, then the curve at the crank angle asked for (N m; arcmin). */
export function hysteresisSeries(x: HysteresisView): Series[] {
  return [
    { label: 'mean over a mesh cycle', data: curve(x.torque_nm, x.twist_arcmin) },
    { label: `at crank ${x.crank_deg} deg`, data: curve(x.at_crank_angle.torque_nm, x.at_crank_angle.twist_arcmin), dash: [6, 3] },
  ];
}

/** The catalogue quantities marked on the curve, from the library's points (torque N m;
 *  twist arcmin): the lost motion's two midpoints at +-the measuring torque joined, and the
 *  torsional stiffness's secant b/a from the measuring to the rated torque. */
export function catalogueMarks(x: HysteresisView): Series[] {
  const p = x.catalogue_points;
  return [
    { label: `lost motion ${fmt(x.lost_motion_arcmin)} arcmin`, data: pairs(p.lost_motion), color: '#D55E00', points: true },
    { label: `torsional stiffness b/a = ${fmt(x.torsional_stiffness_nm_per_arcmin)} N m/arcmin`, data: pairs(p.torsional_stiffness), color: '#009E73', dash: [2, 2], points: true },
  ];
}
