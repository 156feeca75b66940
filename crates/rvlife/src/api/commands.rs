//! Every command of rvlife declared once: its name in each front end (the command line's
//! subcommand, the Python function, the page's command), and each option's name, kind, unit,
//! default and the front ends that take it.
//!
//! The front ends are checked against this table, each by a test of its own that fails when
//! it misses a command or an option, names one the table does not, or gives an option another
//! default: the command line's parser (`crates/rvlife-cli/src/declared.rs`), the Python
//! functions' signatures (`crates/rvlife-py/tests/test_commands.py`, reading
//! [`commands_json`] through the binding) and the page's command table (the generated
//! `PageCommand` type in `web/src/generated/results.ts`, which `web/src/protocol.ts` must
//! cover for the page's type check to pass). The defaults the front ends share are the
//! constants named here. docs/architecture.md ("A command") says what a new command
//! touches.

use serde::Serialize;

/// What an option takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A real number in the option's unit.
    Number,
    /// A whole number (a count, a seed, an index).
    Count,
    /// On or off.
    Flag,
    /// A text (a name, an expression such as `KEY=LO:HI`).
    Text,
    /// A file or directory.
    Path,
    /// Several real numbers (comma-separated on the command line).
    Numbers,
    /// Several texts (the option repeated on the command line).
    Texts,
}

/// An option's default.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Default {
    /// None: the option is optional and absent unless given.
    Absent,
    /// It must be given.
    Required,
    /// Off (a flag).
    Off,
    /// This number.
    Number(f64),
    /// This whole number.
    Count(u64),
    /// This text.
    Text(&'static str),
}

/// A front end of rvlife.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Front {
    /// The `rvlife` command line.
    Cli,
    /// The Python package `rvlife`.
    Python,
    /// The web page (the WebAssembly module's commands).
    Page,
}

/// Every front end.
const ALL: &[Front] = &[Front::Cli, Front::Python, Front::Page];
/// The command line and Python.
const NATIVE: &[Front] = &[Front::Cli, Front::Python];
/// The command line alone.
const CLI: &[Front] = &[Front::Cli];

/// One option of a command.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct OptionDecl {
    /// Its name in snake case: `--crank-deg` on the command line, `crank_deg` in Python.
    pub name: &'static str,
    /// Its name in Python where that differs (`constraints` for `--constraint`).
    pub python_name: Option<&'static str>,
    /// What it takes.
    pub kind: Kind,
    /// Its unit (`deg`, `N m`, `um`, `h`; empty for none).
    pub unit: &'static str,
    /// Its default on the command line and in Python (the page passes every option).
    pub default: Default,
    /// Its default in Python where Python says "not given" otherwise (`None` where the
    /// command line has a number, for options given one of two ways).
    pub python_default: Option<Default>,
    /// The front ends that take it.
    pub fronts: &'static [Front],
    /// What it means, one paragraph: the command line's `--help`, the Python function's
    /// docstring and the page's form field (its tooltip) show it.
    pub help: &'static str,
}

impl OptionDecl {
    /// Its default in the front end `front`.
    pub fn default_in(&self, front: Front) -> Default {
        match (front, self.python_default) {
            (Front::Python, Some(d)) => d,
            _ => self.default,
        }
    }
}

/// An optional option every front end takes, absent by default.
const fn opt(name: &'static str, kind: Kind, unit: &'static str) -> OptionDecl {
    OptionDecl {
        name,
        python_name: None,
        kind,
        unit,
        default: match kind {
            Kind::Flag => Default::Off,
            _ => Default::Absent,
        },
        python_default: None,
        fronts: ALL,
        help: "",
    }
}

impl OptionDecl {
    const fn default(mut self, d: Default) -> Self {
        self.default = d;
        self
    }

    const fn only(mut self, fronts: &'static [Front]) -> Self {
        self.fronts = fronts;
        self
    }

    const fn python_default(mut self, d: Default) -> Self {
        self.python_default = Some(d);
        self
    }

    const fn python(mut self, name: &'static str) -> Self {
        self.python_name = Some(name);
        self
    }

    const fn help(mut self, text: &'static str) -> Self {
        self.help = text;
        self
    }
}

