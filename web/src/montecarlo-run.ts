// Monte Carlo over the tolerances on every worker of an engine: the nominal reducer's wear
// history on the first worker (the module's `montecarloWear`), the samples in parts taken by
// whichever worker is free (`montecarloShard`), then the parts merged by the library's own
// merge (`montecarloMerge`, as `rvlife merge` does): the same bytes on one worker as on many.
// The history's early part, up to the last stage, is handed on while the points beyond it are
// integrated: the other workers analyse the samples' stages on it meanwhile, and a sample
// whose life lies beyond its stages waits in its worker for the whole history.
import { partsFor } from './parallel';
import type { Engine, Progress } from './rvlife';

/** The Monte Carlo run of `samples` reducers with `seed` of the config `text` on every worker
 *  of `engine`. Resolves to the module's `montecarlo` JSON; `progress` hears the wear
 *  integration's steps, then the samples analysed at their stages. */
export async function montecarlo(engine: Engine, text: string, samples: number, seed: number,
  progress: Progress): Promise<string> {
  const n = partsFor(samples, engine.size);
  let wearDone = 0;
  let wearTotal = 0;
  const done = new Array<number>(n).fill(0);
  const report = () => progress(wearDone + done.reduce((a, b) => a + b, 0), wearTotal + samples);
  // The history as far as it is known, and the workers waiting for more of it.
  let early: Uint8Array | undefined;
  let whole: Uint8Array | undefined;
  let failed = false;
  const sleepers: (() => void)[] = [];
  const wakeAll = () => sleepers.splice(0).forEach((wake) => wake());
  const more = () => new Promise<void>((wake) => sleepers.push(wake));
  const wear = engine.callOn(0, 'montecarloWear', [text, samples, seed],
    (d, t) => { wearDone = d; wearTotal = t; report(); },
    (bytes) => { early = bytes; wakeAll(); })
    .then((bytes) => { whole = bytes; }, (e: unknown) => { failed = true; throw e; })
    .finally(wakeAll);
  const parts = new Array<string>(n);
  let next = 0;
  const worker = async (k: number) => {
    // The parts whose samples wait in this worker for the whole history.
    const waiting: number[] = [];
    const run = async (i: number, history: Uint8Array) => {
      const r = await engine.callOn(k, 'montecarloShard', [text, samples, seed, history, i + 1, n],
        (d) => { done[i] = Math.max(done[i], d); report(); });
      if ((JSON.parse(r) as { waiting?: number }).waiting !== undefined) waiting.push(i);
      else parts[i] = r;
    };
    // The first worker integrates the wear before it takes a part; the others validate the
    // config meanwhile.
    if (k === 0) await wear.catch(() => undefined);
    else await engine.callOn(k, 'prepare', [text]);
    for (;;) {
      if (failed) return;
      if (whole) for (const i of waiting.splice(0)) await run(i, whole);
      const history = whole ?? early;
      if (!history) { await more(); continue; }
      const i = next++;
      if (i >= n) break;
      await run(i, history);
    }
    while (waiting.length > 0 && !failed) {
      if (!whole) { await more(); continue; }
      for (const i of waiting.splice(0)) await run(i, whole);
    }
  };
  await Promise.all([wear, ...Array.from({ length: Math.min(engine.size, n) }, (_, k) => worker(k))]);
  return engine.call('montecarloMerge', [text, parts]);
}
