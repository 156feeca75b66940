// The hysteresis view: twist against output torque (mean over a mesh cycle and at one crank
// angle) with lost motion, backlash, hysteresis loss and torsional stiffness.
import { lineChart } from '../charts';
import { declaredDefault, declaredField } from '../declared';
import { fmt } from '../format';
import { catalogueMarks, hysteresisSeries } from '../shape/hysteresis';
import { numbers } from '../ui';
import { analysisView } from './analysis';

export function renderHysteresis(panel: HTMLElement) {
  analysisView(panel, {
    chart: 'chart-hysteresis', action: 'Compute', label: 'Hysteresis',
    fields: [
      declaredField('hysteresis', 'crank_deg', { id: 'crank', label: 'crank angle' }),
      declaredField('hysteresis', 'levels', { id: 'levels', label: 'torque levels' }),
      declaredField('hysteresis', 'hours', { id: 'hours', label: 'worn at', value: '0' }),
    ],
    command: 'hysteresis',
    args: (text, v) => [text, v.crank ?? 0, v.levels ?? Number(declaredDefault('hysteresis', 'levels')), v.hours || undefined],
    show: (x, out, c) => {
      out.replaceChildren(numbers(x, ['max_wear_um', 'lost_motion_arcmin', 'backlash_arcmin', 'hysteresis_loss_arcmin', 'torsional_stiffness_nm_per_arcmin']));
      lineChart(c, [...hysteresisSeries(x), ...catalogueMarks(x)], { x: 'output torque, N m', y: 'twist, arcmin', title: `Hysteresis curve: lost motion between the midpoints at +-${fmt(100 * x.measuring_torque_fraction)} % of rated torque, torsional stiffness b/a` });
    },
  });
}