/// One command.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct CommandDecl {
    /// Its subcommand on the command line (`rvlife te`).
    pub name: &'static str,
    /// Its function in the Python package (`None`: not in Python).
    pub python: Option<&'static str>,
    /// Its command on the page (`None`: not on the page).
    pub page: Option<&'static str>,
    /// What it does and writes, one paragraph: the command line's `--help` shows it.
    pub about: &'static str,
    /// The results directory the command line writes when `--out` is not given (`None`:
    /// none, or `--out` has no default).
    pub out_dir: Option<&'static str>,
    /// Its options (the config file or object, given to every command but `merge`, is not
    /// among them).
    pub options: &'static [OptionDecl],
}

/// The default number of sampled reducers of a Monte Carlo run.
pub const MONTECARLO_SAMPLES: usize = 100;
/// The default seed of every command that draws.
pub const SEED: u64 = 1;
/// The default torque levels per side of a hysteresis curve beyond the measuring torque.
pub const HYSTERESIS_LEVELS: u32 = 10;
/// The default candidate studies of a design search.
pub const OPTIMIZE_EVALUATIONS: usize = 150;
/// The default goal of a design search.
pub const OPTIMIZE_OBJECTIVE: &str = "life";
/// The default built-in reducer.
pub const PRESET: &str = "rv-40e";
/// The default target largest wear at the last stage of `calibrate`, um.
pub const CALIBRATE_TARGET_WEAR_UM: f64 = 60.0;

/// How worn the analysed profile is: a uniform depth or the wear model's hours.
const WEAR_UM: OptionDecl = opt("wear_um", Kind::Number, "um")
    .only(NATIVE)
    .help("Uniform wear depth along the whole profile, um (the paper's conservative model)");
const HOURS: OptionDecl = opt("hours", Kind::Number, "h")
    .help("Wear map from the config's wear model after this many working hours");
const OUT: OptionDecl = opt("out", Kind::Path, "").only(NATIVE);
const FORCE: OptionDecl = opt("force", Kind::Flag, "").only(NATIVE);
const JSON: OptionDecl = opt("json", Kind::Flag, "").only(CLI);

