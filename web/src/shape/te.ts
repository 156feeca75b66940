// The transmission error view's series: the static TE and, with a torque, the loaded TE,
// over the first mesh cycle or the whole output revolution.
import type { Series } from '../charts';
import type { TeView } from '../types';
import { curve } from './series';

/** The curves' first `n` points against the input angle (deg; TE in arcmin). */
export function teSeries(x: TeView, n: number): Series[] {
  const cut = (a: number[]) => a.slice(0, n);
  const s: Series[] = [{ label: 'static TE (forward)', data: curve(cut(x.input_deg), cut(x.te_arcmin)) }];
  if (x.loaded_te_arcmin) s.push({ label: `loaded TE at ${x.torque_nm} N m`, data: curve(cut(x.input_deg), cut(x.loaded_te_arcmin)), dash: [6, 3] });
  return s;
}

/** The points of one mesh cycle: the curves hold samples_per_mesh_cycle points a cycle, and
 *  the cycle's last point is the next one's first. */
export function meshCyclePoints(x: TeView): number {
  return x.samples_per_mesh_cycle + 1;
}
