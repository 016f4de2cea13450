//! `framedyn`: scenes in, trajectories out.
//!
//! ```text
//! framedyn run [SCENE] [--output PATH] [--format csv|npz] [--quiet] [--no-space-check]
//! framedyn scenes                # list the embedded example scenes
//! framedyn scenes show NAME      # print one (a starting point for your own)
//! framedyn validate SCENE        # check a scene without running it
//! framedyn methods               # the integration methods (the registry)
//! framedyn sweep SCENE --table members.csv|npz [--output results.npz] [--keep all|final] [--samples K] [--threads N] [--no-space-check]
//! framedyn lyapunov SCENE [--exponents K|all] [--two-trajectory] [--output RUNNING.csv] …   # see [`analysis`]
//! framedyn sali SCENE [--threshold X] [--seed S] [--eps E] [--fourth-order] [--table T [-o MAP.csv]]       # see [`analysis`]
//! framedyn megno SCENE [--seed S] [--eps E] [--fourth-order] [--output RUNNING.csv] [--table T]        # see [`analysis`]
//! framedyn section SCENE [--event NAME | --plane N | --column NAME --value V] [--direction D] [--output SECTION.csv]
//! ```
//!
//! `SCENE` is a TOML or JSON file, or the name of an embedded scene; without
//! it `run` uses the default scene (a gyroscope on S² crossing the pole).
//!
//! A scene with `[[events]]` also writes its located events to
//! `STEM.events.csv` beside the output (`traj.csv` or `traj.npz` →
//! `traj.events.csv`): header `event,rising,terminal` then the record's
//! columns, one line per event in time order. A terminal event ends the run
//! normally (exit code 0) at the event's state.
//!
//! `sweep` runs one member per row of the table (columns named by dotted
//! scene fields: `initial.r`, `potential.kappa`, `body.J.0.1`, …) in
//! parallel and writes every member's records, status and summary to one
//! `.npz`, streamed while the members run (layout in [`sweep::EnsembleWriter`]); a member that is invalid or
//! fails is recorded as such and does not stop the others (exit code 0;
//! the summary counts them).
//!
//! Outputs follow one policy ([`target`]): symbolic links are written
//! through; directories, devices, FIFOs, sockets and read-only files are
//! refused (exit 5); files appear complete or not at all (temporary file and
//! rename). A run that fails or is interrupted never replaces the output:
//! what it computed goes to `STEM.partial.EXT` beside it (a CSV ending with
//! a `# partial: …` line, an `.npz` with `stop` = `partial: …`), the summary
//! names that file, and the exit code says why.
//!
//! Disk space ([`space`]): when the record count is known before the run
//! (fixed steps, `output.times` or `output.samples`; a sweep: its members'),
//! `run` and `sweep` estimate the output's size; above 10 GB they say so,
//! and an output that cannot fit in the free space of the file system that
//! will hold it is refused before the run starts (exit 5, nothing written;
//! the message names the estimate, the free space, the directory and the
//! settings that make the output smaller). `--no-space-check` runs anyway.
//!
//! Signals ([`signals`]): SIGINT (Ctrl-C), SIGTERM and SIGHUP stop a run or
//! a sweep, keep the part computed as a partial result, remove temporary
//! files, and exit with 128 + the signal's number; a second signal exits at
//! once.
//!
//! Exit codes: 0 success; 2 bad command line; 3 invalid scene or table;
//! 4 integration failure (the partial result holds the records up to the
//! last good state); 5 I/O error, refused output path, or not enough free
//! space for the output (nothing is written); 6 finished, output complete, but the quality check of the
//! summary failed (energy drift or constraint defect over the scene's
//! `[quality]` limits, or a non-finite energy or defect); 129, 130, 143
//! stopped by SIGHUP, SIGINT, SIGTERM (the partial result holds the part
//! computed so far).
#![deny(missing_docs)]

pub mod analysis;
pub mod output;
pub mod signals;
pub mod space;
pub mod sweep;
pub mod target;

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::Ordering;
use std::time::Instant;

use clap::{Parser, Subcommand, ValueEnum};
use framedyn::scenes::{self, Format, RunError, Scene, SceneError, SceneStop, EXAMPLES};

