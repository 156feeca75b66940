//! `rvlife`: command-line front end of the rvlife library.
//!
//! Exit codes: 0 success; 2 bad input (invalid value, bad or missing config, bad arguments);
//! 1 any other failure.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, FromArgMatches, Parser, Subcommand};
use console::{print_all_quantities, print_sensitivity, print_stage_table};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use rvlife::api::{commands, Spelling, Wear};
use rvlife::config::{Config, Model};
use rvlife::geometry::Profile;
use rvlife::output::export::{write_profile, ProfileFormat};
use rvlife::Result;
use serde_json::{json, Value};

/// `println!` for the console's result lines: a number that rounds to zero is printed without
/// a sign (`0.00000`, not the round-off's `-0.00000`).
macro_rules! say {
    ($($t:tt)*) => {
        println!("{}", $crate::unsigned_zeros(&format!($($t)*)))
    };
}

mod calibrate;
mod console;
mod declared;
mod efficiency;
mod optimize;
mod sweep;

/// `text` with the minus sign of every number that is all zeros (`-0`, `-0.000`) removed (a
/// space in its place where padding precedes it, so that columns stay aligned).
fn unsigned_zeros(text: &str) -> String {
    let b = text.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    for (i, &c) in b.iter().enumerate() {
        if c == b'-' && (i == 0 || !(b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'.')) {
            let rest = &b[i + 1..];
            let n = rest.iter().take_while(|&&d| d == b'0' || d == b'.').count();
            let next = rest.get(n);
            let zero = n > 0
                && rest[0] == b'0'
                && !matches!(next, Some(d) if d.is_ascii_digit() || *d == b'e' || *d == b'E');
            if zero {
                // In a right-aligned column (padding before it) a space keeps the width.
                if i >= 2 && b[i - 1] == b' ' && b[i - 2] == b' ' {
                    out.push(b' ');
                }
                continue;
            }
        }
        out.push(c);
    }
    // Only ASCII minus signs were removed: still UTF-8.
    String::from_utf8(out).unwrap_or_else(|_| text.to_string())
}

/// The results directory command `name` writes by default (`rvlife::api::commands`).
fn out_dir(name: &str) -> &'static str {
    commands::command(name)
        .and_then(|c| c.out_dir)
        .unwrap_or("rvlife-results")
}

#[derive(Parser)]
#[command(
    name = "rvlife",
    version,
    about = "Accuracy-life prediction of RV reducers: cycloid profile, loaded contact, Archard wear, transmission error"
)]
struct Cli {
    /// Work budget, minutes of estimated computing on a 2-core machine: a config or command
    /// whose estimated work exceeds it is refused before it starts, naming the key that drives
    /// it.
    #[arg(
        long,
        global = true,
        default_value_t = rvlife::budget::DEFAULT_MINUTES,
        allow_negative_numbers = true
    )]
    work_budget_min: f64,
    #[command(subcommand)]
    command: Command,
}

