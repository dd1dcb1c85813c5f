//! The `decohesion` command: a thin shell over the library (scene → model → simulation).

use anyhow::{bail, Context, Result};
use clap::{Parser, Subcommand};
use decohesion::record::{Cadence, Recorder, Sink};
use decohesion::report::{state_bytes, RunSummary};
use decohesion::scene::load_scene;
use decohesion::solver::Simulation;
use decohesion::vtk::VtkWriter;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Instant;

#[derive(Parser)]
#[command(
    name = "decohesion",
    version,
    about = "Explicit non-smooth dynamics of a soft solid torn off a rigid mould (CD-Lagrange + RCCM cohesive law)"
)]
struct Cli {
    /// Worker threads for the element loop (default: all cores). Results do not depend on it.
    #[arg(long, global = true)]
    threads: Option<usize>,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene headless and print a summary.
    Run {
        /// Scene file (TOML), e.g. scenes/pull_off.toml.
        scene: PathBuf,
        /// Override a scene value, e.g. --set interface.law.u_r=0.02 (same validation as the file).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Write the summary as JSON to this file (also written when the run fails).
        #[arg(long, value_name = "FILE")]
        summary: Option<PathBuf>,
        /// No progress output.
        #[arg(long)]
        quiet: bool,
        #[command(flatten)]
        record: RecordArgs,
    },
    /// Validate a scene without running it and print derived quantities.
    Check {
        scene: PathBuf,
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Open the explorer window: scene picker, law editor with live curves, runs on a background
    /// thread streamed to the Rerun viewer, run history.
    Gui {
        /// Scene to open (default: the last one used, or scenes/pull_off.toml).
        scene: Option<PathBuf>,
        /// Start a run as soon as the window opens (for demos and scripted screenshots).
        #[arg(long)]
        run_on_start: bool,
        /// Where runs are recorded: viewer (spawn/reuse the Rerun viewer), file (out/gui/*.rrd)
        /// or off [default: the last choice, initially viewer].
        #[arg(long, value_name = "WHERE", value_parser = ["viewer", "file", "off"])]
        record: Option<String>,
    },
    /// Speed against accuracy: run a grid of quadratures × meshes × time steps of one scene,
    /// compare the observables with the finest run, mark the Pareto front.
    Tradeoff {
        scene: PathBuf,
        /// Cells along the longest side of the mesh.
        #[arg(long, default_value = "4,7,14", value_delimiter = ',')]
        cells: Vec<usize>,
        /// Time-step factors h/h_crit.
        #[arg(long, default_value = "0.9,0.5,0.25", value_delimiter = ',')]
        factors: Vec<f64>,
        /// Quadratures.
        #[arg(long, default_value = "full,reduced", value_delimiter = ',', value_parser = ["full", "reduced"])]
        integration: Vec<String>,
        /// Other overrides applied to every run.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Prefix of the CSV and JSON outputs [default: out/tradeoff_<scene>].
        #[arg(long, value_name = "PREFIX")]
        out: Option<PathBuf>,
        /// Also record the frontier plot to this .rrd file.
        #[arg(long, value_name = "FILE.rrd")]
        save: Option<PathBuf>,
        /// Also show the frontier plot in the Rerun viewer.
        #[arg(long)]
        spawn: bool,
    },
    /// Measure ns per element-step on cubes of n³ hex8 elements (full integration, interface on).
    Bench {
        /// Scene whose physics is used; only the mesh size changes.
        #[arg(long, default_value = "scenes/pull_off.toml")]
        scene: PathBuf,
        /// Cells per side, comma-separated.
        #[arg(long, default_value = "7,14,28,56", value_delimiter = ',')]
        sizes: Vec<usize>,
        /// Repetitions per size, taken round-robin over the sizes and quadratures (the median is reported)
        #[arg(long, default_value_t = 5)]
        repeats: usize,
        /// Element-steps per repetition (steps = this / elements, at least 10).
        #[arg(long, default_value_t = 20_000_000)]
        work: u64,
        /// Quadratures to measure: full (2×2×2) and/or reduced (one point + hourglass control).
        #[arg(long, default_value = "full,reduced", value_delimiter = ',', value_parser = ["full", "reduced"])]
        integration: Vec<String>,
    },
}

/// Where and how often to record: Rerun (one sink) and/or ParaView files (no flag: neither).
#[derive(clap::Args)]
struct RecordArgs {
    /// Record to this .rrd file (open it with `rerun FILE.rrd`). Complete even when the run
    /// fails or is cancelled with Ctrl-C.
    #[arg(long, value_name = "FILE.rrd", group = "sink")]
    save: Option<PathBuf>,
    /// Start the Rerun viewer (`rerun` from PATH, listening on 127.0.0.1) and stream to it.
    #[arg(long, group = "sink")]
    spawn: bool,
    /// Stream to a running Rerun viewer [default: rerun+http://127.0.0.1:9876/proxy].
    #[arg(long, value_name = "URL", num_args = 0..=1, default_missing_value = "", group = "sink")]
    connect: Option<String>,
    /// Also write ParaView files to this directory (created if needed): a .vtu per frame
    /// and NAME.pvd indexing them by simulated time, complete even when the run fails or is
    /// cancelled. Can be combined with --save, --spawn or --connect.
    #[arg(long, value_name = "DIR")]
    vtk: Option<PathBuf>,
    /// Record a frame (Rerun and --vtk) every N steps (1 = every step). Default: 200 frames
    /// over the scene's end time, plus step 0 and the last step.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..), conflicts_with = "fps")]
    every: Option<u64>,
    /// Record F frames per second of simulated time (Rerun and --vtk).
    #[arg(long, value_name = "F", value_parser = positive_f64, allow_negative_numbers = true)]
    fps: Option<f64>,
    /// Field that colours the surface: displacement (|U|, m), von_mises (Pa), jacobian (J).
    #[arg(long, value_name = "FIELD", default_value = "displacement")]
    colour: decohesion::record::ColourField,
}

fn positive_f64(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        Ok(v) => Err(format!("must be a finite number > 0 (got {v})")),
        Err(e) => Err(format!("not a number: {e}")),
    }
}

