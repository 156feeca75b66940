// rvlife's web page: the config editor, the analysis views and the downloads. Every number
// comes from rvlife's WebAssembly module in a Web Worker (rvlife.ts, worker.ts); the page only
// lays out, plots (Chart.js) and saves. This module wires the header's controls, loads the
// presets and the stage quantities, and opens the page on the accuracy-life study.
import './style.css';
import { download } from './downloads';
import { loadPreset, setText } from './editor';
import { callJson, quick } from './engines';
import { cancelJobs } from './job';
import { keepOffline } from './offline';
import { decodeConfig } from './share';
import { quantityDocs, renderTab, setRenderer, state } from './state';
import { showError, status } from './status';
import { buildTabs, drawTab } from './tabs';
import { $ } from './ui';

setRenderer(drawTab);

async function start() {
  buildTabs();
  const presets = await callJson(quick, 'presets', []);
  for (const q of await callJson(quick, 'quantities', [])) quantityDocs.set(q.name, q);
  const sel = $<HTMLSelectElement>('preset');
  for (const p of presets) {
    const o = document.createElement('option');
    o.value = p.name; o.textContent = p.name; o.title = p.summary;
    sel.append(o);
  }
  const custom = document.createElement('option');
  custom.value = ''; custom.textContent = '(imported or shared)';
  sel.append(custom);
  sel.onchange = () => { if (sel.value) loadPreset(sel.value); };
  $('cancel').onclick = () => cancelJobs();
  $('export').onclick = () => {
    const key = state.refused.first();
    if (key !== undefined) { status(`export refused: mend the value at ${key} first`); return; }
    download('rvlife.toml', state.text, 'application/toml');
  };
  $('import').onclick = () => $('import-file').click();
  $<HTMLInputElement>('import-file').onchange = async (ev) => {
    const input = ev.target as HTMLInputElement;
    const f = input.files?.[0];
    if (!f) return;
    sel.value = '';
    await setText(await f.text(), true);
    input.value = '';
  };
  $('share').onclick = async () => {
    await navigator.clipboard?.writeText(location.href).catch(() => undefined);
    status('link copied: it holds the whole config');
  };
  const shared = location.hash.startsWith('#config=') ? await decodeConfig(location.hash.slice(8)).catch(() => null) : null;
  if (shared) { sel.value = ''; await setText(shared, true); } else { sel.value = 'rv-40e'; await loadPreset('rv-40e'); }
  renderTab();
  document.body.dataset.ready = 'true';
  // The verdict and its limiting quantity as soon as the page opens (an edit or another run
  // replaces this study).
  if (state.tab === 'life' && state.valid) $('run-life').click();
}

if ('serviceWorker' in navigator && location.protocol !== 'file:') {
  navigator.serviceWorker.register('./sw.js').catch(() => undefined);
  // Once loaded, the page works offline (offline.ts): `data-offline="ready"` says so.
  navigator.serviceWorker.ready
    .then(() => Promise.all([keepOffline([location.href]), quick.call('keepOffline', [])]))
    .then(() => { document.body.dataset.offline = 'ready'; })
    .catch(() => undefined);
}

start().catch((e) => showError(String(e)));