/// The subcommands. Their descriptions and their options' help are not written here: they
/// come from the library's declaration of the commands (`rvlife::api::commands`), set on the
/// parser by `declared::cli`.
#[derive(Subcommand)]
enum Command {
    Example {
        #[arg(long, default_value = commands::PRESET)]
        preset: String,
        #[arg(long)]
        list: bool,
    },
    Run {
        /// Config file (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, default_value = out_dir("run"))]
        out: PathBuf,
        #[arg(long)]
        force: bool,
        #[arg(long)]
        all: bool,
    },
    Profile {
        /// Config file (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, required_unless_present = "json")]
        out: Option<PathBuf>,
        #[arg(long, conflicts_with = "out")]
        json: bool,
        #[arg(long, requires = "json")]
        points_per_tooth: Option<usize>,
        #[arg(long)]
        nominal: bool,
        #[arg(long)]
        force: bool,
        #[command(flatten)]
        wear: WearArgs,
    },
    Contact {
        /// Config file (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, allow_hyphen_values = true)]
        crank_deg: f64,
        #[arg(long, allow_hyphen_values = true)]
        torque_nm: f64,
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        wear: WearArgs,
    },
    Te {
        /// Config file (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, allow_hyphen_values = true)]
        torque_nm: Option<f64>,
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        wear: WearArgs,
    },
    Hysteresis {
        /// Config file (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
        crank_deg: f64,
        #[arg(long, default_value_t = commands::HYSTERESIS_LEVELS, allow_negative_numbers = true, value_parser = whole::<u32>)]
        levels: u32,
        #[arg(long)]
        json: bool,
        #[arg(long, num_args = 0..=1, default_missing_value = "0.2", allow_negative_numbers = true)]
        sensitivity: Option<f64>,
        #[command(flatten)]
        wear: WearArgs,
    },
    Efficiency {
        /// Config file (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        speeds_rpm: Option<Vec<f64>>,
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        torques_nm: Option<Vec<f64>>,
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        temperatures_c: Option<Vec<f64>>,
        #[arg(long)]
        out: Option<PathBuf>,
        #[arg(long)]
        force: bool,
        #[arg(long)]
        json: bool,
        #[command(flatten)]
        wear: WearArgs,
    },
    Dynamics {
        /// Config file (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, value_parser = ["none", "constant", "sinusoidal", "table"])]
        load: Option<String>,
        #[arg(long, allow_hyphen_values = true)]
        torque_nm: Option<f64>,
        #[arg(long)]
        out: Option<PathBuf>,
        #[arg(long)]
        force: bool,
        #[arg(long)]
        pin_forces: bool,
        #[arg(long)]
        json: bool,
        #[arg(long, value_parser = ["rigid", "flexible"])]
        disc: Option<String>,
        #[command(flatten)]
        wear: WearArgs,
    },
    Montecarlo {
        /// Config file (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, default_value_t = commands::MONTECARLO_SAMPLES, allow_negative_numbers = true, value_parser = whole::<usize>)]
        samples: usize,
        #[arg(long, default_value_t = commands::SEED, allow_negative_numbers = true, value_parser = whole::<u64>)]
        seed: u64,
        #[arg(long, allow_hyphen_values = true)]
        shard: Option<String>,
        #[arg(long)]
        full_wear: bool,
        #[arg(long, default_value_t = rvlife::montecarlo::DEFAULT_SAMPLES_PER_MESH_CYCLE, allow_negative_numbers = true, value_parser = whole::<usize>)]
        samples_per_mesh_cycle: usize,
        #[arg(long, default_value = out_dir("montecarlo"))]
        out: PathBuf,
        #[arg(long)]
        force: bool,
        #[arg(long)]
        keep_going: bool,
    },
    Merge {
        #[arg(required = true)]
        shards: Vec<PathBuf>,
        #[arg(long)]
        out: PathBuf,
        #[arg(long)]
        force: bool,
    },
    Sweep {
        /// Config file the designs start from (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, required = true, allow_hyphen_values = true)]
        vary: Vec<String>,
        #[arg(long, allow_hyphen_values = true)]
        set: Vec<String>,
        #[arg(long, default_value = out_dir("sweep"))]
        out: PathBuf,
        #[arg(long)]
        force: bool,
    },
    Optimize {
        /// Config file the search starts from (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, required = true, allow_hyphen_values = true)]
        vary: Vec<String>,
        #[arg(long, default_value = commands::OPTIMIZE_OBJECTIVE)]
        objective: String,
        #[arg(long, allow_hyphen_values = true)]
        constraint: Vec<String>,
        #[arg(long, default_value_t = commands::OPTIMIZE_EVALUATIONS)]
        evaluations: usize,
        #[arg(long, default_value_t = commands::SEED)]
        seed: u64,
        #[arg(long, default_value = out_dir("optimize"))]
        out: PathBuf,
        #[arg(long)]
        force: bool,
    },
    Calibrate {
        /// Config file (default: the built-in example).
        config: Option<PathBuf>,
        #[arg(long, default_value_t = commands::CALIBRATE_TARGET_WEAR_UM, allow_negative_numbers = true)]
        target_wear_um: f64,
        #[arg(long, conflicts_with_all = ["target_wear_um", "catalogue_stiffness_nm_per_arcmin"])]
        measured: Option<PathBuf>,
        #[arg(long, conflicts_with = "target_wear_um")]
        catalogue_stiffness_nm_per_arcmin: Option<f64>,
        #[arg(long, requires = "measured")]
        fit_running_in: bool,
        #[arg(long)]
        out: Option<PathBuf>,
        #[arg(long, requires = "out")]
        force: bool,
    },
}

