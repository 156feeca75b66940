// The Web Worker that runs rvlife's WebAssembly module: the page never blocks on an analysis.
// Protocol: the page posts {id, cmd, args}; the worker answers {id, kind: 'progress', done,
// total} while the command runs, then {id, kind: 'result', value} or {id, kind: 'error',
// message}. Cancelling a command terminates the worker (see rvlife.ts).
import init, * as rv from './pkg/rvlife_wasm.js';

type Call = { id: number; cmd: string; args: unknown[] };

const ready = init();

// The last study's results, kept here for the page's downloads.
let lastStudy: rv.StudyResults | null = null;

// Commands callable from the page; every one returns text (JSON or TOML) or null.
const commands: Record<string, (...a: any[]) => string | null | undefined> = {
  presets: () => rv.presets(),
  presetText: (name: string) => rv.presetText(name),
  keys: (text: string) => rv.keys(text),
  check: (text: string) => rv.check(text) ?? null,
  setKey: (text: string, key: string, value: string) => rv.setKey(text, key, value),
  configJson: (text: string) => rv.configJson(text),
  profile: (text: string, hours: number | undefined, wearUm: number | undefined, nominal: boolean,
    perTooth: number, p: Function) => rv.profile(text, hours, wearUm, nominal, perTooth, p),
  profileFile: (text: string, hours: number | undefined, format: string, p: Function) =>
    rv.profileFile(text, hours, format, p),
  contact: (text: string, crankDeg: number, torqueNm: number, hours: number | undefined, p: Function) =>
    rv.contact(text, crankDeg, torqueNm, hours, undefined, p),
  te: (text: string, hours: number | undefined, torqueNm: number | undefined, p: Function) =>
    rv.te(text, hours, undefined, torqueNm, p),
  hysteresis: (text: string, crankDeg: number, levels: number, hours: number | undefined, p: Function) =>
    rv.hysteresis(text, crankDeg, levels, hours, undefined, p),
  dynamics: (text: string, hours: number | undefined, torqueNm: number | undefined, p: Function) =>
    rv.dynamics(text, hours, undefined, torqueNm, p),
  study: (text: string, p: Function) => {
    lastStudy?.free();
    lastStudy = null;
    lastStudy = rv.study(text, p);
    return lastStudy.overview();
  },
  studyFile: (name: string) => {
    if (!lastStudy) throw new Error('the study results are gone (an analysis was cancelled since): run the study again');
    return lastStudy.file(name);
  },
  montecarlo: (text: string, samples: number, seed: number, p: Function) =>
    rv.montecarlo(text, samples, BigInt(seed), p),
};

// Commands whose last argument is the progress callback.
const withProgress = new Set(['profile', 'profileFile', 'contact', 'te', 'hysteresis', 'dynamics', 'study', 'montecarlo']);

self.onmessage = async (ev: MessageEvent<Call>) => {
  const { id, cmd, args } = ev.data;
  try {
    await ready;
    const f = commands[cmd];
    if (!f) throw new Error(`unknown command ${cmd}`);
    let last = 0;
    const progress = (done: number, total: number) => {
      const now = performance.now();
      if (now - last > 50 || done === total) {
        last = now;
        (self as unknown as Worker).postMessage({ id, kind: 'progress', done, total });
      }
    };
    const value = f(...(withProgress.has(cmd) ? [...args, progress] : args));
    (self as unknown as Worker).postMessage({ id, kind: 'result', value: value ?? null });
  } catch (e) {
    const message = e instanceof Error ? e.message : String(e);
    (self as unknown as Worker).postMessage({ id, kind: 'error', message });
  }
};
