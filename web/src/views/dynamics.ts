// The dynamics view: the multibody simulation with rigid or flexible discs under a constant
// output torque, its summary and the dynamic transmission error.
import { lineChart } from '../charts';
import { ratedTorque } from '../keys';
import { DISCS, dteSeries } from '../shape/dynamics';
import { state } from '../state';
import { numbers } from '../ui';
import { analysisView } from './analysis';
import { declaredField } from '../declared';

export function renderDynamics(panel: HTMLElement) {
  analysisView(panel, {
    chart: 'chart-dte', action: 'Simulate', label: 'Dynamics',
    note: 'The multibody model of the whole reducer (rvlife dynamics --disc rigid or flexible: the flexible disc is the FE disc\'s modes).',
    fields: [
      declaredField('dynamics', 'hours', { id: 'hours', label: 'worn at', value: '0' }),
      declaredField('dynamics', 'torque_nm', { id: 'torque', label: 'constant output torque', value: String(ratedTorque(state.keys)) }),
      declaredField('dynamics', 'disc', { id: 'disc', label: 'discs', value: '0', choices: DISCS }),
    ],
    command: 'dynamics',
    args: (text, v) => [text, v.hours || undefined, v.torque, DISCS[v.disc ?? 0]],
    show: (x, out, c) => {
      out.replaceChildren(numbers(x.summary, ['max_wear_um', 'te_mean_arcmin', 'te_peak_to_peak_arcmin', 'te_rms_arcmin', 'max_pin_force_n', 'output_speed_deg_s', 'steps']));
      lineChart(c, dteSeries(x), { x: 'time, s', y: 'DTE, arcmin', title: 'Dynamic transmission error', zoom: true });
    },
  });
}