#[derive(Args)]
struct WearArgs {
    #[arg(long, conflicts_with = "hours", allow_hyphen_values = true)]
    wear_um: Option<f64>,
    #[arg(long, allow_hyphen_values = true)]
    hours: Option<f64>,
}

impl WearArgs {
    fn get(&self) -> Wear {
        Wear {
            wear_um: self.wear_um,
            hours: self.hours,
        }
    }
}

/// The percentiles at the last stage and the life distribution, to stdout.
fn print_montecarlo(model: &Model, records: &[rvlife::montecarlo::SampleRecord]) {
    say!(
        "{}",
        rvlife::output::montecarlo::verdict(records, &model.wear.stage_hours, &model.life)
    );
    if !records.iter().any(|r| r.status == "ok") {
        return;
    }
    let pct = rvlife::montecarlo::percentiles(records, &model.wear.stage_hours);
    let last = model.wear.stage_hours.last().copied().unwrap_or(0.0);
    say!("at {last:.0} h: quantity, p5, p50, p95");
    for p in pct.iter().filter(|p| p.hours == last) {
        say!(
            "  {:36} {:10.4} {:10.4} {:10.4}",
            p.quantity,
            p.p5,
            p.p50,
            p.p95
        );
    }
    if model.life.any() {
        let horizon = model.life.horizon_h(&model.wear.stage_hours);
        let l = rvlife::montecarlo::life_distribution(records, horizon);
        let h = |v: Option<f64>| v.map_or(format!("> {horizon:.0} h"), |x| format!("{x:.0} h"));
        let life = rvlife::montecarlo::life_text;
        say!(
            "accuracy life: 5 % {}, B10 {}, B50 {}, 95 % {}; {:.1} % beyond {horizon:.0} h; limited by {:?}",
            h(l.p5_h),
            life(l.b10_h, l.km_b10_h, horizon),
            life(l.b50_h, l.km_b50_h, horizon),
            h(l.p95_h),
            100.0 * l.censored_fraction,
            l.limited_by
        );
        say!("{}", l.weibull_text());
    }
}

/// The JSON value of a result (an object's keys sorted, as `--json` prints it).
/// A whole-number option (`--samples`, `--seed`): a negative or fractional value is refused
/// by clap (exit 2) naming the option and the value, instead of being read as an option.
fn whole<T: std::str::FromStr>(s: &str) -> std::result::Result<T, String> {
    s.trim()
        .parse::<T>()
        .map_err(|_| "must be a whole number, 0 or more (in range of the option)".to_string())
}

fn to_json<T: serde::Serialize>(v: &T) -> Result<Value> {
    serde_json::to_value(v).map_err(|e| rvlife::Error::numerical("json", e.to_string()))
}

/// Prints a result as one line of JSON (`--json`).
fn print_json<T: serde::Serialize>(v: &T) -> Result<()> {
    println!("{}", to_json(v)?);
    Ok(())
}

/// The validated model; a measured profile's fit is reported on stderr.
fn validated(cfg: &Config) -> Result<Model> {
    let model = rvlife::api::validated(cfg)?;
    if let Some(m) = &model.cycloid.measured {
        eprintln!(
            "measured profile {}: {} points, fit residual RMS {:.3} um, max {:.3} um",
            m.source.display(),
            m.points,
            m.fit_rms * 1e6,
            m.fit_max * 1e6
        );
    }
    Ok(model)
}

/// The config file (or the built-in example) with the command line's work budget.
fn load_config(path: Option<&Path>, budget_min: f64) -> Result<Config> {
    load_config_text(path, budget_min).map(|(cfg, _)| cfg)
}

/// [`load_config`] and the config's text, read once.
fn load_config_text(path: Option<&Path>, budget_min: f64) -> Result<(Config, String)> {
    let (mut cfg, text) = match path {
        Some(p) => {
            let text = Config::read_text(p)?;
            let cfg = Config::from_toml_in(&text, &p.display().to_string(), p.parent())?;
            (cfg, text)
        }
        None => (Config::example(), rvlife::config::EXAMPLE_TOML.to_string()),
    };
    cfg.work_budget_minutes = budget_min;
    Ok((cfg, text))
}

