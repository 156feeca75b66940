// The shapes of the JSON the WebAssembly module's commands answer with (the page parses the
// text). Keys and units are the command line's: `rvlife <command> --json`, the results files
// of `rvlife run`, `rvlife montecarlo` and `rvlife optimize`. Only what the module writes is
// declared; a key the module leaves out when it has no value is optional here.

/** One key of the config as the editor shows it (the module's `inspect`). */
export interface KeyDoc {
  /** Its section (`cycloid.modification`), empty at the top level. */
  section: string;
  /** The dotted key (`cycloid.modification.offset_mm`). */
  key: string;
  /** Its value in the text: a number, a boolean, a string, a list, or null if unset. */
  value: unknown;
  /** The value of its commented-out example line, as written, if there is one. */
  commented: string | null;
  comment: string;
  unit: string;
  /** The allowed range the validation recorded (`0 < value <= 20`), if it reached the key. */
  allowed: string | null;
}

/** `inspect`: the command line's message for the text (null if valid) and its keys (null if
 *  the text does not parse). */
export interface Inspection {
  message: string | null;
  keys: KeyDoc[] | null;
}

/** A built-in reducer (`rvlife example --list`). */
export interface Preset {
  name: string;
  summary: string;
}

/** A stage quantity as the library declares it (`quantities`). */
export interface QuantityDoc {
  /** Its name with its unit (`lost_motion_arcmin`): the key of `summary.json`. */
  name: string;
  /** Its unit (`arcmin`; empty for a pure number). */
  unit: string;
  /** A short label (`lost motion`). */
  label: string;
  description: string;
  /** The models that produce it: `static`, `dynamics`, `flexible` or `lubrication`. */
  models: string;
  /** Its columns in `stages.csv`. */
  columns: string[];
}

/** `profile`: a disc profile's points, one list per column, each teeth x points_per_tooth
 *  long (mm, deg, um). */
export interface ProfilePoints {
  points_per_tooth: number;
  max_wear_um: number;
  x_mm: number[];
  y_mm: number[];
  /** Mesh angle, deg (0 root, 180 tip). */
  mesh_angle_deg: number[];
  wear_um: number[];
}

/** One pin of a disc in `contact`. */
export interface ContactPin {
  pin: number;
  mesh_angle_deg: number;
  /** Gap at the solved pose, um (negative: the contact's approach). */
  gap_um: number;
  force_n: number;
  lever_arm_mm: number;
  half_width_um: number;
  max_pressure_mpa: number;
}

/** One disc in `contact`. */
export interface ContactDisc {
  /** Translation of the disc centre, um (x, y). */
  translation_um: [number, number];
  rotation_arcmin: number;
  pin_moment_nm: number;
  max_force_n: number;
  pins_in_contact: number;
  /** Every pin's force, N, in pin order. */
  pin_forces_n: number[];
  pins: ContactPin[];
}

/** `contact` (`rvlife contact --json`): the static equilibrium at one crank angle under an
 *  output torque, input locked. */
export interface ContactResult {
  crank_deg: number;
  torque_nm: number;
  /** How the discs are held: `bearings` or `rigid`. */
  support: string;
  /** Carrier twist beyond nominal, arcmin (the loaded TE). */
  twist_arcmin: number;
  first_contact_arcmin: number;
  max_force_n: number;
  pins_in_contact: number;
  max_pressure_mpa: number;
  torsional_stiffness_nm_per_arcmin: number;
  residual: number;
  residual_roundoff_floor: number;
  max_wear_um: number;
  /** Two with bearings, one with rigid support. */
  discs: ContactDisc[];
}

/** `te` (`rvlife te --json`): the static transmission error over the output revolution, the
 *  catalogue quantities and, with a torque, the loaded TE (its keys present only then). */
