// The contact view: the static equilibrium at one crank angle under an output torque, its
// numbers and the pin forces of each disc.
import { lineChart } from '../charts';
import { ratedTorque } from '../keys';
import { pinForceSeries } from '../shape/contact';
import { state } from '../state';
import { numbers } from '../ui';
import { analysisView } from './analysis';
import { declaredField } from '../declared';

export function renderContact(panel: HTMLElement) {
  analysisView(panel, {
    chart: 'chart-contact', action: 'Solve', label: 'Contact',
    fields: [
      declaredField('contact', 'crank_deg', { id: 'crank', label: 'crank angle', value: '0' }),
      declaredField('contact', 'torque_nm', { id: 'torque', label: 'output torque', value: String(ratedTorque(state.keys)) }),
      declaredField('contact', 'hours', { id: 'hours', label: 'worn at', value: '' }),
    ],
    command: 'contact',
    args: (text, v) => [text, v.crank ?? 0, v.torque ?? 0, v.hours],
    show: (x, out, c) => {
      out.replaceChildren(numbers(x, ['twist_arcmin', 'max_force_n', 'pins_in_contact', 'max_pressure_mpa', 'torsional_stiffness_nm_per_arcmin', 'max_wear_um', 'residual']));
      lineChart(c, pinForceSeries(x), { x: 'pin', y: 'force, N', title: 'Pin forces' });
    },
  });
}
