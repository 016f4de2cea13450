//! `framedyn lyapunov` and `framedyn section`: the analyses of
//! [`framedyn::analysis`] on a scene.
//!
//! ```text
//! framedyn lyapunov SCENE [--exponents K|all] [--every N] [--transient T] [--batches B] [--seed S]
//!                         [--eps E] [--fourth-order] [--differenced] [--two-trajectory] [--output RUNNING.csv]
//! framedyn sali SCENE [--threshold X] [--seed S] [--eps E] [--fourth-order] [--differenced]
//!                     [--table MEMBERS.csv|npz [--output MAP.csv] [--threads N] [--oversubscribe]]
//! framedyn megno SCENE [--seed S] [--eps E] [--fourth-order] [--differenced] [--output RUNNING.csv]
//!                      [--table MEMBERS.csv|npz [--output MAP.csv] [--threads N] [--oversubscribe]]
//! framedyn section SCENE [--event NAME | --plane NX,NY,NZ[,NW] [--offset C] | --column NAME --value V]
//!                        [--direction rising|falling|either] [--output SECTION.csv]
//! ```
//!
//! `lyapunov` integrates the scene's trajectory with its method and fixed
//! step `method.h` over its time span, with tangent vectors (the tangent map
//! of each step: exact where the model and the method have it, else — or
//! with `--differenced` — central differences of the step; the summary's
//! `tangent maps:` line says which), and prints the exponents, largest first, with their
//! batch-means standard errors and the spread of the running estimates
//! over the second half of the run; `--output` writes the running
//! estimates (`t,lambda_1,…`). `--two-trajectory` adds the maximal exponent
//! from two nearby trajectories. `sali` carries two tangent vectors the
//! same way and prints the Smaller Alignment Index (Skokos 2001) at the end,
//! its minimum, and the time it fell below `--threshold` (the run stops
//! there: "chaotic"), else "regular". `megno` carries one tangent vector
//! and prints MEGNO (Cincotta & Simó 2000) at the end, its mean `⟨Y⟩` (→ 2
//! on a quasi-periodic orbit, ≈ λ₁t/2 on a chaotic one), twice the slope of
//! `⟨Y⟩` over the second half (an estimate of λ₁) and the vector's
//! finite-time exponent; `--output` writes `t,megno,mean`. With `--table`
//! (the member table of `sweep`: dotted scene fields, CSV or `.npz`),
//! `sali` and `megno` map the indicator over the members in parallel
//! ([`framedyn::analysis::chaos_map`]) and write one CSV line per member to
//! `--output` (else to standard output): the table's columns, the
//! indicator's columns (`sali,sali_min,chaotic_at,sali_steps` or
//! `megno,megno_mean,megno_slope,lyapunov,megno_steps`; NaN where it
//! failed), `status` and `error`. `section` writes the crossings of a
//! section — an `[[events]]` entry of the scene (`--event NAME`, or the
//! scene's only one), or one given by the options — as CSV: header
//! `rising,t,…` (every record column), one line per crossing.
//!
//! Exit codes as for `run`: 2 bad options (named with their allowed range),
//! 3 invalid or unsuitable scene (an adaptive step, a coordinate method),
//! 4 a failed step, 5 I/O, 128 + signal when stopped.

use std::io::Write;
use std::path::Path;

use framedyn::analysis::{chaos_map, AnalysisError, ChaosMapOptions, Linearisation};
use framedyn::scenes::{EventDirection, EventKind, EventSpec, Scene, SceneAnalysisError};

use crate::{signals, target, EXIT_INTEGRATION, EXIT_INVALID, EXIT_IO};

/// Exit code: bad command line.
const EXIT_USAGE: u8 = 2;

/// The tangent vectors' settings, shared by `lyapunov`, `sali` and `megno`.
#[derive(clap::Args, Debug, Clone)]
pub struct TangentArgs {
    /// Seed of the random initial tangent vectors.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Perturbation of the central differences of the step map, where the tangent maps are differenced (default 1e-5; 1e-3 with --fourth-order).
    #[arg(long)]
    pub eps: Option<f64>,
    /// Fourth-order central differences where the tangent maps are differenced (twice their cost).
    #[arg(long)]
    pub fourth_order: bool,
    /// Difference the step maps even where the exact tangent maps exist (for comparison).
    #[arg(long)]
    pub differenced: bool,
}

