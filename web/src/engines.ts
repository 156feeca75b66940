// The page's two engines (rvlife.ts): config work (quick) and analyses (long, cancellable)
// run in separate workers, so that editing stays live while a study runs; the study's stages
// run on one analysis worker per core (up to four).
import { Engine, type Progress } from './rvlife';
import type { Args, JsonCommand, JsonOf } from './protocol';
import { workerCount } from './parallel';

export const quick = new Engine();
/** The analysis workers: one per core up to four, or the address's `workers=N` (1 to 16; to
 *  compare one worker with several). */
export const jobs = new Engine(workerCount(location.search, navigator.hardwareConcurrency || 1), true);

/** Runs the JSON command `cmd` on `engine` and parses its answer. */
export async function callJson<K extends JsonCommand>(engine: Engine, cmd: K, args: Args<K>, progress?: Progress): Promise<JsonOf<K>> {
  return JSON.parse(await engine.call(cmd, args, progress)) as JsonOf<K>;
}
