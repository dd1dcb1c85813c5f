//! The `decohesion` command: its arguments; the subcommands are in the library
//! ([`decohesion::cli`]).
//!
//! Native only: on wasm32 the crate is the web page (`decohesion::web`, built as a cdylib by
//! `scripts/build_site.sh`), and this binary is empty (no `main`, nothing offered).
#![cfg_attr(target_arch = "wasm32", no_main)]
#![cfg(not(target_arch = "wasm32"))]

use clap::{CommandFactory, Parser, Subcommand};
use decohesion::cli::{
    bench, check, compare, fit, reference, run, sweep, tradeoff, Checkpoints, FitCli, SweepArgs,
};
use decohesion::fit::FitArgs;
use decohesion::scene::load_scene;
use std::path::{Path, PathBuf};

#[derive(Parser)]
#[command(
    name = "decohesion",
    version,
    about = "Explicit non-smooth dynamics of a soft solid torn off a rigid mould (CD-Lagrange + RCCM cohesive law)"
)]
struct Cli {
    /// Worker threads for the element loop (default: all cores). Results do not depend on it.
    #[arg(
        long,
        global = true,
        value_name = "N",
        help_heading = "Global options",
        allow_negative_numbers = true
    )]
    threads: Option<usize>,
    /// No progress on stderr (run, sweep, tradeoff).
    ///
    /// No header, bar, progress lines or advisories of run, no bars or per-run lines of sweep
    /// and tradeoff. Tables, summaries, warnings about the flags and errors are still printed;
    /// the commands that show no progress (check, gui, bench) accept it and ignore it.
    #[arg(long, global = true, help_heading = "Global options")]
    quiet: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene headless and print a summary.
    Run {
        /// Scene file (TOML), e.g. scenes/pull_off.toml (not with --resume, which takes the
        /// checkpoint's).
        #[arg(required_unless_present = "resume", conflicts_with = "resume")]
        scene: Option<PathBuf>,
        /// Override a scene value, e.g. --set interface.law.u_r=0.02 (same validation as the file).
        #[arg(long = "set", value_name = "KEY=VALUE", conflicts_with = "resume")]
        set: Vec<String>,
        /// Write the summary as JSON to this file (also written when the run fails).
        #[arg(long, value_name = "FILE")]
        summary: Option<PathBuf>,
        /// Write checkpoints into this folder (created if needed): its run.toml names the scene,
        /// its state.ckpt holds the state at the last checkpoint, replaced atomically, so a run
        /// killed at any moment continues with --resume DIR, bit for bit.
        #[arg(long, value_name = "DIR", group = "checkpoints")]
        checkpoint: Option<PathBuf>,
        /// How often to checkpoint: every N steps (e.g. 1000) or every T seconds of simulated
        /// time (e.g. 0.01s) [default: a tenth of the end time; with --resume, the folder's].
        #[arg(long, value_name = "N|Ts", requires = "checkpoints")]
        checkpoint_every: Option<decohesion::checkpoint::Every>,
        /// Continue the run whose checkpoints are in this folder (its scene and overrides, from
        /// its last state), checkpointing on into it; the outputs (--save, --vtk, --series,
        /// --summary) are this part's.
        #[arg(long, value_name = "DIR", group = "checkpoints")]
        resume: Option<PathBuf>,
        // Where and how often to record: Rerun (one sink), ParaView files and/or the CSV time
        // series (no flag: none), the outputs of the registry (decohesion::outputs).
        #[command(flatten)]
        record: decohesion::outputs::OutputFlags,
    },
    /// Validate a scene without running it and print derived quantities.
    Check {
        /// Scene file (TOML), e.g. scenes/pull_off.toml.
        scene: PathBuf,
        /// Override a scene value, e.g. --set interface.law.u_r=0.02 (same validation as the
        /// file; repeat for several).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// Open the explorer window: scene picker, law editor with live curves, runs on a background
    /// thread streamed to the Rerun viewer, run history.
    #[cfg(feature = "gui")]
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
        /// Queue one run per value and overlay them, e.g. --compare
        /// interface.law.u_r=0.003,0.004,0.006 (m). KEY is a key path as --vary takes it: a
        /// number parameter of the scene's law (interface.law.NAME, in its unit),
        /// interface.mu_inf, mesh.cells (cells along the longest side of a box mesh),
        /// scheme.time_step_factor (h/h_crit) or end_time (s); the short names NAME, mu_inf,
        /// cells, factor and end_time are aliases.
        #[arg(long, value_name = "KEY=V1,V2,...")]
        compare: Option<String>,
        /// Open a lesson: a shipped one by name (cohesive_law, pull_off, peel, friction, rate,
        /// stability, demoulding) or a lesson file (NAME.md); its steps set the scene.
        #[arg(long, value_name = "NAME|FILE.md", conflicts_with = "scene")]
        lesson: Option<String>,
        /// The lesson's step to open (1 = the first).
        #[arg(long, value_name = "N", requires = "lesson", value_parser = positive_usize)]
        step: Option<usize>,
        /// Override a value of the opened scene, e.g. --set interface.law.u_r=0.004 (same
        /// validation as the file; repeat for several).
        #[arg(long = "set", value_name = "KEY=VALUE", conflicts_with = "lesson")]
        set: Vec<String>,
        /// A measured curve to draw over the compared runs' reaction and fit the law to: a CSV
        /// file of two columns with their units in the header, e.g. `u [mm], F [kN]` (as fit
        /// --data reads it).
        #[arg(long, value_name = "CURVE.csv")]
        data: Option<PathBuf>,
        /// Hide panels, e.g. --hide history,law: settings, history, view (3-D), law (the law's
        /// plots), progress (the run's plots), measured (the measured curve and fit).
        #[arg(long, value_name = "PANEL,...")]
        hide: Vec<String>,
        /// Projector mode: larger type and thicker plot lines.
        #[arg(long)]
        projector: bool,
    },
    /// Run a grid of variants of one scene (every combination of the --vary values) and write
    /// every run's summary as CSV and JSON (and a Rerun plot of the observables with --save).
    Sweep {
        /// Scene file (TOML), e.g. scenes/pull_off.toml.
        scene: PathBuf,
        /// A scene key and its values, e.g. --vary interface.law.u_r=0.003,0.004,0.006 (any key
        /// --set takes; repeat for a grid; values with commas in brackets or quotes stay whole).
        #[arg(long = "vary", value_name = "KEY=V1,V2,...", required = true)]
        vary: Vec<String>,
        /// Override applied to every run, e.g. --set end_time=0.2 (repeat for several).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Folder of sweep.csv and sweep.json, created if needed [default: out/sweep_<scene
        /// name>].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Record the observables against the varied values to this .rrd file.
        #[arg(long, value_name = "FILE.rrd")]
        save: Option<PathBuf>,
        /// Runs at a time [default: the threads (--threads or the cores), at most the runs];
        /// the threads are shared among them.
        #[arg(long, value_name = "N", value_parser = positive_u64)]
        jobs: Option<u64>,
    },
    /// Fit free scene keys (a law's parameters) so that the run reproduces a measured curve:
    /// Nelder–Mead over runs, σ of each value, a plot and the fitted scene file.
    Fit {
        /// Scene file (TOML), e.g. scenes/pull_off.toml.
        scene: PathBuf,
        /// The measured curve: CSV of two columns, a header naming them with units in brackets,
        /// e.g. `u [mm], F [N]`; x strictly increasing.
        #[arg(long, value_name = "FILE.csv")]
        data: PathBuf,
        /// The run's series column compared with the measured x (a column of `run --series`,
        /// with or without its unit), e.g. u_z_plus_z.
        #[arg(long, value_name = "COLUMN")]
        x: String,
        /// The run's series column compared with the measured y, e.g. F_z_plus_z.
        #[arg(long, value_name = "COLUMN")]
        y: String,
        /// A free key and its bounds, e.g. --free interface.law.u_r=1e-3..1e-2 (repeat for
        /// several); it starts from the scene's value (or --set's), else the middle.
        #[arg(long = "free", value_name = "KEY=LO..HI", required = true)]
        free: Vec<String>,
        /// Override applied to every run, e.g. --set end_time=0.2 (repeat for several).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Unit of the measured x when the header gives none (e.g. mm) [default: the column's SI
        /// unit, with a warning].
        #[arg(long, value_name = "UNIT")]
        x_unit: Option<String>,
        /// Unit of the measured y when the header gives none (e.g. kN).
        #[arg(long, value_name = "UNIT")]
        y_unit: Option<String>,
        /// Runs at most (the uncertainty's 2 per free key come on top).
        #[arg(long, value_name = "N", default_value_t = decohesion::fit::DEFAULT_MAX_EVALS)]
        max_evals: usize,
        /// Points of a Halton sample of the bounds' box, run side by side before Nelder–Mead,
        /// which starts from the best of them and the start (0: from the start) [default: 20 per
        /// free key].
        #[arg(long, value_name = "N")]
        sample: Option<usize>,
        /// Stop when the misfits of the simplex's vertices agree within this (their standard
        /// deviation; the misfit is the mean square residual relative to max |y|).
        #[arg(long, value_name = "TOL", default_value_t = decohesion::fit::DEFAULT_TOLERANCE)]
        tolerance: f64,
        /// Folder of the results [default: out/fit_<scene name>].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Record the curves and the optimiser's runs to this .rrd file.
        #[arg(long, value_name = "FILE.rrd")]
        save: Option<PathBuf>,
    },
    /// Speed against accuracy: run a grid of quadratures × meshes × time steps of one scene,
    /// compare the observables with the finest run, mark the Pareto front.
    Tradeoff {
        /// Scene file (TOML) with a box mesh, e.g. scenes/pull_off.toml.
        scene: PathBuf,
        /// Cells along the longest side of the box mesh, comma-separated (the other sides
        /// scaled in proportion).
        #[arg(
            long,
            value_name = "N,...",
            default_value = "4,7,14",
            value_delimiter = ',',
            value_parser = positive_usize,
            allow_negative_numbers = true
        )]
        cells: Vec<usize>,
        /// Time-step factors h/h_crit (dimensionless, in (0, 2)), comma-separated.
        #[arg(
            long,
            value_name = "F,...",
            default_value = "0.9,0.5,0.25",
            value_delimiter = ',',
            value_parser = positive_f64,
            allow_negative_numbers = true
        )]
        factors: Vec<f64>,
        /// Quadratures: full (2×2×2), reduced (one point + hourglass control), fbar (2×2×2 with F̄),
        /// reduced_physical (one point + physical hourglass stabilisation).
        #[arg(long, value_name = "RULE,...", default_value = "full,reduced", value_delimiter = ',', value_parser = ["full", "reduced", "fbar", "reduced_physical"])]
        integration: Vec<String>,
        /// Other override applied to every run, e.g. --set end_time=0.2 (repeat for several).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Folder of tradeoff.csv and tradeoff.json, created if needed [default:
        /// out/tradeoff_<scene name>].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Also record the frontier plot to this .rrd file.
        #[arg(long, value_name = "FILE.rrd")]
        save: Option<PathBuf>,
        /// Also show the frontier plot in the Rerun viewer.
        #[arg(long)]
        spawn: bool,
    },
    /// Measure ns per element-step on cubes of n³ hex8 elements with a scene's physics
    /// (interface on), for each quadrature.
    Bench {
        /// Scene file (TOML) with a box mesh whose physics is used; only the mesh size changes.
        #[arg(default_value = "scenes/pull_off.toml")]
        scene: PathBuf,
        /// Deprecated: give the scene as the first argument.
        #[arg(
            long = "scene",
            value_name = "SCENE",
            hide = true,
            conflicts_with = "scene"
        )]
        scene_flag: Option<PathBuf>,
        /// Cells per side of the cube, comma-separated.
        #[arg(
            long,
            value_name = "N,...",
            default_value = "7,14,28,56",
            value_delimiter = ',',
            value_parser = positive_usize,
            allow_negative_numbers = true
        )]
        sizes: Vec<usize>,
        /// Repetitions per size, taken round-robin over the sizes and quadratures (the median is
        /// reported).
        #[arg(long, value_name = "N", default_value_t = 5, value_parser = positive_usize, allow_negative_numbers = true)]
        repeats: usize,
        /// Element-steps per repetition (steps = this / elements, at least 10).
        #[arg(long, value_name = "ELEMENT_STEPS", default_value_t = 20_000_000, value_parser = positive_u64, allow_negative_numbers = true)]
        work: u64,
        /// Quadratures to measure: full (2×2×2), reduced (one point + hourglass control), fbar (2×2×2
        /// with F̄), reduced_physical (one point + physical hourglass stabilisation).
        #[arg(long, value_name = "RULE,...", default_value = "full,reduced", value_delimiter = ',', value_parser = ["full", "reduced", "fbar", "reduced_physical"])]
        integration: Vec<String>,
    },
    /// Compare two run results observable by observable, each within a physical tolerance: two
    /// summaries (run --summary, or golden files tests/golden/*.json), two time series (run
    /// --series, .csv) or two Rerun captures (run --save, .rrd).
    ///
    /// Prints a table (observable, A, B, difference, tolerance, ok/MOVED) and exits 0 when
    /// every observable is within its tolerance, 1 when one moved beyond it, 2 when a file
    /// cannot be compared (missing, not a summary/series/capture, two different kinds) or a
    /// --tol is bad. Default tolerances: energies within the larger run's balance residual
    /// (max_relative_residual × its largest energy) plus round-off; event times (first damage,
    /// full rupture, a peak's time) within two steps; peak reactions within 2 h/t_peak
    /// (relative); time steps and h_crit 2 %; the step count 1 % + 2; final state counts one
    /// node; max_relative_residual a factor 2; status, error and mesh sizes equal. Series and
    /// captures: each value of A against B over A's time ± two rows; energies as above,
    /// reactions 1 % of the largest force (moment), displacements 1 % of the column's largest value, counts one node.
    Compare {
        /// The reference result: a summary (.json), a series (.csv) or a capture (.rrd).
        a: PathBuf,
        /// The result compared with it, of the same kind.
        b: PathBuf,
        /// Override a tolerance, e.g. --tol energies.damage_dissipated=0.5%, --tol times=1e-4,
        /// --tol warnings=exact (repeat for several). KEY: an observable as the table names it,
        /// or a group (energies, times, peaks, h, steps, counts, residual, status, mesh;
        /// series: reactions, displacements). VALUE: a number ≥ 0 (absolute, in the
        /// observable's unit), N% (relative to the larger magnitude; a series: to the
        /// column's largest value, a force or moment column's to the largest force or moment),
        /// exact, or ignore (shown, not judged).
        #[arg(long = "tol", value_name = "KEY=VALUE")]
        tol: Vec<String>,
        /// Print the comparison as JSON (every row with its tolerance, the allowed difference and
        /// the reason) instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// Print a reference page generated from the code, as Markdown: every key of a scene file
    /// (`scenes`) or every subcommand and option of this command (`cli`).
    Reference {
        /// Which page: scenes (docs/src/reference/scenes.md) or cli (docs/src/reference/cli.md).
        #[arg(value_parser = ["scenes", "cli"])]
        page: String,
        /// Write the page to this file (its folder created if needed) instead of standard output.
        #[arg(long, value_name = "FILE")]
        out: Option<PathBuf>,
    },
}

