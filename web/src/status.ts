// The page's status line and its error box (the command line's message for a bad config, or
// an analysis' failure).
import { $ } from './ui';

export function status(text: string) { $('status').textContent = text; }

/** Shows `message` in the error box, or hides it (null). */
export function showError(message: string | null) {
  const box = $('config-error');
  box.hidden = !message;
  box.textContent = message ?? '';
}
