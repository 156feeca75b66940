//! Every command of rvlife declared once: its name in each front end (the command line's
//! subcommand, the Python function, the page's command), and each option's name, kind, unit,
//! default and the front ends that take it.
//!
//! The front ends are checked against this table, each by a test of its own that fails when
//! it misses a command or an option, names one the table does not, or gives an option another
//! default: the command line's parser (`crates/rvlife-cli/tests/commands.rs`), the Python
//! functions' signatures (`crates/rvlife-py/tests/test_commands.py`, reading
//! [`commands_json`] through the binding) and the page's command table (the generated
//! `PageCommand` type in `web/src/generated/results.ts`, which `web/src/protocol.ts` must
//! cover for the page's type check to pass). The defaults the front ends share are the
//! constants named here. docs/architecture.md ("Add a command") says what a new command
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
    /// What it does, one line.
    pub summary: &'static str,
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
const WEAR_UM: OptionDecl = opt("wear_um", Kind::Number, "um").only(NATIVE);
const HOURS: OptionDecl = opt("hours", Kind::Number, "h");
const OUT: OptionDecl = opt("out", Kind::Path, "").only(NATIVE);
const FORCE: OptionDecl = opt("force", Kind::Flag, "").only(NATIVE);
const JSON: OptionDecl = opt("json", Kind::Flag, "").only(CLI);

