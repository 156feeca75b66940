// The hysteresis view's series: twist against output torque, averaged over a mesh cycle and
// at one crank angle.
import type { Series } from '../charts';
import type { HysteresisResult } from '../types';
import { curve } from './series';

/** The mean curve, then the curve at the crank angle asked for (N m; arcmin). */
export function hysteresisSeries(x: HysteresisResult): Series[] {
  return [
    { label: 'mean over a mesh cycle', data: curve(x.torque_nm, x.twist_arcmin) },
    { label: `at crank ${x.crank_deg} deg`, data: curve(x.at_crank_angle.torque_nm, x.at_crank_angle.twist_arcmin), dash: [6, 3] },
  ];
}