impl TangentArgs {
    /// The linearisation of the step map these options ask for.
    fn linearisation(&self) -> Linearisation {
        Linearisation::chosen(self.fourth_order, self.eps, self.differenced)
    }
}

/// A map over a member table, shared by `sali`, `megno` and `gali`.
#[derive(clap::Args, Debug, Clone)]
pub struct MapArgs {
    /// Map the indicator over the members of this table (CSV with a header of dotted scene fields, or .npz), one CSV line per member.
    #[arg(long)]
    pub table: Option<std::path::PathBuf>,
    /// Worker threads of the map (default: one per core; at most 1024, and at most one per core unless --oversubscribe).
    #[arg(long, requires = "table")]
    pub threads: Option<usize>,
    /// Allow more worker threads than cores.
    #[arg(long, requires = "table")]
    pub oversubscribe: bool,
}

/// The settings of `framedyn lyapunov` besides the scene.
#[derive(Debug, Clone)]
pub struct LyapunovArgs {
    /// Number of exponents, or `None` for all.
    pub exponents: Option<usize>,
    /// Steps between re-orthonormalisations.
    pub every: usize,
    /// Time not averaged at the start.
    pub transient: f64,
    /// Batches of the standard error.
    pub batches: usize,
    /// Seed and linearisation of the tangent vectors.
    pub tangent: TangentArgs,
    /// Add the two-trajectory estimate.
    pub two_trajectory: bool,
    /// The spectrum of the phase space (modulo the gauge directions).
    pub phase_space: bool,
    /// Where to write the running estimates.
    pub output: Option<std::path::PathBuf>,
}

fn error(origin: &str, e: SceneAnalysisError) -> (u8, String) {
    match e {
        SceneAnalysisError::Scene(e @ framedyn::scenes::SceneError::Invalid { .. }) if matches!(&e, framedyn::scenes::SceneError::Invalid { path, .. } if path.starts_with("section")) => {
            (EXIT_USAGE, format!("invalid section: {e}"))
        }
        SceneAnalysisError::Scene(e) => (EXIT_INVALID, format!("{origin}: invalid scene for this analysis: {e}")),
        SceneAnalysisError::Analysis(AnalysisError::InvalidParameter { field, value, allowed }) => {
            (EXIT_USAGE, format!("invalid {} = {value}: must be {allowed}", option_name(field)))
        }
        SceneAnalysisError::Analysis(AnalysisError::Cancelled { t }) => {
            let (code, name) = signals::interruption();
            (code, format!("interrupted by {name} at t = {t}; nothing written"))
        }
        SceneAnalysisError::Analysis(e) => (EXIT_INTEGRATION, format!("{origin}: {e}")),
    }
}

/// The command-line option of an analysis setting.
fn option_name(field: &str) -> String {
    match field {
        "renormalise_every" => "--every".into(),
        "k" => "-k".into(),
        "gali_threshold" => "--threshold".into(),
        "h" => "method.h (the scene's step)".into(),
        "duration" => "time.t_end − time.t0 (the scene's span)".into(),
        f => format!("--{}", f.replace('_', "-")),
    }
}

/// Writes `text` to `path` atomically (temporary file, then rename).
fn write_atomically(path: &Path, text: &str) -> Result<(), (u8, String)> {
    let target = target::Target::resolve(path).map_err(|e| (EXIT_IO, format!("cannot write {}: {e}", path.display())))?;
    let tmp = target.temporary("tmp");
    let written = std::fs::File::create(&tmp).and_then(|mut f| f.write_all(text.as_bytes()).and_then(|_| f.sync_all()));
    if let Err(e) = written.and_then(|_| target.commit(&tmp)) {
        let _ = std::fs::remove_file(&tmp);
        return Err((EXIT_IO, format!("cannot write {}: {e}", path.display())));
    }
    Ok(())
}