/// Exit code: invalid scene.
const EXIT_INVALID: u8 = 3;
/// Exit code: integration failure, partial output kept.
const EXIT_INTEGRATION: u8 = 4;
/// Exit code: I/O error.
const EXIT_IO: u8 = 5;
/// Exit code: the run finished and its output is complete, but the quality
/// check of its summary failed (energy drift, defect, non-finite values).
const EXIT_QUALITY: u8 = 6;

#[derive(Parser, Debug)]
#[command(name = "framedyn", version, about = "Structured particles on curved manifolds: scenes in, trajectories out")]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a scene (file or embedded name; default: the pole-crossing S² gyroscope) and write its trajectory.
    Run {
        /// Scene file (.toml or .json) or embedded scene name.
        scene: Option<String>,
        /// Output path (overrides `[output] path`).
        #[arg(short, long)]
        output: Option<PathBuf>,
        /// Output format (overrides `[output] format` and the extension).
        #[arg(short, long, value_enum)]
        format: Option<FormatArg>,
        /// No progress bar and no summary.
        #[arg(short, long)]
        quiet: bool,
        /// Run even if the estimated output exceeds the free space of its file system.
        #[arg(long)]
        no_space_check: bool,
    },
    /// List the embedded example scenes, or print one with `show NAME`.
    Scenes {
        #[command(subcommand)]
        action: Option<ScenesAction>,
    },
    /// Check a scene without running it.
    Validate {
        /// Scene file or embedded scene name.
        scene: String,
    },
    /// List the integration methods a scene's `[method] name` can take.
    Methods,
    /// Run one member per row of a table (columns: dotted scene fields such as `initial.r`) and write all of them to one .npz.
    Sweep {
        /// Scene file (.toml or .json) or embedded scene name: the base of every member.
        scene: String,
        /// The members: CSV with a header of dotted field names, or .npz of 1-D arrays named by field.
        #[arg(short, long)]
        table: PathBuf,
        /// Output .npz (default: sweep.npz).
        #[arg(short, long, default_value = "sweep.npz")]
        output: PathBuf,
        /// Keep every record (`all`) or each member's final record only (`final`).
        #[arg(long, value_enum, default_value = "all")]
        keep: KeepArg,
        /// Keep K equally spaced records per member (K ≥ 2; replaces the scene's output times).
        #[arg(long, conflicts_with = "keep")]
        samples: Option<u64>,
        /// Worker threads (default: one per core; at most 1024, and at most one per core unless --oversubscribe).
        #[arg(long)]
        threads: Option<usize>,
        /// Allow more worker threads than cores.
        #[arg(long)]
        oversubscribe: bool,
        /// No progress bar and no summary.
        #[arg(short, long)]
        quiet: bool,
        /// Run even if the estimated output exceeds the free space of its file system.
        #[arg(long)]
        no_space_check: bool,
    },
    /// Lyapunov exponents of a scene's trajectory (its method and steps, fixed or error-controlled; tangent map of each step).
    Lyapunov {
        /// Scene file (.toml or .json) or embedded scene name.
        scene: String,
        /// Number of exponents (largest first), or `all` (the state group's dimension; the phase space's with --phase-space).
        #[arg(short = 'k', long, default_value = "1")]
        exponents: String,
        /// The spectrum of the phase space: tangent vectors modulo the parallel frame's gauge directions, so that no exponent is the gauge's zero and a Hamiltonian model's 2n exponents pair.
        #[arg(long)]
        phase_space: bool,
        /// Steps between re-orthonormalisations of the tangent vectors.
        #[arg(long, default_value_t = 10)]
        every: usize,
        /// Time at the start left out of the averages.
        #[arg(long, default_value_t = 0.0)]
        transient: f64,
        /// Batches of the batch-means standard error.
        #[arg(long, default_value_t = 10)]
        batches: usize,
        #[command(flatten)]
        tangent: analysis::TangentArgs,
        /// Also estimate the maximal exponent from two nearby trajectories.
        #[arg(long)]
        two_trajectory: bool,
        /// Write the running estimates (t, lambda_1, …) to this CSV.
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// SALI, the Smaller Alignment Index, of a scene's trajectory: a fast chaos indicator (its method and steps, fixed or error-controlled).
    Sali {
        /// Scene file (.toml or .json) or embedded scene name.
        scene: String,
        /// The SALI below which the orbit is called chaotic (the run stops there), 0 < threshold < 1.
        #[arg(long, default_value_t = 1e-8)]
        threshold: f64,
        #[command(flatten)]
        tangent: analysis::TangentArgs,
        #[command(flatten)]
        map: analysis::MapArgs,
        /// With --table: write the map to this CSV (default: standard output).
        #[arg(short, long, requires = "table")]
        output: Option<PathBuf>,
    },
    /// GALI_k, the Generalised Alignment Index of k tangent vectors, of a scene's trajectory (its method and steps, fixed or error-controlled).
    Gali {
        /// Scene file (.toml or .json) or embedded scene name.
        scene: String,
        /// Number of tangent vectors, 2 … the phase space's dimension (the state group's with --stored-state), or `all`.
        #[arg(short = 'k', default_value = "2")]
        k: String,
        /// The GALI below which the orbit is called chaotic (the run stops there), 1e-300 ≤ threshold < 1.
        #[arg(long, default_value_t = 1e-12)]
        threshold: f64,
        /// Measure on the stored state instead of the phase space: keep the deviation vectors' components along the parallel frame's gauge directions.
        #[arg(long)]
        stored_state: bool,
        #[command(flatten)]
        tangent: analysis::TangentArgs,
        #[command(flatten)]
        map: analysis::MapArgs,
        /// Write the running values (t, log10_gali) to this CSV; with --table, the map (default: standard output).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// MEGNO of a scene's trajectory: a fast chaos indicator from one tangent vector (its method and steps, fixed or error-controlled).
    Megno {
        /// Scene file (.toml or .json) or embedded scene name.
        scene: String,
        #[command(flatten)]
        tangent: analysis::TangentArgs,
        #[command(flatten)]
        map: analysis::MapArgs,
        /// Write the running values (t, megno, mean) to this CSV; with --table, the map (default: standard output).
        #[arg(short, long)]
        output: Option<PathBuf>,
    },
    /// Poincaré section of a scene's trajectory: its crossings of a plane, a column value or an [[events]] entry, as CSV.
    Section {
        /// Scene file (.toml or .json) or embedded scene name.
        scene: String,
        /// An [[events]] entry of the scene, by name (default: its only one).
        #[arg(long)]
        event: Option<String>,
        /// A plane n·x = offset: the normal's embedding components, comma-separated.
        #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
        plane: Option<Vec<f64>>,
        /// The plane's offset (default 0).
        #[arg(long, allow_hyphen_values = true)]
        offset: Option<f64>,
        /// A record column (`r`, `phi`, `energy`, …) …
        #[arg(long)]
        column: Option<String>,
        /// … and the value it crosses.
        #[arg(long, allow_hyphen_values = true)]
        value: Option<f64>,
        /// Crossing direction (default: the event's, or either).
        #[arg(long, value_enum)]
        direction: Option<DirectionArg>,
        /// Output CSV.
        #[arg(short, long, default_value = "section.csv")]
        output: PathBuf,
    },
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum DirectionArg {
    Rising,
    Falling,
    Either,
}

#[derive(ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
enum KeepArg {
    All,
    Final,
}

/// The method list of `framedyn methods` and of `framedyn run --help`,
/// from the registry: name, order, stepping, what the method needs.
fn methods_text() -> String {
    use framedyn::method::METHODS;
    let width = METHODS.iter().map(|m| m.name.len()).max().unwrap_or(0);
    let mut out = String::new();
    for m in METHODS {
        let order = match m.embedded_order {
            Some(q) => format!("{}({q})", m.order),
            None => m.order.to_string(),
        };
        let stepping = if m.adaptive { "h or rtol/atol" } else { "h" };
        out.push_str(&format!("  {:width$}  {:<28} order {:<5} {:<14} {}\n", m.name, m.display, order, stepping, m.needs.describe()));
    }
    out
}

#[derive(Subcommand, Debug)]
enum ScenesAction {
    /// Print an embedded scene as TOML.
    Show {
        /// The scene's name (see `framedyn scenes`).
        name: String,
    },
}

#[derive(ValueEnum, Clone, Copy, Debug)]
enum FormatArg {
    Csv,
    Npz,
}

/// A count option that also takes `all` (`None`): `--exponents`, `-k`.
/// The range is checked by the analysis, which knows the state's dimension.
fn count_or_all(text: &str, option: &str, allowed: &str) -> Result<Option<usize>, (u8, String)> {
    match text {
        "all" => Ok(None),
        k => k.parse::<usize>().map(Some).map_err(|_| (2, format!("invalid {option} = {k:?}: must be {allowed} or `all`"))),
    }
}

/// Reads a scene from a file, or an embedded one by name.
fn load(scene: &str) -> Result<(Scene, String), (u8, String)> {
    let path = std::path::Path::new(scene);
    if path.exists() {
        let bytes = std::fs::read(path).map_err(|e| (EXIT_IO, format!("cannot read {scene}: {e}")))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            (EXIT_INVALID, format!("{scene}: invalid scene: not UTF-8 text (invalid byte at offset {})", e.utf8_error().valid_up_to()))
        })?;
        let is_json = path.extension().is_some_and(|e| e.eq_ignore_ascii_case("json"));
        let parsed = if is_json { Scene::from_json_str(&text) } else { Scene::from_str_auto(&text) };
        parsed.map(|s| (s, scene.to_string())).map_err(|e| (EXIT_INVALID, format!("{scene}: invalid scene: {e}")))
    } else {
        match scenes::example(scene) {
            Ok(s) => Ok((s, format!("embedded scene {scene}"))),
            Err(SceneError::UnknownScene { available, .. }) => Err((
                EXIT_INVALID,
                format!("no scene file `{scene}` and no embedded scene of that name; embedded scenes: {available}"),
            )),
            Err(e) => Err((EXIT_INVALID, format!("embedded scene {scene}: {e}"))),
        }
    }
}