impl RecordArgs {
    fn sink(&self) -> Option<Sink> {
        if let Some(p) = &self.save {
            Some(Sink::Save(p.clone()))
        } else if self.spawn {
            Some(Sink::Spawn)
        } else {
            self.connect
                .as_ref()
                .map(|u| Sink::Connect((!u.is_empty()).then(|| u.clone())))
        }
    }

    fn cadence(&self) -> Cadence {
        match (self.every, self.fps) {
            (Some(n), _) => Cadence::EverySteps(n),
            (None, Some(f)) => Cadence::PerSimSecond(f),
            (None, None) => Cadence::Default,
        }
    }
}

fn main() {
    let cli = Cli::parse();
    if let Some(n) = cli.threads {
        if n == 0 {
            eprintln!("error: --threads must be ≥ 1 (got 0)");
            std::process::exit(2);
        }
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .ok();
        let cores = std::thread::available_parallelism().map_or(1, |c| c.get());
        if n > cores {
            eprintln!(
                "warning: --threads {n} is more than the {cores} cores of this machine: the \
                 step's threads wait for each other by spinning, so extra threads slow every step \
                 (one point at 28³: 23 ns per element-step on 2 threads, 73 on 4, on 2 cores). \
                 Results do not depend on the thread count."
            );
        }
    }
    let result = match cli.command {
        Command::Run {
            scene,
            set,
            summary,
            quiet,
            record,
        } => run(&scene, &set, summary.as_deref(), quiet, &record),
        Command::Check { scene, set } => check(&scene, &set),
        Command::Tradeoff {
            scene,
            cells,
            factors,
            integration,
            set,
            out,
            save,
            spawn,
        } => tradeoff(
            &scene,
            &cells,
            &factors,
            &integration,
            &set,
            out,
            save,
            spawn,
        ),
        Command::Gui {
            scene,
            run_on_start,
            record,
        } => {
            use decohesion::gui::RecordChoice;
            let record = record.map(|r| match r.as_str() {
                "file" => RecordChoice::File,
                "off" => RecordChoice::Off,
                _ => RecordChoice::Viewer,
            });
            let scene = scene.map(|p| p.display().to_string());
            if let Some(s) = &scene {
                if let Err(e) = load_scene(Path::new(s), &[]) {
                    eprintln!("error: {e}");
                    std::process::exit(1);
                }
            }
            decohesion::gui::run_window(scene, run_on_start, record).map_err(anyhow::Error::msg)
        }
        Command::Bench {
            scene,
            sizes,
            repeats,
            work,
            integration,
        } => bench(&scene, &sizes, repeats, work, &integration),
    };
    if let Err(e) = result {
        eprintln!("error: {e:#}");
        std::process::exit(1);
    }
}