/// The steps of an analysis, for its summary: "of h = 0.005", or
/// "error-controlled (rtol 1e-10, atol 1e-10)".
fn describe(step: &framedyn::solve::StepSize) -> String {
    use framedyn::solve::{StepSize, Tol};
    let tol = |t: &Tol| match t {
        Tol::Scalar(v) => format!("{v:e}"),
        Tol::PerComponent(v) => format!("per component, {} values", v.len()),
    };
    match step {
        StepSize::Fixed(h) => format!("of h = {h:?}"),
        StepSize::Adaptive(a) => format!("error-controlled (rtol {}, atol {})", tol(&a.rtol), tol(&a.atol)),
    }
}

/// `framedyn lyapunov`.
pub fn lyapunov(scene: &Scene, origin: &str, args: &LyapunovArgs) -> Result<(), (u8, String)> {
    let cancel = signals::arm();
    let mut opts = scene.lyapunov_options().map_err(|e| error(origin, e.into()))?;
    let dof = scene.state_dimension().map_err(|e| error(origin, e.into()))?;
    let dimension = if args.phase_space { scene.phase_space_dimension().map_err(|e| error(origin, e.into()))? } else { dof };
    opts.exponents = args.exponents.unwrap_or(dimension);
    opts.quotient = args.phase_space;
    opts.renormalise_every = args.every;
    opts.transient = args.transient;
    opts.batches = args.batches;
    opts.seed = args.tangent.seed;
    opts.linearisation = args.tangent.linearisation();
    let started = std::time::Instant::now();
    let e = scene.lyapunov(&opts, cancel).map_err(|e| error(origin, e))?;
    let wall = started.elapsed().as_secs_f64();
    let two = if args.two_trajectory {
        let mut o = scene.two_trajectory_options().map_err(|e| error(origin, e.into()))?;
        o.renormalise_every = args.every;
        o.transient = args.transient;
        o.batches = args.batches;
        o.seed = args.tangent.seed;
        Some(scene.two_trajectory(&o, cancel).map_err(|e| error(origin, e))?)
    } else {
        None
    };
    if let Some(path) = &args.output {
        let mut text = String::from("t");
        for i in 1..=e.exponents.len() {
            text.push_str(&format!(",lambda_{i}"));
        }
        text.push('\n');
        for (t, row) in e.times.iter().zip(&e.running) {
            text.push_str(&format!("{t:?}"));
            for x in row {
                text.push_str(&format!(",{x:?}"));
            }
            text.push('\n');
        }
        write_atomically(path, &text)?;
    }
    println!("scene:           {origin}");
    if args.phase_space {
        println!("phase space:     {} (the state group's {dof} less {} gauge direction(s) of the parallel frame; exponents computed: {})", e.dimension, dof - e.dimension, e.exponents.len());
    } else {
        println!("state dimension: {dof} (exponents computed: {})", e.exponents.len());
    }
    println!("steps:           {} {} ({} method steps each)", e.steps, describe(&opts.step), e.steps_per_step);
    println!("tangent maps:    {}", e.linearisation.describe());
    println!("wall time:       {wall:.3} s");
    println!("{:>3}  {:>12}  {:>10}  {:>10}", "i", "exponent", "stderr", "spread");
    for (i, ((l, s), w)) in e.exponents.iter().zip(&e.stderr).zip(&e.spread).enumerate() {
        println!("{:>3}  {l:>12.6}  {s:>10.2e}  {w:>10.2e}", i + 1);
    }
    if e.exponents.len() == e.dimension {
        println!("sum:             {:.3e}", e.exponents.iter().sum::<f64>());
    }
    if let Some(t) = two {
        println!("two trajectories: {:.6} ± {:.2e} (spread {:.2e})", t.exponent, t.stderr, t.spread);
    }
    if let Some(path) = &args.output {
        println!("running estimates: {}", path.display());
    }
    Ok(())
}