/// Runs the command line `args` (the first item is the program name, as in
/// `std::env::args_os`) and returns the process exit code (see the crate
/// documentation). Used by the `framedyn` binary and by the Python module's
/// console script; never panics on bad input.
pub fn main_with_args<I, T>(args: I) -> i32
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    use clap::{CommandFactory, FromArgMatches};
    let after = format!("Methods ([method] name in a scene; `framedyn methods`):\n{}", methods_text());
    let command = Cli::command().mut_subcommand("run", |c| c.after_long_help(after.clone())).mut_subcommand("validate", |c| c.after_long_help(after.clone()));
    let cli = match command.try_get_matches_from(args).and_then(|m| Cli::from_arg_matches(&m)) {
        Ok(c) => c,
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() { 2 } else { 0 };
        }
    };
    match run(cli) {
        Ok(()) => 0,
        Err((code, msg)) => {
            if !msg.is_empty() {
                eprintln!("framedyn: {msg}");
            }
            i32::from(code)
        }
    }
}

fn run(cli: Cli) -> Result<(), (u8, String)> {
    match cli.command {
        Command::Scenes { action: None } => {
            let width = EXAMPLES.iter().map(|(n, _)| n.len()).max().unwrap_or(0);
            for (name, _) in EXAMPLES {
                let desc = scenes::example(name).ok().and_then(|s| s.description).unwrap_or_default();
                let marker = if *name == scenes::DEFAULT_SCENE { " (default)" } else { "" };
                println!("{name:width$}  {desc}{marker}");
            }
            Ok(())
        }
        Command::Scenes { action: Some(ScenesAction::Show { name }) } => match EXAMPLES.iter().find(|(n, _)| *n == name) {
            Some((_, text)) => {
                print!("{text}");
                Ok(())
            }
            None => Err((
                EXIT_INVALID,
                format!("no embedded scene `{name}`; available: {}", EXAMPLES.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", ")),
            )),
        },
        Command::Methods => {
            print!("{}", methods_text());
            Ok(())
        }
        Command::Validate { scene } => {
            let (s, origin) = load(&scene)?;
            s.validate().map_err(|e| (EXIT_INVALID, format!("{origin}: invalid scene: {e}")))?;
            println!("{origin}: valid");
            Ok(())
        }
        Command::Sweep { scene, table, output, keep, samples, threads, oversubscribe, quiet, no_space_check } => {
            let (s, origin) = load(&scene)?;
            let keep = match (samples, keep) {
                (Some(k), _) => scenes::Keep::Samples(k),
                (None, KeepArg::Final) => scenes::Keep::Final,
                (None, KeepArg::All) => scenes::Keep::All,
            };
            run_sweep(s, &origin, &table, &output, keep, (threads, oversubscribe), (quiet, !no_space_check))
        }
        Command::Lyapunov { scene, exponents, phase_space, every, transient, batches, tangent, two_trajectory, output } => {
            let (s, origin) = load(&scene)?;
            let exponents = count_or_all(&exponents, "--exponents", "a positive integer")?;
            let args = analysis::LyapunovArgs { exponents, every, transient, batches, tangent, two_trajectory, phase_space, output };
            analysis::lyapunov(&s, &origin, &args)
        }
        Command::Sali { scene, threshold, tangent, map, output } => {
            let (s, origin) = load(&scene)?;
            analysis::sali(&s, &origin, &analysis::SaliArgs { threshold, tangent, map, output })
        }
        Command::Gali { scene, k, threshold, stored_state, tangent, map, output } => {
            let (s, origin) = load(&scene)?;
            let k = count_or_all(&k, "-k", "an integer ≥ 2")?;
            analysis::gali(&s, &origin, &analysis::GaliArgs { k, threshold, quotient: !stored_state, tangent, map, output })
        }
        Command::Megno { scene, tangent, map, output } => {
            let (s, origin) = load(&scene)?;
            analysis::megno(&s, &origin, &analysis::MegnoArgs { tangent, map, output })
        }
        Command::Section { scene, event, plane, offset, column, value, direction, output } => {
            let (s, origin) = load(&scene)?;
            let direction = direction.map(|d| match d {
                DirectionArg::Rising => framedyn::scenes::EventDirection::Rising,
                DirectionArg::Falling => framedyn::scenes::EventDirection::Falling,
                DirectionArg::Either => framedyn::scenes::EventDirection::Either,
            });
            analysis::section(&s, &origin, &analysis::SectionArgs { event, plane, offset, column, value, direction, output })
        }
        Command::Run { scene, output, format, quiet, no_space_check } => {
            let name = scene.unwrap_or_else(|| scenes::DEFAULT_SCENE.to_string());
            let (s, origin) = load(&name)?;
            run_scene(s, &origin, output, format, (quiet, !no_space_check))
        }
    }
}