/// The profile for the wear arguments (a spinner while the wear model integrates).
fn profile_for(model: &Model, wear: &WearArgs, nominal: bool) -> Result<Profile> {
    let pb = spinner("wear");
    let p = rvlife::api::profile_for(model, wear.get(), nominal, Spelling::Cli, &progress_to(&pb));
    pb.finish_and_clear();
    p
}

/// A progress bar on stderr for work that can take more than a second (drawn only on a
/// terminal), with `what` as its message.
fn spinner(what: &str) -> ProgressBar {
    let pb = progress_bar(1);
    pb.set_message(what.to_string());
    pb
}

/// A progress callback `(done, total)` that moves `pb`.
fn progress_to(pb: &ProgressBar) -> impl Fn(usize, usize) + Sync + '_ {
    move |done, total| {
        pb.set_length(total as u64);
        pb.set_position(done as u64);
    }
}

/// A spinner with the elapsed time on stderr (drawn only on a terminal) for work without a
/// step count.
fn busy(what: &str) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
    pb.set_style(
        ProgressStyle::with_template("{spinner} {msg} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    pb.set_message(what.to_string());
    pb.enable_steady_tick(std::time::Duration::from_millis(250));
    pb
}

fn progress_bar(len: u64) -> ProgressBar {
    let pb = ProgressBar::with_draw_target(Some(len), ProgressDrawTarget::stderr());
    pb.set_style(
        ProgressStyle::with_template("{spinner} {msg:12} [{bar:40}] {pos}/{len} {elapsed}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    pb.set_message("study");
    pb
}

fn run(cli: Cli) -> Result<()> {
    let budget = cli.work_budget_min;
    match cli.command {
        Command::Example { preset, list } => {
            if list {
                for p in rvlife::config::PRESETS {
                    say!("{:8} {}", p.name, p.summary);
                }
            } else {
                print!("{}", rvlife::config::preset_text(&preset)?);
            }
        }
        Command::Montecarlo {
            config,
            samples,
            seed,
            shard,
            full_wear,
            samples_per_mesh_cycle,
            out,
            force,
            keep_going,
        } => {
            let (cfg, text) = load_config_text(config.as_deref(), budget)?;
            let model = validated(&cfg)?;
            let plan = rvlife::api::montecarlo_plan(
                &model,
                samples,
                seed,
                shard.as_deref(),
                full_wear,
                samples_per_mesh_cycle,
                Spelling::Cli,
            )?;
            let staging = rvlife::output::Staging::prepare(&out, force)?;
            let pb = progress_bar(plan.indices().len() as u64);
            pb.set_message("samples");
            let start = std::time::Instant::now();
            let records = rvlife::montecarlo::run(&model, &plan, &progress_to(&pb))?;
            pb.finish_and_clear();
            let meta = rvlife::output::montecarlo::ShardMeta {
                rvlife_version: env!("CARGO_PKG_VERSION").into(),
                plan,
                stage_hours: model.wear.stage_hours.clone(),
                config_toml: text,
            };
            let whole = plan.shard == (1, 1);
            staging.commit(|dir| {
                if whole {
                    rvlife::output::montecarlo::write_results(dir, &meta, &records)
                } else {
                    rvlife::output::montecarlo::write_shard(dir, &meta, &records)
                }
            })?;
            let ok = records.iter().filter(|r| r.status == "ok").count();
            say!(
                "rvlife montecarlo: {} samples ({} ok), {:.2} s; results in {}",
                records.len(),
                ok,
                start.elapsed().as_secs_f64(),
                out.display()
            );
            if whole {
                print_montecarlo(&model, &records);
            }
            if let Some(why) = rvlife::montecarlo::unusable(&records) {
                if !keep_going {
                    return Err(rvlife::Error::invalid(
                        "tolerances",
                        why,
                        format!(
                            "the sampled reducers must mostly assemble and start within spec: \
                             the tolerances are wider than the stage's clearances, or the spec \
                             tighter than the new reducer (results written to {}; \
                             --keep-going accepts the run)",
                            out.display()
                        ),
                    ));
                }
                eprintln!("warning: {why} (kept: --keep-going)");
            }
        }
        Command::Merge { shards, out, force } => {
            let (meta, records) = rvlife::output::montecarlo::merge(&shards)?;
            let staging = rvlife::output::Staging::prepare(&out, force)?;
            staging
                .commit(|dir| rvlife::output::montecarlo::write_results(dir, &meta, &records))?;
            say!(
                "rvlife merge: {} shards, {} samples; results in {}",
                shards.len(),
                records.len(),
                out.display()
            );
        }
        Command::Run {
            config,
            out,
            force,
            all,
        } => {
            let cfg = load_config(config.as_deref(), budget)?;
            let model = validated(&cfg)?;
            // The results folder is checked and its temporary directory made before any work.
            let staging = rvlife::output::Staging::prepare(&out, force)?;
            let pb = progress_bar(1);
            let start = std::time::Instant::now();
            let bar = rvlife::study::Progress(|done, total| {
                pb.set_length(total as u64);
                pb.set_position(done as u64);
            });
            let notices = rvlife::study::Notices(|line: &str| {
                pb.set_message("life search");
                pb.suspend(|| eprintln!("{line}"));
            });
            let study = rvlife::study::Executor::new(&model)
                .observe(&bar)
                .observe(&notices)
                .run()?;
            pb.set_message("writing");
            staging.commit(|dir| rvlife::output::write_files(&study, dir))?;
            pb.finish_and_clear();
            let s = study.summary();
            say!(
                "rvlife study: i_H = {:.2}, {} stages, {} wear-rate evaluations, {:.2} s; results in {}",
                s.ratio,
                s.stages.len(),
                s.wear_rate_evaluations,
                start.elapsed().as_secs_f64(),
                out.display()
            );
            say!("{}", study.verdict());
            print_stage_table(&s.stages);
            if all {
                print_all_quantities(&s.stages);
            }
            if let Some(p) = &s.paper_comparison {
                say!(
                    "against the paper: STE {:.4} arcmin per 10 um of the worn profile's largest \
                     depth; a uniform 10 um offset (the paper's assumption) {:.4}; the paper's \
                     rigid Adams model {:.4} at 10 um",
                    p.ste_per_10um_arcmin,
                    p.uniform_offset_per_10um_arcmin,
                    p.paper_ste_at_10um_arcmin
                );
            }
            if let Some(l) = &s.validity_limit {
                say!(
                    "the model leaves its validity at {:.0} h ({:.2} um of wear): {}; the stages \
                     from there on are not reported",
                    l.hours,
                    l.max_wear_um,
                    l.reason
                );
            }
        }
        Command::Profile {
            config,
            out: None,
            json: true,
            points_per_tooth,
            nominal,
            wear,
            ..
        } => {
            let model = validated(&load_config(config.as_deref(), budget)?)?;
            let pb = spinner("wear");
            let points = rvlife::api::profile_points(
                &model,
                wear.get(),
                nominal,
                points_per_tooth.unwrap_or(0),
                Spelling::Cli,
                &progress_to(&pb),
            );
            pb.finish_and_clear();
            print_json(&points?)?;
        }
        Command::Profile {
            config,
            out,
            nominal,
            force,
            wear,
            ..
        } => {
            let out = out.expect("--out or --json");
            let format = ProfileFormat::from_path(&out)?;
            rvlife::output::check_output_file(&out, force)?;
            let model = validated(&load_config(config.as_deref(), budget)?)?;
            let profile = profile_for(&model, &wear, nominal)?;
            // Written beside, then renamed: no half-written file, none left on failure.
            rvlife::output::write_file_atomically(&out, force, |tmp| {
                write_profile(&profile, tmp, format)
            })?;
            eprintln!("wrote {}", out.display());
        }
        Command::Contact {
            config,
            crank_deg,
            torque_nm,
            json,
            wear,
        } => {
            let model = validated(&load_config(config.as_deref(), budget)?)?;
            let pb = spinner("wear");
            let v = rvlife::api::contact(
                &model,
                wear.get(),
                crank_deg,
                torque_nm,
                Spelling::Cli,
                &progress_to(&pb),
            );
            pb.finish_and_clear();
            let r = v?;
            if json {
                print_json(&r)?;
            } else {
                say!(
                    "crank {crank_deg} deg, output torque {torque_nm} N m ({} support): twist {:.5} arcmin (first contact {:.5}), max force {:.1} N, max pressure {:.1} MPa, residual {:.1e}",
                    r.support,
                    r.twist_arcmin,
                    r.first_contact_arcmin,
                    r.max_force_n,
                    r.max_pressure_mpa,
                    r.residual
                );
                for (i, d) in r.discs.iter().enumerate() {
                    say!(
                        "disc {}: pin moment {:.2} N m, translation ({:.3}, {:.3}) um, {} pins in contact",
                        i + 1,
                        d.pin_moment_nm,
                        d.translation_um[0],
                        d.translation_um[1],
                        d.pins_in_contact
                    );
                    say!(
                        "{:>4} {:>10} {:>10} {:>10} {:>10} {:>10}",
                        "pin",
                        "mesh_deg",
                        "gap_um",
                        "force_N",
                        "b_um",
                        "p0_MPa"
                    );
                    for p in d.pins.iter().filter(|p| p.force_n > 0.0) {
                        // The pin number unpadded, as the JSON value it once was printed from.
                        say!(
                            "{} {:>10.3} {:>10.4} {:>10.2} {:>10.3} {:>10.1}",
                            p.pin,
                            p.mesh_angle_deg,
                            p.gap_um,
                            p.force_n,
                            p.half_width_um,
                            p.max_pressure_mpa
                        );
                    }
                }
            }
        }
        Command::Te {
            config,
            torque_nm,
            json,
            wear,
        } => {
            let model = validated(&load_config(config.as_deref(), budget)?)?;
            let pb = busy("static TE");
            let v = rvlife::api::te(&model, wear.get(), torque_nm, Spelling::Cli, &|_, _| {});
            pb.finish_and_clear();
            let r = v?;
            if json {
                print_json(&r)?;
            } else {
                say!(
                    "STE mean {:.5} arcmin, peak-to-peak {:.5} arcmin; angular TE {:.5} arcmin over an output revolution; backlash {:.5} arcmin (largest {:.5}); lost motion {:.5} arcmin (+-{:.1} N m)",
                    r.te_mean_arcmin,
                    r.te_peak_to_peak_arcmin,
                    r.angular_te_arcmin,
                    r.backlash_arcmin,
                    r.backlash_max_arcmin,
                    r.lost_motion_arcmin,
                    r.measuring_torque_nm
                );
                if let (Some(t), Some(l)) = (torque_nm, &r.loaded) {
                    say!(
                        "loaded TE at {t} N m: mean {:.5} arcmin, peak-to-peak {:.5} arcmin",
                        l.loaded_te_mean_arcmin,
                        l.loaded_te_peak_to_peak_arcmin
                    );
                }
            }
        }
        Command::Efficiency {
            config,
            speeds_rpm,
            torques_nm,
            temperatures_c,
            out,
            force,
            json,
            wear,
        } => {
            let cfg = load_config(config.as_deref(), budget)?;
            let model = validated(&cfg)?;
            efficiency::check_out(out.as_deref(), force)?;
            let pb = busy("efficiency");
            let r = rvlife::api::efficiency(
                &model,
                wear.get(),
                speeds_rpm.as_deref(),
                torques_nm.as_deref(),
                temperatures_c.as_deref(),
                Spelling::Cli,
                &|_, _| {},
            );
            pb.finish_and_clear();
            let r = r?;
            if let Some(path) = &out {
                rvlife::output::efficiency::write_csv(path, &r.points)?;
            }
            if json {
                print_json(&r)?;
            } else {
                efficiency::print(&r);
            }
        }
        Command::Hysteresis {
            config,
            crank_deg,
            levels,
            json,
            sensitivity,
            wear,
        } => {
            let cfg = load_config(config.as_deref(), budget)?;
            let model = validated(&cfg)?;
            if let Some(f) = sensitivity {
                rvlife::sensitivity::check_fraction(f, &model)?;
            }
            let pb = busy("hysteresis");
            let v = rvlife::api::hysteresis_curve(
                &model,
                wear.get(),
                crank_deg,
                levels as usize,
                Spelling::Cli,
                &|_, _| {},
            );
            let table = sensitivity
                .map(|f| rvlife::sensitivity::sensitivity(&cfg, f))
                .transpose();
            pb.finish_and_clear();
            let r = v?;
            let table = table?;
            if json {
                let mut j = to_json(&r)?;
                if let (Some(t), Some(o)) = (&table, j.as_object_mut()) {
                    o.insert("sensitivity".into(), to_json(t)?);
                }
                print_json(&j)?;
            } else {
                let (a, b) = (&r.mesh_cycle_mean, &r.at_crank_angle);
                say!(
                    "mean over a mesh cycle: backlash {:.5} arcmin, lost motion {:.5} arcmin (+-{:.1} N m), hysteresis loss {:.5} arcmin, torsional stiffness {:.1} N m/arcmin (b/a)",
                    a.backlash_arcmin,
                    a.lost_motion_arcmin,
                    r.measuring_torque_fraction * r.rated_torque_nm,
                    a.hysteresis_loss_arcmin,
                    a.torsional_stiffness_nm_per_arcmin
                );
                say!(
                    "at crank {crank_deg} deg: backlash {:.5} arcmin, lost motion {:.5} arcmin, torsional stiffness {:.1} N m/arcmin",
                    b.backlash_arcmin, b.lost_motion_arcmin, b.torsional_stiffness_nm_per_arcmin
                );
                if !r.twist_shares.is_empty() {
                    let parts: Vec<String> = r
                        .twist_shares
                        .iter()
                        .map(|s| format!("{} {:.1} %", s.part, 100.0 * s.share))
                        .collect();
                    say!(
                        "share of the elastic twist at {} N m: {}",
                        r.rated_torque_nm,
                        parts.join(", ")
                    );
                }
                if let Some(t) = &table {
                    print_sensitivity(t);
                }
                say!("{:>12} {:>14}", "torque_N_m", "twist_arcmin");
                for (t, x) in a.torque_nm.iter().zip(&a.twist_arcmin) {
                    say!("{t:>12.3} {x:>14.6}");
                }
            }
        }
        Command::Dynamics {
            config,
            load,
            torque_nm,
            out,
            force,
            pin_forces,
            json,
            disc,
            wear,
        } => {
            let cfg = load_config(config.as_deref(), budget)?;
            let opts = rvlife::api::DynamicsOptions {
                load,
                torque_nm,
                disc,
            };
            let model = rvlife::api::dynamics_model(&cfg, &opts, Spelling::Cli)?;
            let staging = match &out {
                Some(dir) => Some(rvlife::output::Staging::prepare(dir, force)?),
                None => None,
            };
            let start = std::time::Instant::now();
            let pb = busy("simulating");
            let res =
                rvlife::api::dynamics(&model, wear.get(), pin_forces, Spelling::Cli, &|_, _| {});
            pb.finish_and_clear();
            let res = res?;
            let mut v = to_json(&res.summary)?;
            let wall = start.elapsed().as_secs_f64();
            if let Some(staging) = staging {
                staging.commit(|dir| rvlife::output::write_dynamics_files(&res, dir))?;
            }
            let s = &res.summary;
            v["wall_time_s"] = json!(wall);
            if json {
                say!("{v}");
            } else {
                say!(
                    "DTE over {:.3}-{:.3} s: mean {:.4} arcmin, peak-to-peak {:.4} arcmin, RMS {:.4} arcmin",
                    s.window_start_s, s.window_end_s, s.te_mean_arcmin, s.te_peak_to_peak_arcmin, s.te_rms_arcmin
                );
                say!(
                    "output speed {:.4} deg/s (input / i_H: {:.4}); max pin force {:.1} N; {} steps of {}, {} evaluations and {} Jacobian columns, {:.2} s",
                    s.output_speed_deg_s,
                    s.nominal_output_speed_deg_s,
                    s.max_pin_force_n,
                    s.steps,
                    s.integrator,
                    s.rhs_evaluations,
                    s.jacobian_columns,
                    wall
                );
                if let Some(why) = &s.integrator_fallback {
                    eprintln!("warning: esdirk34 failed ({why}); the run was repeated with tsit45");
                }
                if s.disc_modes > 0 {
                    say!("flexible discs: {} elastic modes each", s.disc_modes);
                }
                if let Some(dir) = &out {
                    say!("results in {}", dir.display());
                }
            }
        }
        Command::Sweep {
            config,
            vary,
            set,
            out,
            force,
        } => sweep::sweep(config.as_deref(), budget, &vary, &set, &out, force)?,
        Command::Optimize {
            config,
            vary,
            objective,
            constraint,
            evaluations,
            seed,
            out,
            force,
        } => optimize::optimize(
            config.as_deref(),
            budget,
            &vary,
            &objective,
            &constraint,
            rvlife::optimize::Settings { evaluations, seed },
            &out,
            force,
        )?,
        Command::Calibrate {
            config,
            target_wear_um,
            measured,
            catalogue_stiffness_nm_per_arcmin,
            fit_running_in,
            out,
            force,
        } => calibrate::run(
            config.as_deref(),
            budget,
            target_wear_um,
            measured.as_deref(),
            catalogue_stiffness_nm_per_arcmin,
            fit_running_in,
            out.as_deref(),
            force,
        )?,
    }
    Ok(())
}

fn main() -> ExitCode {
    // A closed pipe (`rvlife te --json | head -1`) ends the process quietly, as it ends `cat`,
    // instead of making the next print panic: the default action of SIGPIPE, which the Rust
    // runtime sets to ignore.
    #[cfg(unix)]
    // SAFETY: restores the default disposition of one signal before any thread is started.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    // glibc raises its mmap threshold whenever a large block is freed, after which the
    // FE solver's 20 MB right-hand-side blocks come from the per-thread heaps and stay there
    // when freed: the built-in study then peaks at 350 MB resident for a 145 MB heap. A fixed
    // 1 MB threshold (mallopt(3), M_MMAP_THRESHOLD) maps every large block and returns it on
    // free: 165 MB. The heaps grow and shrink by 64 MB at a time (M_TOP_PAD; glibc's default
    // is 128 kB): the analyses' many smaller buffers then reuse pages already mapped instead
    // of faulting fresh zeroed pages in after every trim (the built-in study spends a third
    // of the system time it had in page faults; peak 150 MB).
    #[cfg(all(target_os = "linux", target_env = "gnu"))]
    // SAFETY: sets allocator parameters before any thread is started.
    unsafe {
        libc::mallopt(libc::M_MMAP_THRESHOLD, 1 << 20);
        libc::mallopt(libc::M_TOP_PAD, 64 << 20);
    }
    // SIGINT, SIGTERM and SIGHUP remove this run's temporary outputs before it ends (exit 130,
    // as a shell reports an interrupted command).
    let _ = ctrlc::set_handler(|| {
        // A design search stops at the next candidate and writes what it has.
        if rvlife::output::take_signal() {
            eprintln!("stopping after this candidate (again to end at once)");
            return;
        }
        rvlife::output::remove_pending();
        std::process::exit(130);
    });
    let cli = Cli::from_arg_matches(&declared::cli().get_matches()).unwrap_or_else(|e| e.exit());
    let result = run(cli);
    // A signal arrived: its handler is removing the temporary outputs and ends the process
    // with 130; an error met meanwhile (a file removed under a writer) is not reported.
    while rvlife::output::interrupted() {
        std::thread::park();
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            if e.is_input_error() {
                ExitCode::from(2)
            } else {
                ExitCode::from(1)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::unsigned_zeros;

    #[test]
    fn zeros_lose_their_round_off_sign_and_nothing_else_does() {
        assert_eq!(
            unsigned_zeros("mean -0.00000 arcmin, -0 N m, [-0.000, -0.001], 1e-0, x-0.0"),
            "mean 0.00000 arcmin, 0 N m, [0.000, -0.001], 1e-0, x-0.0"
        );
        assert_eq!(unsigned_zeros("-0.0e0 -10 -0.5 -00"), "-0.0e0 -10 -0.5 00");
        assert_eq!(unsigned_zeros("     -0.000  -1.6"), "      0.000  -1.6");
    }
}