/// The settings of `framedyn sali` besides the scene.
#[derive(Debug, Clone)]
pub struct SaliArgs {
    /// SALI below which the orbit is called chaotic.
    pub threshold: f64,
    /// Seed and linearisation of the two tangent vectors.
    pub tangent: TangentArgs,
    /// A map over a member table.
    pub map: MapArgs,
    /// Where to write the map.
    pub output: Option<std::path::PathBuf>,
}

/// `framedyn sali`.
pub fn sali(scene: &Scene, origin: &str, args: &SaliArgs) -> Result<(), (u8, String)> {
    if let Some(table) = &args.map.table {
        let opts = ChaosMapOptions { megno: false, threshold: args.threshold, ..map_options(&args.tangent, &args.map) };
        return map(scene, origin, table, &opts, args.output.as_deref());
    }
    let cancel = signals::arm();
    let mut opts = scene.sali_options().map_err(|e| error(origin, e.into()))?;
    opts.threshold = args.threshold;
    opts.seed = args.tangent.seed;
    opts.linearisation = args.tangent.linearisation();
    let started = std::time::Instant::now();
    let e = scene.sali(&opts, cancel).map_err(|e| error(origin, e))?;
    println!("scene:           {origin}");
    println!("steps:           {} {}", e.steps, describe(&opts.step));
    println!("tangent maps:    {}", e.linearisation.describe());
    println!("wall time:       {:.3} s", started.elapsed().as_secs_f64());
    println!("sali:            {:.6e} (at the end of the run)", e.sali);
    println!("min:             {:.6e}", e.min);
    match e.chaotic_at {
        Some(t) => println!("verdict:         chaotic (SALI < {:e} at t = {t:?})", opts.threshold),
        None => println!("verdict:         regular over T = {:?} (SALI stayed above {:e})", opts.duration, opts.threshold),
    }
    Ok(())
}

/// The settings of `framedyn megno` besides the scene.
#[derive(Debug, Clone)]
pub struct MegnoArgs {
    /// Seed and linearisation of the tangent vector.
    pub tangent: TangentArgs,
    /// A map over a member table.
    pub map: MapArgs,
    /// Where to write the running values (with a table: the map).
    pub output: Option<std::path::PathBuf>,
}

/// `framedyn megno`.
pub fn megno(scene: &Scene, origin: &str, args: &MegnoArgs) -> Result<(), (u8, String)> {
    if let Some(table) = &args.map.table {
        let opts = ChaosMapOptions { sali: false, ..map_options(&args.tangent, &args.map) };
        return map(scene, origin, table, &opts, args.output.as_deref());
    }
    let cancel = signals::arm();
    let mut opts = scene.megno_options().map_err(|e| error(origin, e.into()))?;
    opts.seed = args.tangent.seed;
    opts.linearisation = args.tangent.linearisation();
    let started = std::time::Instant::now();
    let e = scene.megno(&opts, cancel).map_err(|e| error(origin, e))?;
    let wall = started.elapsed().as_secs_f64();
    if let Some(path) = &args.output {
        let mut text = String::from("t,megno,mean\n");
        for ((t, y), m) in e.times.iter().zip(&e.running_megno).zip(&e.running_mean) {
            text.push_str(&format!("{t:?},{y:?},{m:?}\n"));
        }
        write_atomically(path, &text)?;
    }
    println!("scene:           {origin}");
    println!("steps:           {} {} ({} method steps each)", e.steps, describe(&opts.step), e.steps_per_step);
    println!("tangent maps:    {}", e.linearisation.describe());
    println!("wall time:       {wall:.3} s");
    println!("megno:           {:.6} (Y at the end of the run)", e.megno);
    println!("mean:            {:.6} (<Y>: 2 quasi-periodic, 0 stable periodic, ~lambda_1 t/2 chaotic)", e.mean);
    println!("2 x slope:       {:.6} (of <Y> over the second half: lambda_1 if chaotic, ~0 if regular)", 2.0 * e.slope);
    println!("lyapunov:        {:.6} (finite-time exponent of the same vector)", e.lyapunov);
    if let Some(path) = &args.output {
        println!("running values:  {}", path.display());
    }
    Ok(())
}

