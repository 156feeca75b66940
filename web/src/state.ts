// The page's state: the config text and its keys, the open view, the last results of the
// views that keep them, and the library's stage quantities. The views and the editor redraw
// the open view through `renderTab`, which main.ts points at the tab table (which imports
// them).
import { Refusals } from './keys';
import type { KeyDoc, MonteCarloView, OptimizeView, QuantityDoc, StudyOverview } from './types';

/** The views, by the id of their tab. */
export type TabId = 'life' | 'profile' | 'contact' | 'te' | 'hysteresis' | 'dynamics' | 'montecarlo' | 'optimize';

export const state = {
  text: '',
  valid: false,
  keys: [] as KeyDoc[],
  tab: 'life' as TabId,
  study: null as StudyOverview | null,
  /** The config the last study ran: the editor's text with the dynamics off and `[fem]`
   *  as chosen (`rvlife run` on it repeats the study). */
  studyConfig: '',
  montecarlo: null as MonteCarloView | null,
  optimize: null as OptimizeView | null,
  /** Keys whose typed value the config refused (the box keeps what the user wrote; the
   *  config keeps its last value, so nothing runs or exports until it is mended). */
  refused: new Refusals(),
};

/** The library's stage quantities by name, loaded when the page starts. */
export const quantityDocs = new Map<string, QuantityDoc>();

let redraw: () => void = () => undefined;

/** Sets what `renderTab` does (main.ts: the tab table's renderer). */
export function setRenderer(render: () => void): void {
  redraw = render;
}

/** Redraws the open view from the state. */
export function renderTab(): void {
  redraw();
}