fn run(
    path: &Path,
    set: &[String],
    summary_path: Option<&Path>,
    quiet: bool,
    record: &RecordArgs,
) -> Result<()> {
    let wall = Instant::now();
    let scene = load_scene(path, set)?;
    let end_time = scene.model.end_time;
    let mut sim = Simulation::new(scene.model.clone())
        .with_context(|| format!("setting up {}", path.display()))?;
    // ParaView first: a directory that cannot be written is refused before a viewer starts or
    // a capture file is created.
    let mut paraview = match &record.vtk {
        Some(dir) => Some(VtkWriter::new(dir, &sim, record.cadence())?),
        None => None,
    };
    let mut recorder = match record.sink() {
        Some(sink) => Some(
            Recorder::new(sink, &scene, &sim, record.cadence(), record.colour)
                .context("starting the recording")?,
        ),
        None => None,
    };
    // Ctrl-C: stop after the current step, then write the recording, the ParaView index and
    // the summary.
    let interrupted = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupted.clone();
        let _ = ctrlc::set_handler(move || {
            if flag.swap(true, Ordering::SeqCst) {
                // Second Ctrl-C: leave now (a recording then lacks its footer; the ParaView
                // index holds the frames written so far).
                std::process::exit(130);
            }
        });
    }
    let mut record_error = None;
    let mut paraview_error = None;
    let expected = (end_time / sim.h).ceil() as u64;
    let tty = std::io::stderr().is_terminal() && !quiet;
    let bar = if tty {
        let pb = indicatif::ProgressBar::new(expected);
        pb.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} steps  {msg}  ETA {eta}",
            )
            .expect("static template"),
        );
        Some(pb)
    } else {
        None
    };
    if !quiet {
        eprintln!(
            "{}: {} elements, h = {:.4e} s (h_crit {:.4e} s), ~{} steps to t = {} s",
            sim.model.name,
            sim.model.mesh.elements.len(),
            sim.h,
            sim.h_crit,
            expected,
            end_time
        );
        for w in sim.advisories() {
            eprintln!("warning: {w}");
        }
    }
    let mut next_line = 0.1;
    let outcome = sim.run(|s| {
        if let Some(r) = recorder.as_mut() {
            if record_error.is_none() {
                if let Err(e) = r.on_step(s) {
                    record_error = Some(e);
                    return false;
                }
            }
        }
        if let Some(w) = paraview.as_mut() {
            if paraview_error.is_none() {
                if let Err(e) = w.on_step(s) {
                    paraview_error = Some(e);
                    return false;
                }
            }
        }
        if let Some(pb) = &bar {
            if s.step_count % 16 == 0 {
                pb.set_position(s.step_count);
                let c = s.state_counts();
                pb.set_message(format!(
                    "t = {:.4} s, ruptured {}/{}",
                    s.time,
                    c.ruptured,
                    s.interface_nodes.len()
                ));
            }
        } else if !quiet && s.time >= next_line * end_time {
            next_line += 0.1;
            let c = s.state_counts();
            eprintln!(
                "  {:>3.0} %  t = {:.5} s  step {}  ruptured {}/{}  residual {:.2e}",
                100.0 * s.time / end_time,
                s.time,
                s.step_count,
                c.ruptured,
                s.interface_nodes.len(),
                s.ledger.relative_residual()
            );
        }
        !interrupted.load(Ordering::SeqCst)
    });
    if let Some(pb) = bar {
        pb.finish_and_clear();
    }
    let recording = match recorder {
        Some(r) => match r.finish(&sim, outcome.as_ref().err()) {
            Ok(rep) => Some(rep),
            Err(e) => {
                record_error.get_or_insert(e);
                None
            }
        },
        None => None,
    };
    let paraview = match paraview {
        Some(w) => match w.finish(&sim) {
            Ok(rep) => Some(rep),
            Err(e) => {
                paraview_error.get_or_insert(e);
                None
            }
        },
        None => None,
    };
    let mut summary = RunSummary::new(&sim, wall.elapsed().as_secs_f64(), outcome.as_ref().err());
    summary.recording = recording;
    summary.paraview = paraview;
    println!("{}", summary.table());
    if let Some(p) = summary_path {
        let json = serde_json::to_string_pretty(&summary)?;
        std::fs::write(p, json)
            .with_context(|| format!("writing the summary to {}", p.display()))?;
    }
    if let Some(e) = record_error {
        bail!(anyhow::Error::new(e).context("recording"));
    }
    if let Some(e) = paraview_error {
        bail!(anyhow::Error::new(e).context("ParaView output"));
    }
    if let Err(e) = outcome {
        bail!(e);
    }
    Ok(())
}

