// The page's handle on rvlife: each call runs in a Web Worker (one of the engine's, each with
// its own WebAssembly module) and returns a promise; a long command can be cancelled (the
// workers running it are terminated and fresh ones started). The accuracy-life study runs in
// parts on all of an engine's workers (`study`).
import type { Args, Command, Item, Reply, Result } from './protocol';

export type Progress = (done: number, total: number) => void;

type Pending = {
  resolve: (v: unknown) => void; reject: (e: Error) => void; progress?: Progress; item?: (v: unknown) => void;
  worker: number;
};

export class Cancelled extends Error {
  constructor() { super('cancelled'); }
}

export class Engine {
  private workers: Worker[];
  private next = 1;
  private pending = new Map<number, Pending>();

  /** `size` workers (at least one): the first takes `call`, every one `callOn`. With `warm`
   *  and more than one worker, the last runs the module's `warm` when it starts: the engine
   *  compiles and optimises the solvers' code, which the page's workers share, before the
   *  first analysis (on the last worker, so that the first stays free for the page's views). */
  constructor(readonly size = 1, warm = false) {
    this.workers = Array.from({ length: Math.max(1, size) }, () => this.spawn());
    // Its answer (id 0) is nobody's call.
    if (warm && this.workers.length > 1) this.workers[this.workers.length - 1].postMessage({ id: 0, cmd: 'warm', args: [] });
  }

  private spawn(): Worker {
    const w = new Worker(new URL('./worker.ts', import.meta.url), { type: 'module' });
    w.onmessage = (ev) => {
      const m = ev.data as Reply;
      const p = this.pending.get(m.id);
      if (!p) return;
      if (m.kind === 'progress') { p.progress?.(m.done, m.total); return; }
      if (m.kind === 'item') { p.item?.(m.value); return; }
      this.pending.delete(m.id);
      if (m.kind === 'result') p.resolve(m.value); else p.reject(new Error(m.message));
    };
    return w;
  }

  /** Runs `cmd` with `args` in the first worker; `progress` hears (done, total). */
  call<K extends Command>(cmd: K, args: Args<K>, progress?: Progress): Promise<Result<K>> {
    return this.callOn(0, cmd, args, progress);
  }

  /** Runs `cmd` with `args` in worker `k` (0 <= k < size); `item` hears each piece the
   *  command hands on before it ends. */
  callOn<K extends Command>(k: number, cmd: K, args: Args<K>, progress?: Progress,
    item?: (v: Item<K>) => void): Promise<Result<K>> {
    const id = this.next++;
    return new Promise<Result<K>>((resolve, reject) => {
      // The worker answers call `id` with what `cmd` answers and hands on.
      this.pending.set(id, {
        resolve: (v) => resolve(v as Result<K>), reject, progress,
        item: item && ((v) => item(v as Item<K>)), worker: k,
      });
      this.workers[k].postMessage({ id, cmd, args });
    });
  }

  /** Stops whatever runs: every pending call rejects with `Cancelled`; the workers that had
   *  one are terminated and fresh ones started (the others keep their state). Returns the
   *  restarted workers' indices (what they kept, such as a study's results, is gone). */
  cancel(): number[] {
    const busy = new Set([...this.pending.values()].map((p) => p.worker));
    for (const k of busy) {
      this.workers[k].terminate();
      this.workers[k] = this.spawn();
    }
    for (const p of this.pending.values()) p.reject(new Cancelled());
    this.pending.clear();
    return [...busy];
  }

  get busy() { return this.pending.size > 0; }
}

/** The accuracy-life study of `text` (`rvlife run` without dynamics and FE) on every worker of
 *  `engine`: the wear integration on the first, the unworn first stage beside it on a second;
 *  each stage, as soon as the integration hands it on, on whichever worker is free (in the
 *  order handed on while the wear goes on, then the most worn waiting first); the accuracy
 *  life's trials between two stages on the first once the stages show where they go; the study
 *  assembled on the first, which keeps its results
 *  (`studyFile`). Resolves to the results' overview JSON (the module's
 *  `StudyResults.overview`); `progress` hears the wear-rate evaluations and the stages done,
 *  `notice` each step of the accuracy life's search beyond the last stage (the library's
 *  line, as `rvlife run` prints it). With `flexible`, then the flexible disc's analysis of
 *  every stage on the first worker (`rvlife run` with `[fem] enabled`; `text` must enable
 *  it, so that its `[fem]` is validated). */
export async function study(engine: Engine, text: string, progress: Progress,
  notice: (text: string) => void = () => undefined, flexible = false): Promise<string> {
  const plan = await engine.call('studyPlan', [text]);
  const total = plan.wearSteps + plan.stages;
  let wearDone = 0;
  const outcomes: Uint8Array[] = [];
  const report = () => progress(Math.min(wearDone, plan.wearSteps) + outcomes.length, total);
  const analyse = async (k: number, stage: Uint8Array) => {
    outcomes.push(await engine.callOn(k, 'studyStage', [text, plan.ground, stage]));
    report();
  };
  const apart = plan.first !== undefined && engine.size > 1;
  const aside = apart ? analyse(1, plan.first!) : Promise.resolve();
  // The stages handed on and not yet taken, and the workers waiting for one.
  const queue: Uint8Array[] = [];
  const idle: (() => void)[] = [];
  let handed = 0;
  let integrated = false;
  const wear = engine.callOn(0, 'studyWear', [text, plan.ground],
    (d) => { wearDone = d; report(); },
    (stage: Uint8Array) => {
      if (handed++ === 0 && apart) return;
      queue.push(stage);
      idle.shift()?.();
    }).finally(() => { integrated = true; idle.splice(0).forEach((wake) => wake()); });
  // The accuracy life's trials between two stages, made on the first worker (which holds the
  // wear) as soon as the stages up to the first outside the spec are in, while the others go
  // on; offered again before each of its stages until settled.
  let settled = false;
  const worker = async (k: number) => {
    if (k === 0) await wear;
    if (k === 1) await aside;
    for (;;) {
      if (k === 0 && !settled) settled = await engine.callOn(0, 'studyOffer', [outcomes]);
      // In the order handed on while the wear goes on (the early stages settle the accuracy
      // life's crossing), the most worn first once it has ended (they take longest).
      const s = integrated ? queue.pop() : queue.shift();
      if (s) await analyse(k, s);
      else if (integrated) return;
      else await new Promise<void>((wake) => idle.push(wake));
    }
  };
  await Promise.all([wear, ...Array.from({ length: engine.size }, (_, k) => worker(k))]);
  const overview = await engine.callOn(0, 'studyAssemble', [outcomes], undefined, notice);
  if (!flexible) return overview;
  // The flexible disc on the worker that keeps the results: the FE disc, then each stage.
  return engine.callOn(0, 'studyFlexible', [], (d, t) => progress(total + d, total + t));
}