/// Every command, in the command line's order.
pub const COMMANDS: &[CommandDecl] = &[
    CommandDecl {
        name: "example",
        python: Some("example"),
        page: Some("presetText"),
        about: "Print a built-in config, fully commented: the built-in RV-40E-class reducer by default",
        out_dir: None,
        options: &[
            opt("preset", Kind::Text, "").default(Default::Text(PRESET)).help("Which built-in reducer (`--list` shows them)"),
            opt("list", Kind::Flag, "").only(CLI).help("List the built-in reducers with their sources"),
        ],
    },
    CommandDecl {
        name: "run",
        python: Some("run_study"),
        page: Some("study"),
        about: "Run the accuracy-life study and write the results directory",
        out_dir: Some("rvlife-results"),
        options: &[
            OUT.help("Results directory (created; must not exist or be empty unless --force)"),
            FORCE.help("Replace an existing results directory"),
            opt("all", Kind::Flag, "").only(CLI).help("Also print every quantity of every stage (all of `stages.csv`), one row per quantity"),
        ],
    },
    CommandDecl {
        name: "profile",
        python: Some("profile"),
        page: Some("profile"),
        about: "Export the disc profile (nominal, modified or worn) to CSV, DXF or SVG",
        out_dir: None,
        options: &[
            opt("out", Kind::Path, "").only(CLI).help("Output file; the format follows the extension (.csv, .dxf, .svg)"),
            JSON.help("Print the points as JSON instead (x, y in mm, mesh angle in deg, wear depth along the normal in um; the web page's `profile`)"),
            // 0 in Python: the export's, as the command line's absent option.
            opt("points_per_tooth", Kind::Count, "").python_default(Default::Count(0)).help("Points per tooth of `--json` (default: the export's)"),
            opt("nominal", Kind::Flag, "").help("Ignore the config's modifications (the nominal profile)"),
            opt("force", Kind::Flag, "").only(CLI).help("Replace an existing output file"),
            WEAR_UM,
            HOURS,
        ],
    },
    CommandDecl {
        name: "contact",
        python: Some("contact"),
        page: Some("contact"),
        about: "Static equilibrium of the reducer at one crank angle under an output torque (input locked): pin forces on each disc, disc translations, twist",
        out_dir: None,
        options: &[
            opt("crank_deg", Kind::Number, "deg").default(Default::Required).help("Crank angle, degrees (0: eccentric towards pin 0)"),
            opt("torque_nm", Kind::Number, "N m").default(Default::Required).help("Torque on the output, N m (positive counter-clockwise)"),
            JSON.help("Print one JSON object"),
            WEAR_UM,
            HOURS,
        ],
    },
    CommandDecl {
        name: "te",
        python: Some("te"),
        page: Some("te"),
        about: "Static TE, backlash and lost motion over a mesh cycle (and loaded TE with --torque-nm)",
        out_dir: None,
        options: &[
            opt("torque_nm", Kind::Number, "N m").help("Also the loaded TE at this output torque, N m"),
            JSON.help("Print one JSON object"),
            WEAR_UM,
            HOURS,
        ],
    },
    CommandDecl {
        name: "hysteresis",
        python: Some("hysteresis"),
        page: Some("hysteresis"),
        about: "Hysteresis curve (output torque 0 -> +rated -> -rated -> +rated, input locked) with backlash, lost motion, hysteresis loss and torsional stiffness",
        out_dir: None,
        options: &[
            opt("crank_deg", Kind::Number, "deg").default(Default::Number(0.0)).help("Crank angle of the single-crank-angle curve, degrees (the mean over a mesh cycle is always reported)"),
            opt("levels", Kind::Count, "").default(Default::Count(HYSTERESIS_LEVELS as u64)).help("Torque levels per side beyond the measuring torque"),
            JSON.help("Print one JSON object"),
            opt("sensitivity", Kind::Number, "").only(CLI).help("Also how `b/a` and the lost motion of the new reducer move when each estimated dimension or count of its structure and bearings changes by this fraction both ways (0.2 when given without a value; in (0, 0.5]); `--json` as `sensitivity`"),
            WEAR_UM,
            HOURS,
        ],
    },
    CommandDecl {
        name: "efficiency",
        python: Some("efficiency"),
        page: None,
        about: "Power losses and efficiency over output speed, torque and oil temperature: the disc-pin contacts (the oil film's friction), crank bearings and sun-planet meshes",
        out_dir: None,
        options: &[
            opt("speeds_rpm", Kind::Numbers, "rpm").only(NATIVE).help("Output speeds, rpm, comma-separated (default 5,10,15,20,30,40,50)"),
            opt("torques_nm", Kind::Numbers, "N m").only(NATIVE).help("Output torques, N m, comma-separated (default 1/4, 1/2, 3/4 and all of the rated torque)"),
            opt("temperatures_c", Kind::Numbers, "deg C").only(NATIVE).help("Oil temperatures, deg C, comma-separated (default `[lubrication] temperature_c`)"),
            opt("out", Kind::Path, "").only(CLI).help("Also write the map as CSV to this file (must not exist unless --force)"),
            opt("force", Kind::Flag, "").only(CLI).help("Replace an existing --out file"),
            JSON.help("Print one JSON object"),
            WEAR_UM,
            HOURS.only(NATIVE),
        ],
    },
    CommandDecl {
        name: "dynamics",
        python: Some("dynamics"),
        page: Some("dynamics"),
        about: "Simulate the whole reducer (multibody model, impact contact) and report the dynamic TE",
        out_dir: None,
        options: &[
            opt("load", Kind::Text, "").only(NATIVE).help("Output load, overriding `[dynamics.load] kind` (its other keys still apply)"),
            opt("torque_nm", Kind::Number, "N m").help("Constant torque on the output, N m (with --load constant; default: rated torque; positive counter-clockwise, a load resisting forward rotation is negative)"),
            OUT.help("Results directory: `dynamics.csv`, `summary.json`, plots (created; must not exist or be empty unless --force)"),
            FORCE.help("Replace an existing results directory"),
            opt("pin_forces", Kind::Flag, "").only(NATIVE).help("Also write every pin force at every sample (`pin_forces.csv`)"),
            JSON.help("Print the summary as one JSON object"),
            opt("disc", Kind::Text, "").help("The discs, overriding `[dynamics] disc`: rigid, or the FE disc of `[fem]` modally reduced (`[dynamics.flexible]`)"),
            WEAR_UM,
            HOURS,
        ],
    },
    CommandDecl {
        name: "montecarlo",
        python: Some("montecarlo"),
        page: Some("montecarlo"),
        about: "Monte Carlo over the part tolerances (`[tolerances]`): sampled reducers through the accuracy-life study; per-sample results, percentiles, the accuracy life's distribution",
        out_dir: Some("rvlife-montecarlo"),
        options: &[
            opt("samples", Kind::Count, "").default(Default::Count(MONTECARLO_SAMPLES as u64)).help("Number of sampled reducers of the whole run"),
            opt("seed", Kind::Count, "").default(Default::Count(SEED)).help("Seed: same seed, same bytes"),
            opt("shard", Kind::Text, "").only(NATIVE).help("`I/N`: run only the I-th (1-based) of N disjoint parts of the samples; `/N` takes I from SLURM_ARRAY_TASK_ID (cluster job arrays with `--array=1-N`); `rvlife merge` combines the parts"),
            opt("full_wear", Kind::Flag, "").only(NATIVE).help("Integrate every sample's own wear instead of sharing the nominal reducer's"),
            opt("samples_per_mesh_cycle", Kind::Count, "")
                .default(Default::Count(
                    crate::montecarlo::DEFAULT_SAMPLES_PER_MESH_CYCLE as u64,
                ))
                .only(NATIVE).help("Crank angles per mesh cycle of the hysteresis curves and the revolution TE"),
            OUT.help("Results directory"),
            FORCE.help("Replace an existing results directory"),
            opt("keep_going", Kind::Flag, "").only(CLI).help("Accept a run in which most samples cannot be assembled, fail, or start out of spec (by default such a run writes its results and exits with code 2, naming `[tolerances]`)"),
            opt("threads", Kind::Count, "").only(&[Front::Python]).help("The threads this process runs the samples on (default: one per core; Python only)"),
        ],
    },
    CommandDecl {
        name: "merge",
        python: Some("merge"),
        page: Some("montecarloMerge"),
        about: "Combine the shards of a Monte Carlo run into exactly the files the unsharded run writes",
        out_dir: None,
        options: &[
            opt("shards", Kind::Texts, "")
                .default(Default::Required)
                .only(NATIVE).help("The shards' results directories"),
            opt("out", Kind::Path, "")
                .default(Default::Required)
                .only(NATIVE).help("Results directory"),
            FORCE.help("Replace an existing results directory"),
        ],
    },
    CommandDecl {
        name: "sweep",
        python: Some("sweep"),
        page: None,
        about: "Design sweep: the product of values of config keys (`--vary`), one accuracy-life study per design; writes the tidy table of every design and stage (`sweep.csv`), each design's verdict (`designs.csv`), its config, and a report",
        out_dir: Some("rvlife-sweep"),
        options: &[
            opt("vary", Kind::Texts, "")
                .default(Default::Required)
                .only(CLI).help("A varied key: `KEY=LO:HI:N` (N values from LO to HI) or `KEY=A,B,C`, the key dotted as in the config (`cycloid.eccentricity_mm=1.2:1.4:3`); repeat for a product"),
            opt("set", Kind::Texts, "").only(CLI).help("A key set in every design, `KEY=VALUE` (`dynamics.enabled=false`); repeatable"),
            OUT.help("Results directory"),
            FORCE.help("Replace an existing results directory"),
            opt("tasks", Kind::Count, "").only(&[Front::Python]).help("Shards of a Monte Carlo run handed to the Dask workers (default: four per worker thread; Python only)"),
        ],
    },
    CommandDecl {
        name: "optimize",
        python: Some("optimize"),
        page: Some("optimize"),
        about: "Design search: the keys of `--vary` within their ranges that keep the reducer in spec longest (`--objective life`, or `b10`), or the Pareto front of several goals (`life,lost_motion_arcmin`), under constraints on any quantity at any stage; writes every candidate (`candidates.csv`), the front (`pareto.csv`), the best design's config (`optimum.toml`) and a report. Ctrl-C stops after the running candidate and writes what was found",
        out_dir: Some("rvlife-optimize"),
        options: &[
            opt("vary", Kind::Texts, "").default(Default::Required).help("A varied key and its range, `KEY=LO:HI`, dotted as in the config (`cycloid.modification.equidistant_mm=0.008:0.03`); whole-number ends on a key that takes whole numbers (pins) search whole numbers; repeat for each key"),
            opt("objective", Kind::Text, "").default(Default::Text(OPTIMIZE_OBJECTIVE)).help("The goals, comma separated: `life` (the accuracy life), `b10` or `b10:SAMPLES` (a Monte Carlo of `[tolerances]` per candidate), a quantity of stages.csv (minimised; `max:` to maximise), a quantity optionally at a stage (`@new`, `@last`, `@HOURS`); two or more give a Pareto front (NSGA-II)"),
            opt("constraint", Kind::Texts, "").python("constraints").help("A constraint, `QUANTITY[@STAGE]<=VALUE` or `>=` (`lost_motion_arcmin<=0.8`: the new reducer; `max_pressure_mpa@last<=1500`); repeatable"),
            opt("evaluations", Kind::Count, "")
                .default(Default::Count(OPTIMIZE_EVALUATIONS as u64)).help("Most candidate studies (2 to 5000)"),
            opt("seed", Kind::Count, "").default(Default::Count(SEED)).help("Seed of the search's random draws (and of the B10 goal's samples)"),
            OUT.help("Results directory"),
            FORCE.help("Replace an existing results directory"),
        ],
    },
    CommandDecl {
        name: "calibrate",
        python: Some("calibrate"),
        page: None,
        about: "Find the Archard coefficient that gives a target maximum wear at the last stage, or (with --measured) fit it to measured lost motion, backlash or wear against hours",
        out_dir: None,
        options: &[
            // None in Python: the target, unless measurements are given.
            opt("target_wear_um", Kind::Number, "um")
                .default(Default::Number(CALIBRATE_TARGET_WEAR_UM))
                .python_default(Default::Absent)
                .only(NATIVE).help("Target maximum wear depth at the last stage, um"),
            opt("measured", Kind::Path, "").help("Measurements CSV: a column `hours` (h) and one or more of `lost_motion_arcmin`, `backlash_arcmin`, `angular_te_arcmin`, `max_wear_um` (empty cell: not measured). Fits the Archard coefficient by weighted least squares with a 95 % confidence interval (Gauss-Newton, Student-t) instead of aiming at --target-wear-um; with `[wear] running_in_factor` > 1 in the config it fits that factor too (`running_in_hours` kept). Or a measured hysteresis curve of the new reducer, columns `torque_nm,twist_arcmin` in the bench's order (0 -> +rated -> -rated -> +rated): fits `[reducer.structure] compliance_arcmin_per_knm` with its 95 % interval"),
            opt(
                "catalogue_stiffness_nm_per_arcmin",
                Kind::Number,
                "N m/arcmin",
            )
            .only(CLI).help("A catalogue torsional stiffness b/a, N m/arcmin: sets `[reducer.structure] compliance_arcmin_per_knm` so that the new reducer's b/a equals it"),
            opt("fit_running_in", Kind::Flag, "").only(NATIVE).help("Also fit a running-in play b0 (arcmin) added to backlash and lost motion (the assembly play of a new reducer beyond the model's own)"),
            OUT.help("Results directory: calibrated.toml (the config with the fitted values set, ready for `rvlife run`) and, for a fit to measurements, calibration.json, residuals.csv, calibration.svg/png (created; must not exist or be empty unless --force). Without it, calibrated.toml is written in the current directory, where it must not exist"),
            FORCE.help("Replace an existing results directory"),
        ],
    },
];

/// [`COMMANDS`] as JSON: `[{name, python, page, about, out_dir, options: [{name, python_name, kind,
/// unit, default, python_default, fronts, help}]}]`, for the front ends' tests and the Python
/// functions' docstrings.
pub fn commands_json() -> String {
    serde_json::to_string(COMMANDS).unwrap_or_default()
}

/// The command `name` of the command line.
pub fn command(name: &str) -> Option<&'static CommandDecl> {
    COMMANDS.iter().find(|c| c.name == name)
}