fn run_sweep(
    scene: Scene,
    origin: &str,
    table: &std::path::Path,
    output: &std::path::Path,
    keep: scenes::Keep,
    (threads, oversubscribe): (Option<usize>, bool),
    (quiet, check_space): (bool, bool),
) -> Result<(), (u8, String)> {
    // Built once: the validation of the base scene, and its columns and
    // record bound for the size estimate and the block size.
    let sim = scene.build().map_err(|e| (EXIT_INVALID, format!("{origin}: invalid scene: {e}")))?;
    let table = sweep::read_table(table).map_err(|e| match e {
        sweep::TableError::Io(m) => (EXIT_IO, m),
        sweep::TableError::Invalid(m) => (EXIT_INVALID, m),
    })?;
    // The output path is checked before the members run, and so is the
    // room for what they can write.
    let target = target::Target::resolve(output).map_err(|e| (EXIT_IO, format!("cannot write the output: {e}")))?;
    let estimate = sweep::estimate(&scene, &sim, &table, keep);
    announce_or_refuse(
        Some(&estimate),
        &target,
        check_space,
        "keep fewer records with --keep final or --samples K, or fewer columns with output.quantities, or write elsewhere with --output",
    )?;
    let cancel = signals::arm();
    let n = table.len() as u64;
    let bar = (!quiet && std::io::stderr().is_terminal()).then(|| {
        let b = indicatif::ProgressBar::with_draw_target(Some(n), indicatif::ProgressDrawTarget::stderr());
        b.set_style(
            indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} members (eta {eta})")
                .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
        );
        b
    });
    let opts = scenes::EnsembleOptions { keep, threads, oversubscribe };
    let started = Instant::now();
    // Streamed: each block of members goes to the output's raw temporary
    // file as soon as it is done (sweep::EnsembleWriter).
    let mut writer = sweep::EnsembleWriter::create_at(target).map_err(|e| (EXIT_IO, format!("cannot write the output {}: {e} (no output written)", output.display())))?;
    let mut write_error = None;
    scenes::run_ensemble_blocks(
        &scene,
        &table,
        &opts,
        None,
        cancel,
        &|k| {
            if let Some(b) = &bar {
                b.set_position(k as u64);
            }
        },
        sweep::block_size(&sim, keep),
        &mut |_, block| match writer.push(&block) {
            Ok(()) => std::ops::ControlFlow::Continue(()),
            Err(e) => {
                write_error = Some(e);
                std::ops::ControlFlow::Break(())
            }
        },
    )
    .map_err(|e| (EXIT_INVALID, format!("{origin}: {e}")))?;
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    if let Some(e) = write_error {
        return Err((EXIT_IO, format!("writing {}: {e} (no output written)", output.display())));
    }
    let interrupted = cancel.load(Ordering::SeqCst);
    let members = writer.members();
    let report = [
        format!("scene:           {origin}"),
        format!("members:         {} ({})", members.len(), sweep::status_counts(members)),
        match members.iter().filter(|m| m.summary.as_ref().is_some_and(|s| !s.warnings.is_empty())).count() {
            0 => "quality:         ok".to_string(),
            k => format!("quality:         {k} members with warnings (`warnings` in the output)"),
        },
        match members.iter().enumerate().find(|(_, m)| m.error.is_some()) {
            Some((i, m)) => format!("first failure:   member {i}: {}", m.error.as_deref().unwrap_or("")),
            None => String::new(),
        },
    ];
    let records = writer.records();
    let written = writer.finish(&table, interrupted).map_err(|e| (EXIT_IO, format!("writing {}: {e} (no output written)", output.display())))?;
    if !quiet {
        for line in report.iter().filter(|l| !l.is_empty()) {
            println!("{line}");
        }
        println!("wall time:       {:.3} s", started.elapsed().as_secs_f64());
        println!("output:          {} ({records} records{})", written.display(), if interrupted { ", partial" } else { "" });
    }
    if interrupted {
        let (code, name) = signals::interruption();
        return Err((
            code,
            format!(
                "interrupted by {name}; {} holds the members computed so far (status `cancelled` for the rest); {} was left as it was",
                written.display(),
                output.display()
            ),
        ));
    }
    Ok(())
}

