// The dynamics view's series: the dynamic transmission error against time.
import type { Series } from '../charts';
import type { DynamicsView } from '../types';
import { curve } from './series';

/** The disc models of the dynamics (`rvlife dynamics --disc`), in the form's order. */
export const DISCS = ['rigid', 'flexible'];

/** DTE (arcmin) against time (s). */
export function dteSeries(x: DynamicsView): Series[] {
  return [{ label: 'dynamic TE', data: curve(x.time_s, x.te_arcmin) }];
}
