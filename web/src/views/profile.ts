// The profile view: the disc outline nominal, modified and worn at some hours (zoom and pan),
// and below it the wear of one tooth as a profile deviation (tens of um, invisible on the
// outline).
import { chartOf, lineChart } from '../charts';
import { callJson, jobs } from '../engines';
import { job } from '../job';
import { lastStageHours } from '../keys';
import { flankWearSeries, outlineSeries } from '../shape/profile';
import { state } from '../state';
import { chartBox, form, noteOf, wrap } from '../ui';
import { declaredField } from '../declared';

/** The hours last drawn at, kept while the page is open (blank: not worn); the last stage's
 *  at first. */
let profileHours = '';

export function renderProfile(panel: HTMLElement) {
  const outline = chartBox('chart-profile');
  const wear = chartBox('chart-wear');
  // The wear of one tooth, or a note where there is none.
  const wearBox = document.createElement('div');
  const draw = async (hours: number | undefined) => {
    const text = state.text;
    const r = await job('Profile', async (p) => {
      const nominal = await callJson(jobs, 'profile', [text, undefined, undefined, true, 60]);
      const modified = await callJson(jobs, 'profile', [text, undefined, undefined, false, 60]);
      const worn = hours ? await callJson(jobs, 'profile', [text, hours, undefined, false, 60], p) : null;
      return { nominal, modified, worn };
    });
    if (!r || text !== state.text) return;
    lineChart(outline, outlineSeries(r, hours), { x: 'x, mm', y: 'y, mm', equal: true, zoom: true, title: 'Disc profile (wheel or pinch to zoom, drag to pan)' });
    const flank = r.worn ? flankWearSeries(r.worn, hours) : null;
    if (flank) {
      wearBox.replaceChildren(wrap(wear));
      lineChart(wear, flank, { x: 'mesh angle, deg (0 root, 180 tip)', y: 'wear depth normal to the flank, um', title: 'Wear: deviation normal to the flank over one tooth' });
    } else {
      wearBox.replaceChildren(noteOf(hours ? `Unworn at ${hours} h: no wear to draw.` : 'Unworn: give the hours worn to draw the wear of a tooth.'));
    }
  };
  if (!profileHours) profileHours = String(lastStageHours(state.keys));
  const f = form([declaredField('profile', 'hours', { id: 'profile-hours', label: 'worn at', value: profileHours })], 'Draw', (v) => {
    profileHours = v['profile-hours'] === undefined ? '' : String(v['profile-hours']);
    draw(v['profile-hours']);
  });
  const reset = document.createElement('button');
  reset.textContent = 'Reset zoom';
  reset.onclick = () => chartOf(outline)?.resetZoom();
  panel.append(f, reset, wrap(outline, 'square'), wearBox);
  draw(profileHours === '' ? undefined : Number(profileHours));
}
