// The Web Worker that runs rvlife's WebAssembly module: the page never blocks on an analysis.
// Protocol: the page posts {id, cmd, args}; the worker answers {id, kind: 'progress', done,
// total} while the command runs (and {id, kind: 'item', value} for each piece a command hands
// on before it ends: the stages of a study's wear), then {id, kind: 'result', value} or {id,
// kind: 'error', message}. Cancelling a command terminates the worker (see rvlife.ts).
import init, * as rv from './pkg/rvlife_wasm.js';
import { keepOffline } from './offline';
import type { Args, Command, Request, Result } from './protocol';
import type { StudyPlan } from './types';

const ready = init();

// The last study's results, kept here for the page's downloads, and the wear integration of
// a study run in parts (rvlife.ts, `study`) until it is assembled.
let lastStudy: rv.StudyResults | null = null;
let lastWear: rv.StudyWear | null = null;

// Commands callable from the page, each given the progress callback first (with `item`, which
// hands a piece on); every one returns text (JSON or TOML), but the parts of a study, which
// return their bytes (a promise of it where the command waits, as keepOffline does).
type Progress = ((done: number, total: number) => void) & { item: (value: unknown) => void };
/** A command's function: its progress callback, then the page's arguments. */
type Run<K extends Command> = (p: Progress, ...a: Args<K>) => Result<K> | Promise<Result<K>>;
const commands: { [K in Command]: Run<K> } = {
  warm: () => { rv.warm(); return ''; },
  keepOffline: async () => { await keepOffline([self.location.href]); return ''; },
  presets: () => rv.presets(),
  quantities: () => rv.quantities(),
  presetText: (_p, name: string) => rv.presetText(name),
  inspect: (_p, text: string) => rv.inspect(text),
  setKey: (_p, text: string, key: string, value: string) => rv.setKey(text, key, value),
  profile: (p, text: string, hours: number | undefined, wearUm: number | undefined, nominal: boolean,
    perTooth: number) => rv.profile(text, hours, wearUm, nominal, perTooth, p),
  contact: (p, text: string, crankDeg: number, torqueNm: number, hours: number | undefined) =>
    rv.contact(text, crankDeg, torqueNm, hours, undefined, p),
  te: (p, text: string, hours: number | undefined, torqueNm: number | undefined) =>
    rv.te(text, hours, undefined, torqueNm, p),
  hysteresis: (p, text: string, crankDeg: number, levels: number, hours: number | undefined) =>
    rv.hysteresis(text, crankDeg, levels, hours, undefined, p),
  dynamics: (p, text: string, hours: number | undefined, torqueNm: number | undefined, disc: string) =>
    rv.dynamics(text, hours, undefined, torqueNm, disc, p),
  study: (p, text: string) => {
    lastStudy?.free();
    lastStudy = null;
    lastStudy = rv.study(text, p);
    return lastStudy.overview();
  },
  // The module declares a plain object: its keys are those of `StudyPlan`.
  studyPlan: (_p, text: string) => rv.studyPlan(text) as StudyPlan,
  studyWear: (p, text: string, ground: Uint8Array) => {
    lastWear?.free();
    lastWear = null;
    lastWear = rv.studyWear(text, ground, p, p.item);
    return '';
  },
  studyStage: (_p, text: string, ground: Uint8Array, stage: Uint8Array) => rv.studyStage(text, ground, stage),
  studyOffer: (_p, outcomes: Uint8Array[]) => (lastWear ? lastWear.offer(outcomes) : true),
  studyAssemble: (p, outcomes: Uint8Array[]) => {
    if (!lastWear) throw new Error('the study\'s wear integration is gone (an analysis was cancelled since): run the study again');
    lastStudy?.free();
    lastStudy = null;
    lastStudy = lastWear.assemble(outcomes, p.item);
    lastWear.free();
    lastWear = null;
    return lastStudy.overview();
  },
  studyFlexible: (p) => {
    if (!lastStudy) throw new Error('the study results are gone (an analysis was cancelled since): run the study again');
    return lastStudy.flexible(p);
  },
  studyFile: (_p, name: string) => {
    if (!lastStudy) throw new Error('the study results are gone (an analysis was cancelled since): run the study again');
    return lastStudy.file(name);
  },
  montecarlo: (p, text: string, samples: number, seed: number) =>
    rv.montecarlo(text, samples, BigInt(seed), p),
  prepare: (_p, text: string) => { rv.prepare(text); return ''; },
  montecarloWear: (p, text: string, samples: number, seed: number) =>
    rv.montecarloWear(text, samples, BigInt(seed), p, p.item),
  montecarloShard: (p, text: string, samples: number, seed: number, wear: Uint8Array, index: number,
    count: number) => rv.montecarloShard(text, samples, BigInt(seed), wear, index, count, p),
  montecarloMerge: (_p, text: string, shards: string[]) => rv.montecarloMerge(text, shards),
  optimize: (p, text: string, vary: string, objective: string, constraints: string, evaluations: number,
    seed: number) => rv.optimize(text, vary, objective, constraints, evaluations, BigInt(seed), p),
};

/** Runs the command `r` names on its arguments (generic, so that the name and the arguments'
 *  types go together). */
function run<K extends Command>(r: { cmd: K; args: Args<K> }, p: Progress): Result<K> | Promise<Result<K>> {
  const f: Run<K> = commands[r.cmd];
  return f(p, ...r.args);
}

self.onmessage = async (ev: MessageEvent<Request>) => {
  const { id, cmd } = ev.data;
  try {
    await ready;
    if (!Object.hasOwn(commands, cmd)) throw new Error(`unknown command ${cmd}`);
    let last = 0;
    const post = (m: object) => (self as unknown as Worker).postMessage({ id, ...m });
    const progress = Object.assign((done: number, total: number) => {
      const now = performance.now();
      if (now - last > 50 || done === total) {
        last = now;
        post({ kind: 'progress', done, total });
      }
    }, { item: (value: unknown) => post({ kind: 'item', value }) });
    const value = await run(ev.data, progress);
    (self as unknown as Worker).postMessage({ id, kind: 'result', value });
  } catch (e) {
    const message = e instanceof Error ? e.message : String(e);
    (self as unknown as Worker).postMessage({ id, kind: 'error', message });
  }
};