/// The settings of `framedyn gali` besides the scene.
#[derive(Debug, Clone)]
pub struct GaliArgs {
    /// Number of tangent vectors (`None`: the dimension of the space they
    /// live in).
    pub k: Option<usize>,
    /// GALI below which the orbit is called chaotic.
    pub threshold: f64,
    /// Modulo the gauge directions (the phase space) or on the stored state.
    pub quotient: bool,
    /// Seed and linearisation of the tangent vectors.
    pub tangent: TangentArgs,
    /// A map over a member table.
    pub map: MapArgs,
    /// Where to write the running values (or the map).
    pub output: Option<std::path::PathBuf>,
}

/// `framedyn gali`.
pub fn gali(scene: &Scene, origin: &str, args: &GaliArgs) -> Result<(), (u8, String)> {
    let k = match args.k {
        Some(k) => k,
        None if args.quotient => scene.phase_space_dimension().map_err(|e| error(origin, e.into()))?,
        None => scene.state_dimension().map_err(|e| error(origin, e.into()))?,
    };
    if let Some(table) = &args.map.table {
        let opts = ChaosMapOptions { sali: false, megno: false, gali: Some(k), gali_threshold: args.threshold, gali_quotient: args.quotient, ..map_options(&args.tangent, &args.map) };
        return map(scene, origin, table, &opts, args.output.as_deref());
    }
    let cancel = signals::arm();
    let mut opts = scene.gali_options(k).map_err(|e| error(origin, e.into()))?;
    opts.threshold = args.threshold;
    opts.seed = args.tangent.seed;
    opts.linearisation = args.tangent.linearisation();
    opts.quotient = args.quotient;
    let started = std::time::Instant::now();
    let e = scene.gali(&opts, cancel).map_err(|e| error(origin, e))?;
    let wall = started.elapsed().as_secs_f64();
    if let Some(path) = &args.output {
        let mut text = String::from("t,log10_gali\n");
        for (t, l) in e.times.iter().zip(&e.running_log10) {
            text.push_str(&format!("{t:?},{l:?}\n"));
        }
        write_atomically(path, &text)?;
    }
    println!("scene:           {origin}");
    println!("steps:           {} {} ({} method steps each)", e.steps, describe(&opts.step), e.steps_per_step);
    println!("tangent maps:    {}", e.linearisation.describe());
    println!("wall time:       {wall:.3} s");
    let dof = scene.state_dimension().map_err(|e| error(origin, e.into()))?;
    if args.quotient {
        println!("dimension:       {} (the phase space: the state group's {dof} less {} gauge direction(s) of the parallel frame)", e.dimension, dof - e.dimension);
    } else {
        println!("dimension:       {} (the stored state)", e.dimension);
    }
    println!("gali_{k}:          {:.6e} (log10 {:.6})", e.gali, e.log10);
    // Below the threshold means chaos only when the fall is exponential: on
    // a regular orbit GALI_k falls like a power of t for k above the
    // torus's dimension.
    match e.below_at {
        Some(t) => println!("below:           {:e} at t = {t:?} (exponential fall: chaotic; a power of t: regular, k above the torus's dimension)", opts.threshold),
        None => println!("below:           not {:e} over T = {:?}", opts.threshold, opts.duration),
    }
    if let Some(path) = &args.output {
        println!("running values:  {}", path.display());
    }
    Ok(())
}

/// The map's options from the command line (both indicators; the caller
/// turns one off).
fn map_options(tangent: &TangentArgs, map: &MapArgs) -> ChaosMapOptions {
    ChaosMapOptions { seed: tangent.seed, linearisation: tangent.linearisation(), threads: map.threads, oversubscribe: map.oversubscribe, ..ChaosMapOptions::default() }
}

/// A CSV field: quoted (with `"` doubled) if it holds a comma, a quote or a
/// line break.
fn csv_field(text: &str) -> String {
    if text.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", text.replace('"', "\"\""))
    } else {
        text.to_string()
    }
}

