// Downloads: a file saved from text the page holds or fetches when its button is clicked
// (the results' files as the command line writes them).
import { showError } from './status';

/** The media type a file is saved with. */
export function typeOf(name: string): string {
  return name.endsWith('.json') ? 'application/json' : 'text/plain';
}

/** Saves `text` as the file `name` (a path's slashes become underscores). */
export function download(name: string, text: string, type = 'text/plain') {
  const a = document.createElement('a');
  a.href = URL.createObjectURL(new Blob([text], { type }));
  a.download = name.replace(/\//g, '_');
  document.body.append(a);
  a.click();
  a.remove();
  setTimeout(() => URL.revokeObjectURL(a.href), 10_000);
}

/** Each file's text, or a function that fetches it when its button is clicked. */
export type Files = Record<string, string | (() => Promise<string>)>;

/** Download buttons (`data-file` the name), with the size of each text held. */
export function downloadList(files: Files): HTMLElement {
  const ul = document.createElement('ul');
  ul.className = 'downloads';
  for (const [name, text] of Object.entries(files)) {
    const li = document.createElement('li');
    const b = document.createElement('button');
    b.textContent = name;
    b.dataset.file = name;
    b.onclick = async () => {
      try {
        const t = typeof text === 'string' ? text : await text();
        download(name, t, typeOf(name));
      } catch (e) { showError((e as Error).message); }
    };
    li.append(b);
    if (typeof text === 'string') li.append(` ${(text.length / 1024).toFixed(0)} kB`);
    ul.append(li);
  }
  return ul;
}
