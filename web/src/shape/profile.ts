// The profile view's series: the disc outline nominal, modified and worn, and the wear depth
// along one tooth's flank.
import type { Series } from '../charts';
import { fmt } from '../format';
import type { ProfilePoints } from '../types';
import { curve } from './series';

/** The profiles the view draws: `worn` only when worn at some hours. */
export interface Profiles {
  nominal: ProfilePoints;
  modified: ProfilePoints;
  worn: ProfilePoints | null;
}

/** The outlines (x, y in mm), the worn one's label with its hours and largest wear. */
export function outlineSeries(r: Profiles, hours: number | undefined): Series[] {
  const pts = (p: ProfilePoints) => curve(p.x_mm, p.y_mm);
  const series: Series[] = [
    { label: 'nominal', data: pts(r.nominal) },
    { label: 'modified', data: pts(r.modified), dash: [6, 3] },
  ];
  if (r.worn) series.push({ label: `worn at ${hours} h (max ${fmt(r.worn.max_wear_um)} um)`, data: pts(r.worn), dash: [2, 2] });
  return series;
}

/** The wear of the first tooth as gear metrology draws a profile deviation: the depth of
 *  material removed normal to the flank (um, the result's `wear_um`) against the mesh angle
 *  (deg, 0 at the root, 180 at the tip), over the first `points_per_tooth` points; null when
 *  that tooth is unworn (every depth zero), where a chart would be empty. */
export function flankWearSeries(worn: ProfilePoints, hours: number | undefined): Series[] | null {
  const per = worn.points_per_tooth;
  const wear = worn.wear_um.slice(0, per);
  if (wear.every((w) => w === 0)) return null;
  return [{ label: `wear depth of tooth 1 at ${hours} h (max ${fmt(Math.max(...wear))} um)`, data: curve(worn.mesh_angle_deg.slice(0, per), wear) }];
}