/// `framedyn sali|megno|gali SCENE --table`: the indicator of `opts` over the
/// members of the table, one CSV line per member.
fn map(scene: &Scene, origin: &str, table: &Path, opts: &ChaosMapOptions, output: Option<&Path>) -> Result<(), (u8, String)> {
    let table = crate::sweep::read_table(table).map_err(|e| match e {
        crate::sweep::TableError::Io(m) => (EXIT_IO, m),
        crate::sweep::TableError::Invalid(m) => (EXIT_INVALID, m),
    })?;
    let cancel = signals::arm();
    let started = std::time::Instant::now();
    let m = chaos_map(scene, &table, opts, cancel).map_err(|e| error(origin, e.into()))?;
    let wall = started.elapsed().as_secs_f64();
    let names: Vec<&str> = table.names().collect();
    let mut header: Vec<String> = names.iter().map(|n| csv_field(n)).collect();
    let mut columns: Vec<Vec<String>> = names.iter().map(|n| table.column(n).unwrap_or(&[]).iter().map(|v| format!("{v:?}")).collect()).collect();
    let mut add = |name: &str, values: Vec<String>| {
        header.push(name.to_string());
        columns.push(values);
    };
    let floats = |v: &[f64]| v.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>();
    let ints = |v: &[u64]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
    if opts.sali {
        add("sali", floats(&m.sali));
        add("sali_min", floats(&m.sali_min));
        add("chaotic_at", floats(&m.chaotic_at));
        add("sali_steps", ints(&m.sali_steps));
    }
    if opts.megno {
        add("megno", floats(&m.megno));
        add("megno_mean", floats(&m.megno_mean));
        add("megno_slope", floats(&m.megno_slope));
        add("lyapunov", floats(&m.lyapunov));
        add("megno_steps", ints(&m.megno_steps));
    }
    if opts.gali.is_some() {
        add("gali_log10", floats(&m.gali_log10));
        add("gali_below_at", floats(&m.gali_below_at));
        add("gali_steps", ints(&m.gali_steps));
    }
    add("status", m.status.iter().map(|s| s.name().to_string()).collect());
    add("error", m.errors.iter().map(|e| csv_field(e.as_deref().unwrap_or(""))).collect());
    let mut text = header.join(",") + "\n";
    for i in 0..m.len() {
        text.push_str(&columns.iter().map(|c| c[i].as_str()).collect::<Vec<_>>().join(","));
        text.push('\n');
    }
    let counts: Vec<String> = ["finished", "invalid", "failed", "cancelled"]
        .iter()
        .filter_map(|name| match m.status.iter().filter(|s| s.name() == *name).count() {
            0 => None,
            k => Some(format!("{k} {name}")),
        })
        .collect();
    let mut report = vec![format!("scene:           {origin}"), format!("members:         {} ({})", m.len(), counts.join(", "))];
    if opts.sali {
        report.push(format!("chaotic:         {} by SALI < {:e}", m.chaotic_at.iter().filter(|t| t.is_finite()).count(), opts.threshold));
    }
    if let Some(k) = opts.gali {
        report.push(format!("below:           {} with GALI_{k} < {:e}", m.gali_below_at.iter().filter(|t| t.is_finite()).count(), opts.gali_threshold));
    }
    if opts.megno {
        report.push(format!("<Y> > 4:         {} by MEGNO (2: quasi-periodic, ~lambda_1 t/2: chaotic)", m.megno_mean.iter().filter(|y| **y > 4.0).count()));
    }
    if let Some((i, e)) = m.errors.iter().enumerate().find_map(|(i, e)| e.as_ref().map(|e| (i, e))) {
        report.push(format!("first failure:   member {i}: {e}"));
    }
    report.push(format!("wall time:       {wall:.3} s"));
    match output {
        Some(path) => {
            write_atomically(path, &text)?;
            report.push(format!("output:          {}", path.display()));
            for line in &report {
                println!("{line}");
            }
        }
        None => {
            print!("{text}");
            for line in &report {
                eprintln!("{line}");
            }
        }
    }
    if cancel.load(std::sync::atomic::Ordering::SeqCst) {
        let (code, name) = signals::interruption();
        return Err((code, format!("interrupted by {name}; the members not computed have status `cancelled`")));
    }
    Ok(())
}

