// How the page spreads work over its analysis workers (pure, so the unit tests reach it).

/** The analysis workers for the address's query `search` on a machine of `cores` cores: one
 *  per core up to four, or the query's `workers=N` (1 to 16; to compare one worker with
 *  several). */
export function workerCount(search: string, cores: number): number {
  const asked = Number(new URLSearchParams(search).get('workers') ?? NaN);
  if (Number.isInteger(asked) && asked >= 1 && asked <= 16) return asked;
  return Math.max(1, Math.min(cores, 4));
}

/** The number of parts a Monte Carlo run of `samples` is cut into for `workers` workers: one
 *  sample a part up to eight parts a worker (each part starts by rebuilding the wear maps,
 *  small beside a sample; samples differ in cost, so small parts keep the workers evenly
 *  busy). */
export function partsFor(samples: number, workers: number): number {
  return Math.max(1, Math.min(samples, 8 * Math.max(1, workers)));
}