fn positive_usize(s: &str) -> Result<usize, String> {
    match s.trim().parse::<i128>() {
        Ok(v) if v >= 1 => usize::try_from(v).map_err(|_| format!("{v} is too large")),
        Ok(v) => Err(format!("must be an integer ≥ 1 (got {v})")),
        Err(e) => Err(format!("not an integer: {e}")),
    }
}

fn positive_u64(s: &str) -> Result<u64, String> {
    positive_usize(s).map(|v| v as u64)
}

fn positive_f64(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
        Ok(v) => Err(format!("must be a finite number > 0 (got {v})")),
        Err(e) => Err(format!("not a number: {e}")),
    }
}

fn main() {
    // Output piped into a reader that stops early (`decohesion fit … | head`) ends the process
    // quietly, as for any Unix tool, instead of a panic in println! on EPIPE: SIGPIPE back to
    // its default action (Rust's runtime ignores it).
    #[cfg(target_os = "linux")]
    // SAFETY: setting a signal's disposition to SIG_DFL before any thread is started.
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
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
            record,
            checkpoint,
            checkpoint_every,
            resume,
        } => {
            let checkpoints = match (checkpoint, resume) {
                (Some(dir), _) => Checkpoints::Write {
                    dir,
                    every: checkpoint_every,
                },
                (None, Some(dir)) => Checkpoints::Resume {
                    dir,
                    every: checkpoint_every,
                },
                (None, None) => Checkpoints::None,
            };
            run(
                scene.as_deref(),
                &set,
                summary.as_deref(),
                cli.quiet,
                &record.plan(),
                &checkpoints,
            )
        }
        Command::Check { scene, set } => check(&scene, &set),
        Command::Sweep {
            scene,
            vary,
            set,
            out,
            save,
            jobs,
        } => sweep(SweepArgs {
            scene: &scene,
            vary: &vary,
            set: &set,
            out,
            save,
            jobs: jobs.map(|j| j as usize),
            quiet: cli.quiet,
        }),
        Command::Fit {
            scene,
            data,
            x,
            y,
            free,
            set,
            x_unit,
            y_unit,
            max_evals,
            sample,
            tolerance,
            out,
            save,
        } => fit(FitCli {
            args: FitArgs {
                set,
                x_unit,
                y_unit,
                max_evals,
                sample,
                tolerance,
                threads: rayon::current_num_threads().max(1),
                ..FitArgs::new(&scene, &data, &x, &y, &free)
            },
            out,
            save,
            quiet: cli.quiet,
        }),
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
            cli.quiet,
        ),
        #[cfg(feature = "gui")]
        Command::Gui {
            scene,
            run_on_start,
            record,
            compare,
            lesson,
            step,
            set,
            data,
            hide,
            projector,
        } => {
            use decohesion::gui::RecordChoice;
            let opening = decohesion::gui::Opening {
                lesson,
                step: step.unwrap_or(1),
                set,
                data: data.map(|p| p.display().to_string()),
                hide,
                projector,
                embed: false,
            };
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
            if let Some(spec) = &compare {
                if let Err(e) = decohesion::gui::check_compare(spec, scene.as_deref()) {
                    eprintln!("error: --compare {e}");
                    std::process::exit(2);
                }
            }
            if let Err(e) = decohesion::gui::check_opening(scene.as_deref(), &opening) {
                eprintln!("error: {e}");
                std::process::exit(1);
            }
            decohesion::gui::run_window(scene, run_on_start, record, compare, opening)
                .map_err(anyhow::Error::msg)
        }
        Command::Bench {
            scene,
            scene_flag,
            sizes,
            repeats,
            work,
            integration,
        } => {
            if scene_flag.is_some() {
                eprintln!(
                    "warning: bench --scene is deprecated: give the scene as the first argument \
                     (decohesion bench SCENE)"
                );
            }
            let scene = scene_flag.unwrap_or(scene);
            bench(&scene, &sizes, repeats, work, &integration)
        }
        Command::Compare { a, b, tol, json } => std::process::exit(compare(&a, &b, &tol, json)),
        Command::Reference { page, out } => {
            let text = match page.as_str() {
                "scenes" => reference::scenes(),
                _ => reference::cli(&Cli::command()),
            };
            reference::emit(&text, out.as_deref())
        }
    };
    if let Err(e) = result {
        eprintln!("error: {}", decohesion::cli::error_message(&e));
        std::process::exit(1);
    }
}
