// The page's views as tabs, and drawing the open one (none while the config is invalid).
import { destroyCharts } from './charts';
import { state, type TabId } from './state';
import { $ } from './ui';
import { renderContact } from './views/contact';
import { renderDynamics } from './views/dynamics';
import { renderHysteresis } from './views/hysteresis';
import { renderLife } from './views/life';
import { renderMonteCarlo } from './views/montecarlo';
import { renderOptimize } from './views/optimize';
import { renderProfile } from './views/profile';
import { renderTe } from './views/te';

const tabs: Record<TabId, { title: string; render: (panel: HTMLElement) => void }> = {
  // The answer first: the page opens on the accuracy life, its study already running.
  life: { title: 'Accuracy life', render: renderLife },
  profile: { title: 'Profile', render: renderProfile },
  contact: { title: 'Contact', render: renderContact },
  te: { title: 'Transmission error', render: renderTe },
  hysteresis: { title: 'Hysteresis', render: renderHysteresis },
  dynamics: { title: 'Dynamics', render: renderDynamics },
  montecarlo: { title: 'Monte Carlo', render: renderMonteCarlo },
  optimize: { title: 'Design search', render: renderOptimize },
};

/** A button a view, in the table's order. */
export function buildTabs() {
  const nav = $('tabs');
  for (const id of Object.keys(tabs) as TabId[]) {
    const b = document.createElement('button');
    b.textContent = tabs[id].title;
    b.dataset.tab = id;
    b.onclick = () => { state.tab = id; drawTab(); };
    nav.append(b);
  }
}

/** Draws the open view afresh (its charts of before destroyed). */
export function drawTab() {
  destroyCharts();
  document.querySelectorAll<HTMLElement>('#tabs button').forEach((b) => b.classList.toggle('active', b.dataset.tab === state.tab));
  const panel = $('panel');
  panel.replaceChildren();
  if (!state.valid) {
    const p = document.createElement('p');
    p.className = 'error';
    p.textContent = 'Fix the config (the message above names the key) to see this view.';
    panel.append(p);
    return;
  }
  tabs[state.tab].render(panel);
}
