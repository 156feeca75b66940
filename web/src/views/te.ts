// The transmission error view: the static TE (and, with a torque, the loaded TE) over one
// mesh cycle and over the output revolution, with the catalogue quantities.
import { lineChart } from '../charts';
import { ratedTorque } from '../keys';
import { meshCyclePoints, teSeries } from '../shape/te';
import { state } from '../state';
import { chartBox, numbers, wrap } from '../ui';
import { analysisView } from './analysis';
import { declaredField } from '../declared';

export function renderTe(panel: HTMLElement) {
  analysisView(panel, {
    chart: 'chart-te', action: 'Compute', label: 'Transmission error',
    fields: [
      declaredField('te', 'hours', { id: 'hours', label: 'worn at', value: '0' }),
      declaredField('te', 'torque_nm', { id: 'torque', label: 'loaded at', value: String(ratedTorque(state.keys)) }),
    ],
    command: 'te',
    // 0 h is the new reducer: no wear asked for.
    args: (text, v) => [text, v.hours || undefined, v.torque],
    show: (x, out, c) => {
      out.replaceChildren(numbers(x, ['max_wear_um', 'te_mean_arcmin', 'te_peak_to_peak_arcmin', 'loaded_te_mean_arcmin', 'loaded_te_peak_to_peak_arcmin', 'backlash_arcmin', 'lost_motion_arcmin', 'angular_te_arcmin', 'torsional_stiffness_nm_per_arcmin']));
      lineChart(c, teSeries(x, meshCyclePoints(x)), { x: 'input angle, deg', y: 'TE, arcmin', title: 'Transmission error over one mesh cycle' });
      const whole = chartBox('chart-te-revolution');
      out.append(wrap(whole));
      lineChart(whole, teSeries(x, x.input_deg.length), { x: 'input angle, deg', y: 'TE, arcmin', title: 'Transmission error over the output revolution (angular TE)' });
    },
  });
}
