// The contact view's series: each disc's pin forces in pin order.
import type { Series } from '../charts';
import type { ContactResult } from '../types';

/** One series a disc (`disc 1`, `disc 2`): force (N) against the pin's index. */
export function pinForceSeries(x: ContactResult): Series[] {
  return x.discs.map((d, i) => ({
    label: `disc ${i + 1}`, data: d.pin_forces_n.map((f, j) => ({ x: j, y: f })), points: true,
  }));
}