/// Every command, in the command line's order.
pub const COMMANDS: &[CommandDecl] = &[
    CommandDecl {
        name: "example",
        python: Some("example"),
        page: Some("presetText"),
        summary: "a built-in config, fully commented",
        out_dir: None,
        options: &[
            opt("preset", Kind::Text, "").default(Default::Text(PRESET)),
            opt("list", Kind::Flag, "").only(CLI),
        ],
    },
    CommandDecl {
        name: "run",
        python: Some("run_study"),
        page: Some("study"),
        summary: "the accuracy-life study and its results directory",
        out_dir: Some("rvlife-results"),
        options: &[OUT, FORCE, opt("all", Kind::Flag, "").only(CLI)],
    },
    CommandDecl {
        name: "profile",
        python: Some("profile"),
        page: Some("profile"),
        summary: "the disc profile's points or its export",
        out_dir: None,
        options: &[
            opt("out", Kind::Path, "").only(CLI),
            JSON,
            // 0 in Python: the export's, as the command line's absent option.
            opt("points_per_tooth", Kind::Count, "").python_default(Default::Count(0)),
            opt("nominal", Kind::Flag, ""),
            opt("force", Kind::Flag, "").only(CLI),
            WEAR_UM,
            HOURS,
        ],
    },
    CommandDecl {
        name: "contact",
        python: Some("contact"),
        page: Some("contact"),
        summary: "the static equilibrium at one crank angle under an output torque",
        out_dir: None,
        options: &[
            opt("crank_deg", Kind::Number, "deg").default(Default::Required),
            opt("torque_nm", Kind::Number, "N m").default(Default::Required),
            JSON,
            WEAR_UM,
            HOURS,
        ],
    },
    CommandDecl {
        name: "te",
        python: Some("te"),
        page: Some("te"),
        summary: "static and loaded transmission error, backlash and lost motion",
        out_dir: None,
        options: &[opt("torque_nm", Kind::Number, "N m"), JSON, WEAR_UM, HOURS],
    },
    CommandDecl {
        name: "hysteresis",
        python: Some("hysteresis"),
        page: Some("hysteresis"),
        summary: "the hysteresis curve and its catalogue quantities",
        out_dir: None,
        options: &[
            opt("crank_deg", Kind::Number, "deg").default(Default::Number(0.0)),
            opt("levels", Kind::Count, "").default(Default::Count(HYSTERESIS_LEVELS as u64)),
            JSON,
            opt("sensitivity", Kind::Number, "").only(CLI),
            WEAR_UM,
            HOURS,
        ],
    },
    CommandDecl {
        name: "efficiency",
        python: Some("efficiency"),
        page: None,
        summary: "losses and efficiency over speed, torque and oil temperature",
        out_dir: None,
        options: &[
            opt("speeds_rpm", Kind::Numbers, "rpm").only(NATIVE),
            opt("torques_nm", Kind::Numbers, "N m").only(NATIVE),
            opt("temperatures_c", Kind::Numbers, "deg C").only(NATIVE),
            opt("out", Kind::Path, "").only(CLI),
            opt("force", Kind::Flag, "").only(CLI),
            JSON,
            WEAR_UM,
            HOURS.only(NATIVE),
        ],
    },
    CommandDecl {
        name: "dynamics",
        python: Some("dynamics"),
        page: Some("dynamics"),
        summary: "the multibody simulation and its dynamic transmission error",
        out_dir: None,
        options: &[
            opt("load", Kind::Text, "").only(NATIVE),
            opt("torque_nm", Kind::Number, "N m"),
            OUT,
            FORCE,
            opt("pin_forces", Kind::Flag, "").only(NATIVE),
            JSON,
            opt("disc", Kind::Text, ""),
            WEAR_UM,
            HOURS,
        ],
    },
    CommandDecl {
        name: "montecarlo",
        python: Some("montecarlo"),
        page: Some("montecarlo"),
        summary: "Monte Carlo over the part tolerances: the accuracy life's distribution",
        out_dir: Some("rvlife-montecarlo"),
        options: &[
            opt("samples", Kind::Count, "").default(Default::Count(MONTECARLO_SAMPLES as u64)),
            opt("seed", Kind::Count, "").default(Default::Count(SEED)),
            opt("shard", Kind::Text, "").only(NATIVE),
            opt("full_wear", Kind::Flag, "").only(NATIVE),
            opt("samples_per_mesh_cycle", Kind::Count, "")
                .default(Default::Count(
                    crate::montecarlo::DEFAULT_SAMPLES_PER_MESH_CYCLE as u64,
                ))
                .only(NATIVE),
            OUT,
            FORCE,
            opt("keep_going", Kind::Flag, "").only(CLI),
            opt("threads", Kind::Count, "").only(&[Front::Python]),
        ],
    },
    CommandDecl {
        name: "merge",
        python: Some("merge"),
        page: Some("montecarloMerge"),
        summary: "the parts of a Monte Carlo run combined",
        out_dir: None,
        options: &[
            opt("shards", Kind::Texts, "")
                .default(Default::Required)
                .only(NATIVE),
            opt("out", Kind::Path, "")
                .default(Default::Required)
                .only(NATIVE),
            FORCE,
        ],
    },
    CommandDecl {
        name: "sweep",
        python: Some("sweep"),
        page: None,
        summary: "one accuracy-life study per design of a product of key values",
        out_dir: Some("rvlife-sweep"),
        options: &[
            opt("vary", Kind::Texts, "")
                .default(Default::Required)
                .only(CLI),
            opt("set", Kind::Texts, "").only(CLI),
            OUT,
            FORCE,
            opt("tasks", Kind::Count, "").only(&[Front::Python]),
        ],
    },
    CommandDecl {
        name: "optimize",
        python: Some("optimize"),
        page: Some("optimize"),
        summary: "the design that stays in spec longest, or the Pareto front of several goals",
        out_dir: Some("rvlife-optimize"),
        options: &[
            opt("vary", Kind::Texts, "").default(Default::Required),
            opt("objective", Kind::Text, "").default(Default::Text(OPTIMIZE_OBJECTIVE)),
            opt("constraint", Kind::Texts, "").python("constraints"),
            opt("evaluations", Kind::Count, "")
                .default(Default::Count(OPTIMIZE_EVALUATIONS as u64)),
            opt("seed", Kind::Count, "").default(Default::Count(SEED)),
            OUT,
            FORCE,
        ],
    },
    CommandDecl {
        name: "calibrate",
        python: Some("calibrate"),
        page: None,
        summary: "the Archard coefficient for a target wear or fitted to measurements",
        out_dir: None,
        options: &[
            // None in Python: the target, unless measurements are given.
            opt("target_wear_um", Kind::Number, "um")
                .default(Default::Number(CALIBRATE_TARGET_WEAR_UM))
                .python_default(Default::Absent)
                .only(NATIVE),
            opt("measured", Kind::Path, ""),
            opt(
                "catalogue_stiffness_nm_per_arcmin",
                Kind::Number,
                "N m/arcmin",
            )
            .only(CLI),
            opt("fit_running_in", Kind::Flag, "").only(NATIVE),
            OUT,
            FORCE,
        ],
    },
];

/// [`COMMANDS`] as JSON: `[{name, python, page, summary, options: [{name, python_name, kind,
/// unit, default, fronts}]}]`, for the front ends' tests.
pub fn commands_json() -> String {
    serde_json::to_string(COMMANDS).unwrap_or_default()
}

/// The command `name` of the command line.
pub fn command(name: &str) -> Option<&'static CommandDecl> {
    COMMANDS.iter().find(|c| c.name == name)
}