/// The section of `framedyn section`.
#[derive(Debug, Clone, Default)]
pub struct SectionArgs {
    /// An `[[events]]` entry of the scene, by name.
    pub event: Option<String>,
    /// A plane's normal.
    pub plane: Option<Vec<f64>>,
    /// The plane's offset.
    pub offset: Option<f64>,
    /// A record column.
    pub column: Option<String>,
    /// The value the column crosses.
    pub value: Option<f64>,
    /// `rising`, `falling` or `either`.
    pub direction: Option<EventDirection>,
    /// The output CSV.
    pub output: std::path::PathBuf,
}

/// `framedyn section`.
pub fn section(scene: &Scene, origin: &str, args: &SectionArgs) -> Result<(), (u8, String)> {
    let given = [args.event.is_some(), args.plane.is_some(), args.column.is_some()].iter().filter(|g| **g).count();
    if given > 1 {
        return Err((EXIT_USAGE, "give one section: --event, --plane or --column".into()));
    }
    let mut spec = if let Some(name) = &args.event {
        scene.events.iter().find(|e| e.name.as_deref() == Some(name.as_str())).cloned().ok_or_else(|| {
            let names: Vec<&str> = scene.events.iter().filter_map(|e| e.name.as_deref()).collect();
            (EXIT_USAGE, format!("invalid --event = {name:?}: must name an [[events]] entry of the scene; named entries: {}", if names.is_empty() { "none".to_string() } else { names.join(", ") }))
        })?
    } else if let Some(n) = &args.plane {
        EventSpec { kind: EventKind::Plane, name: Some("section".into()), normal: Some(n.clone()), offset: args.offset, point: None, distance: None, column: None, value: None, direction: EventDirection::default(), terminal: false }
    } else if let Some(c) = &args.column {
        let v = args.value.ok_or_else(|| (EXIT_USAGE, "--column needs --value (the value crossed)".to_string()))?;
        EventSpec { kind: EventKind::Column, name: Some("section".into()), normal: None, offset: None, point: None, distance: None, column: Some(c.clone()), value: Some(v), direction: EventDirection::default(), terminal: false }
    } else {
        match scene.events.as_slice() {
            [one] => one.clone(),
            [] => return Err((EXIT_USAGE, "no section: give --plane, --column or --event (the scene has no [[events]])".into())),
            _ => return Err((EXIT_USAGE, format!("the scene has {} [[events]]: choose one with --event NAME", scene.events.len()))),
        }
    };
    if args.plane.is_none() && args.offset.is_some() {
        return Err((EXIT_USAGE, "--offset goes with --plane".into()));
    }
    if args.column.is_none() && args.value.is_some() {
        return Err((EXIT_USAGE, "--value goes with --column".into()));
    }
    if let Some(d) = args.direction {
        spec.direction = d;
    }
    let cancel = signals::arm();
    let started = std::time::Instant::now();
    let s = scene.section(&spec, cancel).map_err(|e| error(origin, e))?;
    let mut text = String::from("rising");
    for c in &s.columns {
        text.push(',');
        text.push_str(&c.name);
    }
    text.push('\n');
    let w = s.columns.len();
    for (row, rising) in s.data.chunks(w).zip(&s.rising) {
        text.push_str(if *rising { "1" } else { "0" });
        for x in row {
            text.push_str(&format!(",{x:?}"));
        }
        text.push('\n');
    }
    write_atomically(&args.output, &text)?;
    println!("scene:           {origin}");
    println!("section:         {} ({} crossings)", s.name, s.len());
    println!("wall time:       {:.3} s", started.elapsed().as_secs_f64());
    println!("output:          {}", args.output.display());
    Ok(())
}
