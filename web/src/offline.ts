// Offline from the first visit: the page and its worker each keep the same-origin resources
// they loaded (the page, its script and style; the worker's script and the WebAssembly module)
// in the service worker's cache, which answers from it when the network is gone (public/sw.js).
// On a first visit those resources were fetched before the service worker took control, so it
// could not keep them itself.

/** The service worker's cache (public/sw.js's `CACHE`). */
export const CACHE = 'rvlife-v1';

/** Adds `extra` and every same-origin resource this context has loaded to the cache;
 *  resolves when done (quietly where there is no Cache Storage, as on `file:`). */
export async function keepOffline(extra: string[] = []): Promise<void> {
  if (!('caches' in self)) return;
  const names = [...extra, ...performance.getEntriesByType('resource').map((e) => e.name)];
  const urls = new Set(names
    .map((u) => new URL(u, self.location.href))
    .filter((u) => u.origin === self.location.origin && !u.pathname.endsWith('/sw.js'))
    .map((u) => { u.hash = ''; return u.href; }));
  const cache = await caches.open(CACHE);
  await Promise.all([...urls].map((u) => cache.add(u).catch(() => undefined)));
}