/// Says before a run when its output could exceed
/// [`space::LARGE_OUTPUT_BYTES`], and refuses it (exit 5, nothing written)
/// when it cannot fit in the free space of the target's file system
/// (unless `check` is off: `--no-space-check`).
fn announce_or_refuse(estimate: Option<&space::OutputEstimate>, target: &target::Target, check: bool, advice: &str) -> Result<(), (u8, String)> {
    let Some(estimate) = estimate else { return Ok(()) };
    if check {
        space::check(estimate, target.directory(), advice).map_err(|e| (EXIT_IO, e.to_string()))?;
    }
    if estimate.is_large() {
        eprintln!("framedyn: note: this run can write {}; {advice}", estimate.describe());
    }
    Ok(())
}

fn run_scene(scene: Scene, origin: &str, output: Option<PathBuf>, format: Option<FormatArg>, (quiet, check_space): (bool, bool)) -> Result<(), (u8, String)> {
    let mut sim = scene.build().map_err(|e| (EXIT_INVALID, format!("{origin}: invalid scene: {e}")))?;
    let path = output.unwrap_or_else(|| PathBuf::from(scene.output_path()));
    let format = match format {
        Some(FormatArg::Csv) => Format::Csv,
        Some(FormatArg::Npz) => Format::Npz,
        None if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("npz")) => Format::Npz,
        None if path.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv")) => Format::Csv,
        None => scene.output_format(),
    };
    let target = target::Target::resolve(&path).map_err(|e| (EXIT_IO, format!("cannot write the output: {e}")))?;
    // A word before a run whose output could fill a disk, and a refusal,
    // before anything is written, of one that cannot fit.
    let estimate = sim.record_bound().map(|records| space::OutputEstimate::new(records, sim.columns().len(), format));
    announce_or_refuse(
        estimate.as_ref(),
        &target,
        check_space,
        "record fewer with output.every, output.samples or output.quantities, or write elsewhere with --output",
    )?;
    let mut sink = output::FileSink::create_at(target, format).map_err(|e| (EXIT_IO, format!("cannot write the output: {e}")))?;
    let cancel = signals::arm();
    let show_bar = !quiet && std::io::stderr().is_terminal();
    let started = Instant::now();
    let mut bar: Option<indicatif::ProgressBar> = None;
    let mut progress = |p: &scenes::Progress| {
        if !show_bar {
            return;
        }
        if bar.is_none() && started.elapsed().as_secs_f64() > 1.0 {
            let b = indicatif::ProgressBar::with_draw_target(Some(1000), indicatif::ProgressDrawTarget::stderr())
                .with_elapsed(started.elapsed());
            b.set_style(
                indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {percent:>3}% t = {msg} (eta {eta})")
                    .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
            );
            bar = Some(b);
        }
        if let Some(b) = &bar {
            b.set_position((p.fraction * 1000.0) as u64);
            b.set_message(format!("{:.4}", p.t));
        }
    };
    let result = sim.run(&mut sink, cancel, &mut progress);
    if let Some(b) = &bar {
        b.finish_and_clear();
    }
    let (summary, err) = match result {
        Ok(s) => (s, None),
        Err(f) => (f.summary, Some(f.error)),
    };
    if let Some(RunError::Io(e)) = &err {
        sink.abort();
        return Err((EXIT_IO, format!("writing {}: {e} (no output written)", path.display())));
    }
    let events = sink.take_events();
    let event_columns = sink.column_names();
    // How the run ended decides where its records go: a complete run onto
    // the target, a failed or interrupted one beside it as a partial result.
    let failure = match (&summary.stop, &err) {
        (_, Some(e @ RunError::Integration(_))) => Some((EXIT_INTEGRATION, e.to_string())),
        (_, Some(e)) => Some((EXIT_IO, e.to_string())),
        (SceneStop::Cancelled, None) => {
            let (code, name) = signals::interruption();
            Some((code, format!("interrupted by {name} at t = {}", summary.t_reached)))
        }
        _ => None,
    };
    let no_output = |e: std::io::Error| (EXIT_IO, format!("writing {}: {e} (no output written)", path.display()));
    let events_target = if sim.events().is_empty() {
        None
    } else if failure.is_some() {
        Some(output::events_path(sink.target().partial().map_err(no_output)?.resolved()))
    } else {
        Some(output::events_path(&path))
    };
    let pending = match &events_target {
        Some(ep) => match output::prepare_events(ep, &event_columns, &events) {
            Ok(p) => Some(p),
            Err(e) => {
                sink.abort();
                return Err(no_output(e));
            }
        },
        None => None,
    };
    let written = match &failure {
        None => sink.finish(&summary.stop.to_string()),
        Some((_, reason)) => sink.finish_partial(reason),
    }
    .map_err(no_output)?;
    let events_written = match pending {
        Some(p) => Some(p.commit().map_err(|e| (EXIT_IO, format!("{} was written, but not its events file: {e}", written.display())))?),
        None => None,
    };
    if !quiet {
        println!("scene:           {origin}");
        println!("{summary}");
        println!(
            "output:          {} ({} records, {}{})",
            written.display(),
            summary.records,
            if format == Format::Npz { "npz" } else { "csv" },
            if failure.is_some() { ", partial" } else { "" }
        );
        if let Some(ep) = &events_written {
            println!("events:          {} ({} events)", ep.display(), events.len());
        }
    }
    match failure {
        None if !summary.warnings.is_empty() => Err((
            EXIT_QUALITY,
            format!(
                "quality check failed ({}); {} holds the complete run, to be used with care",
                summary.warning_texts().join("; "),
                written.display()
            ),
        )),
        None => Ok(()),
        Some((code, reason)) => Err((
            code,
            format!("{reason}; {} holds the {} records computed; {} was left as it was", written.display(), summary.records, path.display()),
        )),
    }
}
