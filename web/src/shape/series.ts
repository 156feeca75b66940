// Chart points from the module's columns: the x and y lists of a result, or its [x, y] pairs.
import type { Point } from '../charts';

/** The points (xs[i], ys[i]). */
export function curve(xs: readonly number[], ys: readonly number[]): Point[] {
  return xs.map((x, i) => ({ x, y: ys[i] }));
}

/** The points of [x, y] pairs. */
export function pairs(list: readonly (readonly [number, number])[]): Point[] {
  return list.map(([x, y]) => ({ x, y }));
}