export interface TeResult {
  max_wear_um: number;
  angular_te_arcmin: number;
  support: string;
  te_mean_arcmin: number;
  te_peak_to_peak_arcmin: number;
  te_reverse_mean_arcmin: number;
  backlash_arcmin: number;
  backlash_max_arcmin: number;
  lost_motion_arcmin: number;
  measuring_torque_nm: number;
  torsional_stiffness_nm_per_arcmin: number;
  /** Crank angles per mesh cycle: the curves hold this many points a mesh cycle. */
  samples_per_mesh_cycle: number;
  /** Input angle over the output revolution, deg. */
  input_deg: number[];
  /** Forward static TE over the output revolution, arcmin. */
  te_arcmin: number[];
  /** The loaded TE's output torque, N m. */
  torque_nm?: number;
  loaded_te_mean_arcmin?: number;
  loaded_te_peak_to_peak_arcmin?: number;
  max_force_n?: number;
  pins_in_contact?: number;
  /** Loaded TE over the output revolution, arcmin. */
  loaded_te_arcmin?: number[];
}

/** A hysteresis curve (output torque 0 -> +rated -> -rated -> +rated, input locked) and its
 *  catalogue quantities. */
export interface TwistCurve {
  torque_nm: number[];
  twist_arcmin: number[];
  backlash_arcmin: number;
  lost_motion_arcmin: number;
  hysteresis_loss_arcmin: number;
  torsional_stiffness_nm_per_arcmin: number;
}

/** One part's share of the elastic twist. */
export interface TwistShare {
  part: string;
  /** 0..1. */
  share: number;
  twist_arcmin: number;
}

/** `hysteresis` (`rvlife hysteresis --json`): the curve averaged over a mesh cycle (also at
 *  the top level) and at one crank angle. */
export interface HysteresisResult extends TwistCurve {
  max_wear_um: number;
  support: string;
  rated_torque_nm: number;
  measuring_torque_fraction: number;
  torsional_stiffness_definition: string;
  crank_deg: number;
  at_crank_angle: TwistCurve;
  samples_per_mesh_cycle: number;
  mesh_cycle_mean: TwistCurve;
  twist_shares: TwistShare[];
  /** The module's only (not the command line's): where the mean curve's lost motion and
   *  torsional stiffness are read. */
  catalogue_points: CataloguePoints;
}

/** The points of the mean hysteresis curve the catalogue quantities are read between, each
 *  [torque N m, twist arcmin], from the library (docs/model.md section 6.3). */
export interface CataloguePoints {
  /** The curve's midpoints at -T_m and +T_m (the measuring torque): their twists differ by
   *  the lost motion. */
  lost_motion: [[number, number], [number, number]];
  /** The secant b/a from the loading branch at +T_m to the rated torque: torque over twist
   *  between them is the torsional stiffness. */
  torsional_stiffness: [[number, number], [number, number]];
}

/** The command line's summary of a multibody simulation (`rvlife dynamics --json`). */
export interface DynamicsSummary {
  max_wear_um: number;
  window_start_s: number;
  window_end_s: number;
  te_mean_arcmin: number;
  te_peak_to_peak_arcmin: number;
  te_rms_arcmin: number;
  te_min_arcmin: number;
  te_max_arcmin: number;
  output_speed_deg_s: number;
  nominal_output_speed_deg_s: number;
  max_pin_force_n: number;
  steps: number;
  rhs_evaluations: number;
  jacobian_columns: number;
  /** Elastic modes per disc (0: rigid discs). */
  disc_modes: number;
  disc_mode_frequencies_hz: number[];
  integrator: string;
  integrator_fallback?: string;
}

/** `dynamics`: the summary and the time series at the output interval. */
export interface DynamicsResult {
  summary: DynamicsSummary;
  time_s: number[];
  /** Dynamic transmission error, arcmin. */
  te_arcmin: number[];
  output_speed_deg_s: number[];
}

/** A stage of `summary.json`: every stage quantity by its name (`quantities`), the values a
 *  model did not produce left out. */
export interface StageSummary {
  readonly [quantity: string]: number | undefined;
  hours: number;
  max_wear_um: number;
  lost_motion_arcmin: number;
  backlash_arcmin: number;
  angular_te_arcmin: number;
  torsional_stiffness_nm_per_arcmin: number;
}

/** The accuracy life against `[life]`. */
export interface AccuracyLife {
  /** Working hours at which the first threshold is crossed, h; absent when none is within
   *  the horizon. */
  accuracy_life_h?: number;
  /** The `[life]` key of the threshold crossed first. */
  limited_by?: string;
  /** The last working hours studied, h. */
  horizon_h: number;
}