fn check(path: &Path, set: &[String]) -> Result<()> {
    let scene = load_scene(path, set)?;
    let m = &scene.model;
    let mat = &m.material;
    let le = m.mesh.min_edge();
    let sim =
        Simulation::new(m.clone()).with_context(|| format!("setting up {}", path.display()))?;
    println!("{} is valid: {}", scene.file, m.description);
    println!(
        "  mesh                         {} nodes, {} hex8 elements, smallest edge {:.4e} m",
        m.mesh.nodes.len(),
        m.mesh.elements.len(),
        le
    );
    println!(
        "  material                     {:?}, E = {:.4e} Pa, ν = {}, ρ = {} kg/m³, λ = {:.4e} Pa, μ = {:.4e} Pa",
        mat.model, mat.young, mat.poisson, mat.density, mat.lambda, mat.mu
    );
    println!("  wave speed c_d               {:.4} m/s", mat.wave_speed());
    println!(
        "  h_crit (Lanczos, §6)         {:.5e} s   (L_e/c_d = {:.5e} s would be {:+.1} % off)",
        sim.h_crit,
        le / mat.wave_speed(),
        100.0 * (le / mat.wave_speed() / sim.h_crit - 1.0)
    );
    println!(
        "  time step                    h = {:.5e} s (factor {})",
        sim.h, m.scheme.time_step_factor
    );
    println!(
        "  expected steps               {} to t = {} s",
        (m.end_time / sim.h).ceil(),
        m.end_time
    );
    for (k, itf) in m.interfaces.iter().enumerate() {
        let (tmax, at) = itf.law.peak_traction();
        let area: f64 = m
            .mesh
            .nodal_areas(&m.mesh.face_sets[&itf.faces])
            .iter()
            .map(|p| p.1)
            .sum();
        println!(
            "  interface[{k}] on `{}`         {:?}, g_N(0) = {:.4e} Pa/m, α_e = {:.4e} m, u_r = {:.4e} m, μ_inf = {}",
            itf.faces, itf.law.family, itf.law.g_n0, itf.law.alpha_e, itf.law.u_r, itf.mu_inf
        );
        if itf.initial_damage > 0.0 {
            let alpha0 = itf.initial_damage.min(itf.law.u_r);
            println!(
                "    initial damage             α₀ = {alpha0:.4e} m: {:?} from the start, μ(α₀) = {}",
                itf.law.state(alpha0),
                itf.law.mu(alpha0, itf.mu_inf)
            );
        }
        println!(
            "    peak traction              {:.5e} Pa at δ = {:.4e} m; G_c = {:.5e} J/m²; area {:.4e} m² → {:.5e} J to break",
            tmax,
            at,
            itf.law.fracture_energy(),
            area,
            itf.law.fracture_energy() * area
        );
    }
    println!(
        "  state memory                 {:.0} bytes per element",
        state_bytes(&sim) as f64 / m.mesh.elements.len() as f64
    );
    for w in sim.advisories() {
        println!("  warning                      {w}");
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn tradeoff(
    path: &Path,
    cells: &[usize],
    factors: &[f64],
    integrations: &[String],
    set: &[String],
    out: Option<PathBuf>,
    save: Option<PathBuf>,
    spawn: bool,
) -> Result<()> {
    use decohesion::tradeoff::{compare, csv, grid, run as run_one};
    if cells.is_empty() || factors.is_empty() || integrations.is_empty() {
        bail!("--cells, --factors and --integration each need at least one value");
    }
    // Validate the scene and every configuration before running anything.
    let base = load_scene(path, set)?;
    decohesion::tradeoff::require_box_mesh(&base, "--cells")?;
    let configs = grid(integrations, cells, factors);
    for c in &configs {
        let o = decohesion::tradeoff::overrides(path, c, set)?;
        load_scene(path, &o).with_context(|| {
            format!("configuration {} {}³ ×{}", c.integration, c.cells, c.factor)
        })?;
    }
    let bar = indicatif::ProgressBar::new(configs.len() as u64);
    if std::io::stderr().is_terminal() {
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{spinner} [{elapsed_precise}] {bar:30} {pos}/{len} runs  {msg}",
            )
            .expect("static template"),
        );
    } else {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let mut rows = vec![];
    for c in &configs {
        bar.set_message(format!("{} {}³ ×{}", c.integration, c.cells, c.factor));
        rows.push(run_one(path, c, set)?);
        bar.inc(1);
    }
    bar.finish_and_clear();
    compare(&mut rows);
    println!(
        "decohesion tradeoff: {} ({}), {} threads; reference = the finest full-integration run; error = largest relative error of peak force, first damage, full rupture, dissipation",
        path.display(),
        base.model.name,
        rayon::current_num_threads()
    );
    print!("{}", decohesion::tradeoff::table(&rows));
    let prefix = out.unwrap_or_else(|| PathBuf::from(format!("out/tradeoff_{}", base.model.name)));
    if let Some(dir) = prefix.parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        }
    }
    let csv_path = prefix.with_extension("csv");
    let json_path = prefix.with_extension("json");
    std::fs::write(&csv_path, csv(&rows))
        .with_context(|| format!("writing {}", csv_path.display()))?;
    std::fs::write(&json_path, serde_json::to_string_pretty(&rows)?)
        .with_context(|| format!("writing {}", json_path.display()))?;
    println!("wrote {} and {}", csv_path.display(), json_path.display());
    let sinks = save
        .map(Sink::Save)
        .into_iter()
        .chain(spawn.then_some(Sink::Spawn));
    for sink in sinks {
        decohesion::record::log_frontier(sink, &base.model.name, &rows)
            .context("recording the frontier")?;
    }
    Ok(())
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn bench(
    path: &Path,
    sizes: &[usize],
    repeats: usize,
    work: u64,
    integrations: &[String],
) -> Result<()> {
    if repeats == 0 {
        bail!("--repeats must be ≥ 1");
    }
    decohesion::tradeoff::require_box_mesh(&load_scene(path, &[])?, "--sizes")?;
    println!(
        "decohesion bench: {} on {} threads ({}; meshes under {} elements on one), interface on; full = 2×2×2 Gauss, reduced = one point + hourglass control",
        path.display(),
        rayon::current_num_threads(),
        std::env::consts::ARCH,
        decohesion::solver::PARALLEL_MIN_ELEMENTS
    );
    println!(
        "{:>8} {:>4} {:>9} {:>9} {:>7} {:>14} {:>16} {:>18} {:>12} {:>10} {:>13}",
        "rule",
        "n",
        "elements",
        "nodes",
        "steps",
        "ns/elem-step",
        "elem-steps/s",
        "iface ns/node-step",
        "bytes/elem",
        "setup s",
        "wall s/sim s"
    );
    // Every configuration is built first and the repetitions go round-robin over them, so a
    // burst of load on the machine (this is a shared VM) lands in one repetition of several
    // configurations instead of all the repetitions of one: the medians see it as an outlier.
    struct Config {
        integration: String,
        n: usize,
        sim: Simulation,
        setup: f64,
        steps: u64,
        ns: Vec<f64>,
        iface: Vec<f64>,
        /// Stage times at the start of the first repetition [s].
        stages0: decohesion::solver::StageTimes,
    }
    let mut configs = Vec::new();
    for integration in integrations {
        for &n in sizes {
            let set = vec![
                format!("mesh.cells=[{n},{n},{n}]"),
                "scheme.h_crit_update_interval=0".into(),
                format!("scheme.integration=\"{integration}\""),
            ];
            let scene = load_scene(path, &set)?;
            let t0 = Instant::now();
            let sim = Simulation::new(scene.model)?;
            let setup = t0.elapsed().as_secs_f64();
            let elements = sim.model.mesh.elements.len() as u64;
            configs.push(Config {
                integration: integration.clone(),
                n,
                sim,
                setup,
                steps: (work / elements).max(10),
                ns: Vec::new(),
                iface: Vec::new(),
                stages0: Default::default(),
            });
        }
    }
    for c in configs.iter_mut() {
        c.stages0 = c.sim.stats.stage_times.clone();
    }
    for _ in 0..repeats {
        for c in configs.iter_mut() {
            let sim = &mut c.sim;
            let elements = sim.model.mesh.elements.len() as u64;
            let before = sim.stats.stage_times.interface_contact;
            let t = Instant::now();
            for _ in 0..c.steps {
                sim.step()?;
            }
            let dt = t.elapsed().as_secs_f64();
            c.ns.push(dt * 1e9 / (c.steps * elements) as f64);
            let di = sim.stats.stage_times.interface_contact - before;
            let per_node = c.steps as f64 * sim.interface_nodes.len().max(1) as f64;
            c.iface.push(di * 1e9 / per_node);
        }
    }
    // (elements, wall seconds per simulated second) of each size, for the scaling exponent.
    let mut fits: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for c in configs.iter_mut() {
        let sim = &c.sim;
        let elements = sim.model.mesh.elements.len() as u64;
        let med = median(&mut c.ns);
        // At fixed simulated time: steps ∝ 1/h, so wall = elements × ns/element-step / h.
        let wall_per_sim = elements as f64 * med * 1e-9 / sim.h;
        match fits.last_mut() {
            Some((name, points)) if *name == c.integration => {
                points.push((elements as f64, wall_per_sim))
            }
            _ => fits.push((c.integration.clone(), vec![(elements as f64, wall_per_sim)])),
        }
        println!(
            "{:>8} {:>4} {:>9} {:>9} {:>7} {:>14.1} {:>16.3e} {:>18.1} {:>12.0} {:>10.2} {:>13.3e}",
            c.integration,
            c.n,
            elements,
            sim.model.mesh.nodes.len(),
            c.steps,
            med,
            1e9 / med,
            median(&mut c.iface),
            state_bytes(sim) as f64 / elements as f64,
            c.setup,
            wall_per_sim
        );
    }
    // Where the step goes: each stage's share of the summed stage times over all repetitions.
    println!("share of the step by stage (PHYSICS.md §4), all repetitions:");
    println!(
        "{:>8} {:>4} {:>11} {:>15} {:>14} {:>17} {:>12}",
        "rule",
        "n",
        "positions",
        "internal forces",
        "free velocity",
        "interface/contact",
        "bookkeeping"
    );
    for c in &configs {
        let (a, b) = (&c.stages0, &c.sim.stats.stage_times);
        let d = [
            b.positions - a.positions,
            b.internal_forces - a.internal_forces,
            b.free_velocity - a.free_velocity,
            b.interface_contact - a.interface_contact,
            b.bookkeeping - a.bookkeeping,
        ];
        let total: f64 = d.iter().sum();
        let pct = |x: f64| format!("{:.1} %", 100.0 * x / total.max(f64::MIN_POSITIVE));
        println!(
            "{:>8} {:>4} {:>11} {:>15} {:>14} {:>17} {:>12}",
            c.integration,
            c.n,
            pct(d[0]),
            pct(d[1]),
            pct(d[2]),
            pct(d[3]),
            pct(d[4])
        );
    }
    for (integration, points) in fits {
        if points.len() >= 2 {
            println!(
                "scaling ({integration}): wall time at fixed simulated time ∝ N^{:.3} over N = {:.0}…{:.0} elements (N^4/3 if the cost per element-step were constant: h ∝ N^-1/3)",
                log_log_slope(&points),
                points[0].0,
                points[points.len() - 1].0
            );
        }
    }
    Ok(())
}

/// Least-squares slope of log y against log x: the exponent p of y ∝ x^p.
fn log_log_slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (lx, ly): (Vec<f64>, Vec<f64>) = points.iter().map(|&(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / n, ly.iter().sum::<f64>() / n);
    let sxy: f64 = lx.iter().zip(&ly).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = lx.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}
