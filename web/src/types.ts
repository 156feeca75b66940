// The shapes of the JSON the WebAssembly module's commands answer with (the page parses the
// text): generated from the library's result types and the module's (generated/results.ts,
// written by crates/rvlife-wasm/src/typescript.rs with ts-rs; the Rust test
// `generated_typescript_is_current` fails when a result type changes until it is written
// again). Keys and units are the command line's: `rvlife <command> --json`, the results files
// of `rvlife run`, `rvlife montecarlo` and `rvlife optimize`. Only the page's own types are
// written here.

export type * from './generated/results';

/** The plan of a study in parts (`studyPlan`): bytes every part needs, the unworn first
 *  stage's bytes when the first stage lies at 0 h, the wear integration's progress steps and
 *  the number of stages. */
export interface StudyPlan {
  ground: Uint8Array;
  first?: Uint8Array;
  wearSteps: number;
  stages: number;
}