/** `summary.json` of `rvlife run`, as far as the page reads it. */
export interface StudySummary {
  rvlife_version: string;
  ratio: number;
  rated_torque_nm: number;
  stages: StageSummary[];
  /** Present when `[life]` sets thresholds. */
  accuracy_life?: AccuracyLife;
}

/** `study` and `studyAssemble`: the study's overview. */
export interface StudyOverview {
  summary: StudySummary;
  /** The one-line verdict against `[life]`. */
  verdict: string;
  /** The names of the results' data files, in order (`summary.json`, `stages.csv`, ...,
   *  `profiles/worn_<H>h.dxf`). */
  files: string[];
}

/** The plan of a study in parts (`studyPlan`): bytes every part needs, the unworn first
 *  stage's bytes when the first stage lies at 0 h, the wear integration's progress steps and
 *  the number of stages. */
export interface StudyPlan {
  ground: Uint8Array;
  first?: Uint8Array;
  wearSteps: number;
  stages: number;
}

/** The Monte Carlo accuracy-life distribution over the samples analysed. */
export interface LifeDistribution {
  /** Samples counted. */
  n: number;
  /** Fraction whose life exceeds the horizon. */
  censored_fraction: number;
  /** Each key absent when too few lives fall within the horizon. */
  b10_h?: number;
  b50_h?: number;
  p5_h?: number;
  p95_h?: number;
  /** How many samples each threshold limited, by `[life]` key. */
  limited_by: Record<string, number>;
}

/** Percentiles of one stage quantity at one stage over the samples that reached it. */
export interface Percentiles {
  hours: number;
  /** The quantity's column name in `stages.csv`. */
  quantity: string;
  n: number;
  p5: number;
  p50: number;
  p95: number;
  mean: number;
}

/** One Monte Carlo sample. */
export interface SampleRecord {
  sample: number;
  /** `ok`, or `failed: <reason>`. */
  status: string;
  accuracy_life_h: number | null;
  limited_by: string | null;
}

/** `montecarlo` (`rvlife montecarlo`): its tables as text, the life distribution, every
 *  sample, the report's verdict and the reliability curve. */
export interface MonteCarloResult {
  samples_csv: string;
  stages_csv: string;
  life: LifeDistribution;
  percentiles: Percentiles[];
  records: SampleRecord[];
  /** Beyond it a life is censored, h. */
  horizon_h: number;
  verdict: string;
  /** [working hours, fraction within spec], a step curve from (0, 1). */
  reliability: [number, number][];
}

/** A candidate of the design search. */
export interface Candidate {
  candidate: number;
  /** The search phase that proposed it (`start`, `sample`, `simplex`, `generation 3`). */
  phase: string;
  status: string;
  feasible: boolean;
  /** The varied keys' values, by key. */
  values: Record<string, number>;
  /** Each goal's value by name (null: beyond the horizon). */
  goals: Record<string, number | null>;
  scores: Record<string, number | null>;
  /** Each constraint's value by its text. */
  constraints: Record<string, number | null>;
  limited_by: string | null;
}

/** A curve of one of the design search's plots. */
export interface SearchCurve {
  name: string;
  points: [number, number][];
  /** Joined by a line; false: markers alone. */
  joined: boolean;
}

/** One plot of the design search's report. */
export interface SearchPlot {
  /** File stem in the report (`convergence`, `pareto`, `accuracy`, `sensitivity`). */
  stem: string;
  title: string;
  x_label: string;
  y_label: string;
  against_hours: boolean;
  caption: string;
  curves: SearchCurve[];
}

/** `optimize` (`rvlife optimize`): its tables as text, the best design's config (null: none
 *  feasible), the best and base candidates, the Pareto front's candidate numbers and the
 *  report's plots. */
export interface OptimizeResult {
  candidates_csv: string;
  pareto_csv: string;
  optimum_toml: string | null;
  best: Candidate | null;
  start: Candidate | null;
  front: number[];
  plots: SearchPlot[];
}
