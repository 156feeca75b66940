// The messages between the page and its Web Workers (rvlife.ts posts, worker.ts answers):
// every command by name with its arguments, what it answers with and, for the commands that
// answer with JSON text, what that text parses to. A new command is an entry here and its
// function in worker.ts's table.
import type {
  ContactResult, DynamicsView, HysteresisView, Inspection, MonteCarloView, OptimizeView,
  Preset, ProfilePoints, QuantityDoc, StudyOverview, StudyPlan, TeView,
} from './types';
import type { PageCommand } from './generated/commands';

/** Each command: `args` as the page passes them, `result` as the worker answers (text, bytes
 *  or a flag), `json` the value of a JSON answer, `item` each piece it hands on before it
 *  ends. */
export interface Commands {
  warm: { args: []; result: string };
  keepOffline: { args: []; result: string };
  presets: { args: []; result: string; json: Preset[] };
  quantities: { args: []; result: string; json: QuantityDoc[] };
  /** The TOML text of a built-in reducer. */
  presetText: { args: [name: string]; result: string };
  inspect: { args: [text: string]; result: string; json: Inspection };
  /** The text with a key set to a JSON value (null removes it). */
  setKey: { args: [text: string, key: string, valueJson: string]; result: string };
  profile: {
    args: [text: string, hours: number | undefined, wearUm: number | undefined, nominal: boolean, perTooth: number];
    result: string; json: ProfilePoints;
  };
  contact: {
    args: [text: string, crankDeg: number, torqueNm: number, hours: number | undefined];
    result: string; json: ContactResult;
  };
  te: { args: [text: string, hours: number | undefined, torqueNm: number | undefined]; result: string; json: TeView };
  hysteresis: {
    args: [text: string, crankDeg: number, levels: number, hours: number | undefined];
    result: string; json: HysteresisView;
  };
  dynamics: {
    args: [text: string, hours: number | undefined, torqueNm: number | undefined, disc: string];
    result: string; json: DynamicsView;
  };
  study: { args: [text: string]; result: string; json: StudyOverview };
  studyPlan: { args: [text: string]; result: StudyPlan };
  /** Hands on each stage's bytes as the wear integration passes it. */
  studyWear: { args: [text: string, ground: Uint8Array]; result: string; item: Uint8Array };
  studyStage: { args: [text: string, ground: Uint8Array, stage: Uint8Array]; result: Uint8Array };
  studyOffer: { args: [outcomes: Uint8Array[]]; result: boolean };
  /** Hands on each step of the accuracy life's search beyond the last stage, as a line of
   *  text (each a wear integration: it can take as long as the study). */
  studyAssemble: { args: [outcomes: Uint8Array[]]; result: string; json: StudyOverview; item: string };
  /** The flexible disc's analysis of every stage of the last study (`[fem]`), then its
   *  overview with the `flexible_*` quantities. */
  studyFlexible: { args: []; result: string; json: StudyOverview };
  /** A data file of the last study's results, as text. */
  studyFile: { args: [name: string]; result: string };
  montecarlo: { args: [text: string, samples: number, seed: number]; result: string; json: MonteCarloView };
  /** Validates a config and keeps its model in that worker for the parts that follow. */
  prepare: { args: [text: string]; result: string };
  /** The nominal reducer's wear history of a Monte Carlo run, as bytes for its parts; hands
   *  on its early part (up to the last stage) first when points beyond it follow. */
  montecarloWear: { args: [text: string, samples: number, seed: number]; result: Uint8Array; item: Uint8Array };
  /** Part `index` of `count` (1-based) of a Monte Carlo run on the wear history's bytes (its
   *  early part or the whole): its meta-data and tables as JSON text, for the merge, or
   *  `{"waiting": N}` when samples wait in that worker for the whole history (the same call
   *  there with it finishes the part). */
  montecarloShard: {
    args: [text: string, samples: number, seed: number, wear: Uint8Array, index: number, count: number];
    result: string;
  };
  /** The parts merged by the library's merge: the same JSON as `montecarlo`. */
  montecarloMerge: { args: [text: string, shards: string[]]; result: string; json: MonteCarloView };
  optimize: {
    args: [text: string, vary: string, objective: string, constraints: string, evaluations: number, seed: number];
    result: string; json: OptimizeView;
  };
}

export type Command = keyof Commands;
export type Args<K extends Command> = Commands[K]['args'];
export type Result<K extends Command> = Commands[K]['result'];

/** What command `K` hands on before it ends (never for most). */
export type Item<K extends Command> = Commands[K] extends { item: infer I } ? I : never;

/** The commands that answer with JSON text. */
export type JsonCommand = { [K in Command]: Commands[K] extends { json: unknown } ? K : never }[Command];

/** What a JSON command's answer parses to. */
export type JsonOf<K extends JsonCommand> = Commands[K] extends { json: infer J } ? J : never;

/** The page to a worker: run `cmd` with `args`; `id` names the call in the answers (0: an
 *  answer nobody waits for). */
export type Request = { [K in Command]: { id: number; cmd: K; args: Args<K> } }[Command];

/** A worker to the page, about call `id`: its progress, a piece handed on, its result, or the
 *  message it failed with. */
export type Reply =
  | { id: number; kind: 'progress'; done: number; total: number }
  | { id: number; kind: 'item'; value: unknown }
  | { id: number; kind: 'result'; value: unknown }
  | { id: number; kind: 'error'; message: string };

/** The commands the library declares for the page that the table above lacks: none, or the
 *  type check fails here, naming them (`PageCommand`, generated from `rvlife::api::commands`). */
type Undeclared = Exclude<PageCommand, Command>;
export const EVERY_DECLARED_COMMAND: [Undeclared] extends [never] ? true : Undeclared = true;
