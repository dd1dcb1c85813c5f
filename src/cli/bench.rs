//! `decohesion bench`: ns per element-step on cubes of n³ hex8 elements, the share of each stage
//! of the step, the scaling of the wall time with the mesh size, and the element kernels
//! against the machine's limits (flops counted from the code, the peak rate and the memory
//! bandwidth read at run time, [`super::peak`]).

use super::peak::{peak, triad_gbs};
use crate::report::state_bytes;
use crate::scene::load_scene;
use crate::solver::Simulation;
use anyhow::{anyhow, bail, Result};
use decohesion_physics::kernels::simd::{Isa, ISA_VARIABLE};
use decohesion_physics::kernels::{self, flops};
use decohesion_physics::model::Integration;
use decohesion_physics::timing::median;
use std::path::Path;
use std::time::Instant;

/// Measures and prints the cost of a step on cubes of `sizes`³ elements.
pub fn bench(
    path: &Path,
    sizes: &[usize],
    repeats: usize,
    work: u64,
    integrations: &[String],
) -> Result<()> {
    if repeats == 0 {
        bail!("--repeats must be ≥ 1");
    }
    crate::tradeoff::require_box_mesh(&load_scene(path, &[])?, "--sizes")?;
    // The build the kernels run (an invalid DECOHESION_ISA is refused here, not replaced).
    let isa = Isa::from_env().map_err(|e| anyhow!(e))?;
    let forced = std::env::var_os(ISA_VARIABLE).is_some();
    println!(
        "decohesion bench: {} on {} threads ({}; meshes under {} elements on one), interface on; full = 2×2×2 Gauss, reduced = one point + hourglass control",
        path.display(),
        rayon::current_num_threads(),
        std::env::consts::ARCH,
        crate::solver::PARALLEL_MIN_ELEMENTS
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
    let mut configs = configs(path, sizes, work, integrations)?;
    for _ in 0..repeats {
        for c in configs.iter_mut() {
            c.repeat()?;
        }
    }
    let fits = print_times(&mut configs);
    print_shares(&configs);
    print_limits(&configs, isa, forced);
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

/// One configuration (quadrature, size) and its measurements.
struct Config {
    integration: String,
    n: usize,
    sim: Simulation,
    setup: f64,
    steps: u64,
    ns: Vec<f64>,
    iface: Vec<f64>,
    /// Stage times at the start of the first repetition [s].
    stages0: crate::solver::StageTimes,
    /// Lane groups and corner checks skipped at the start of the first repetition.
    checks0: decohesion_physics::solver::CornerChecks,
}

impl Config {
    /// One repetition: the steps, timed; the time per element-step and per interface
    /// node-step.
    fn repeat(&mut self) -> Result<()> {
        let sim = &mut self.sim;
        let elements = sim.model.mesh.elements.len() as u64;
        let before = sim.stats.stage_times.interface_contact;
        let t = Instant::now();
        for _ in 0..self.steps {
            sim.step()?;
        }
        let dt = t.elapsed().as_secs_f64();
        self.ns.push(dt * 1e9 / (self.steps * elements) as f64);
        let di = sim.stats.stage_times.interface_contact - before;
        let per_node = self.steps as f64 * sim.state.interface_nodes.len().max(1) as f64;
        self.iface.push(di * 1e9 / per_node);
        Ok(())
    }
}

/// Every configuration, set up, with the steps of one repetition.
fn configs(
    path: &Path,
    sizes: &[usize],
    work: u64,
    integrations: &[String],
) -> Result<Vec<Config>> {
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
                checks0: Default::default(),
            });
        }
    }
    for c in configs.iter_mut() {
        c.stages0 = c.sim.stats.stage_times.clone();
        c.checks0 = c.sim.stats.corner_checks;
    }
    Ok(configs)
}

/// The table of times, one row per configuration; returns the (elements, wall seconds per
/// simulated second) of each size by quadrature, for the scaling exponent.
fn print_times(configs: &mut [Config]) -> Vec<(String, Vec<(f64, f64)>)> {
    let mut fits: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
    for c in configs.iter_mut() {
        let sim = &c.sim;
        let elements = sim.model.mesh.elements.len() as u64;
        let med = median(&mut c.ns);
        // At fixed simulated time: steps ∝ 1/h, so wall = elements × ns/element-step / h.
        let wall_per_sim = elements as f64 * med * 1e-9 / sim.state.h;
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
    fits
}

/// Where the step goes: each stage's share of the summed stage times over all repetitions.
fn print_shares(configs: &[Config]) {
    println!("share of the step by stage (model §4), all repetitions:");
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
    for c in configs {
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
}

/// The element kernels against the machine's limits: flops per element-step (counted from the
/// code, [`flops`]), the element loop's time per element-step (stage 3 alone), the rate that
/// makes and its share of the peak; the bytes the element loop moves per element-step and the
/// rate that makes against a measured memory bandwidth.
fn print_limits(configs: &[Config], isa: Isa, forced: bool) {
    let threads = rayon::current_num_threads();
    let p = peak(threads, isa);
    println!(
        "the limit: kernels built for {} ({}; {ISA_VARIABLE}=portable|avx2|avx512 picks one)",
        isa.name(),
        if forced {
            "forced by ".to_string() + ISA_VARIABLE
        } else {
            "the widest this CPU runs".to_string()
        }
    );
    println!("peak: {}", p.describe());
    let triad = triad_gbs();
    println!("memory: {triad:.1} GB/s (triad a = b + s·c on 3 × 64 MiB, one thread, best of 5)");
    let mut sizes: Vec<usize> = configs
        .iter()
        .filter(|c| kernels::prefetch_pays(c.sim.model.mesh.nodes.len()))
        .map(|c| c.n)
        .collect();
    sizes.sort_unstable();
    sizes.dedup();
    println!(
        "prefetch of the next lane group, where U, V and F_int (72 bytes per node) exceed the last-level cache ({}): {}",
        match kernels::last_level_cache_bytes() {
            Some(b) => format!("{:.0} MiB, sysfs", b as f64 / (1 << 20) as f64),
            None => "unread, 32 MiB assumed".to_string(),
        },
        if sizes.is_empty() {
            "at no size here".to_string()
        } else {
            format!("n = {}", sizes.iter().map(|n| n.to_string()).collect::<Vec<_>>().join(", "))
        }
    );
    if let Some(c) = configs.first() {
        let model = c.sim.model.material.model;
        println!(
            "flops per element-step counted from the code; full: {} on axis-aligned boxes (J₀ one diagonal matrix: ⅛ J₀⁻¹ and ⅛ w det J₀ J₀⁻ᵀ applied to the sums over points), {} on other shapes; one point: {} on axis-aligned boxes (through the 8 modes of the trilinear field), {} on other shapes, each with the corner check ({}), which a lane group skips where the corner bound ({}) proves every corner J positive: the table counts the check on the element-steps that ran it (its share under \"checks run\") and the bound on those in lane groups; this mesh: {}",
            flops::full(model, true).total(),
            flops::full(model, false).total(),
            flops::one_point(model, true).total(),
            flops::one_point(model, false).total(),
            flops::one_point(model, true).corners,
            flops::one_point(model, true).bound,
            if c.sim.axis_aligned() { "axis-aligned" } else { "not axis-aligned" }
        );
    }
    println!(
        "{:>8} {:>4} {:>12} {:>13} {:>13} {:>8} {:>8} {:>11} {:>8}",
        "rule",
        "n",
        "flops/elem",
        "checks run",
        "kernel ns/el",
        "GFLOP/s",
        "of peak",
        "bytes/elem",
        "GB/s"
    );
    for c in configs {
        let model = c.sim.model.material.model;
        let count = match c.sim.model.scheme.integration {
            Integration::Full => flops::full(model, c.sim.axis_aligned()),
            Integration::Reduced => flops::one_point(model, c.sim.axis_aligned()),
            Integration::Fbar => flops::fbar(model, c.sim.axis_aligned()),
            Integration::ReducedPhysical => flops::physical(model),
        };
        let elements = c.sim.model.mesh.elements.len() as f64;
        let nodes = c.sim.model.mesh.nodes.len() as f64;
        let steps = (c.steps as usize * c.ns.len()) as f64;
        let secs = c.sim.stats.stage_times.internal_forces - c.stages0.internal_forces;
        let ns = secs * 1e9 / (steps * elements);
        // One point, over the repetitions: the element-steps in lane groups (8 per group) compute
        // the corner bound, and all but those in groups that skipped run the corner check.
        let checks = c.sim.stats.corner_checks;
        let in_groups = 8.0 * (checks.groups - c.checks0.groups) as f64 / (steps * elements);
        let skipping = 8.0 * (checks.skipped - c.checks0.skipped) as f64 / (steps * elements);
        let executed = count.executed(1.0 - skipping, in_groups);
        // Full integration has no corner check (its Gauss points are its J's).
        let checks = if count.corners > 0 {
            format!("{:.1} %", 100.0 * (1.0 - skipping))
        } else {
            "-".to_string()
        };
        let gflops = executed / ns;
        // Per element: its connectivity (8 × u32) and class (u32); per node: U read, F read
        // and written (3 f64 each) — what reaches memory when the nodal arrays leave the caches.
        let bytes = 36.0 + 72.0 * nodes / elements;
        println!(
            "{:>8} {:>4} {:>12.0} {:>13} {:>13.1} {:>8.1} {:>7.1}% {:>11.0} {:>8.2}",
            c.integration,
            c.n,
            executed,
            checks,
            ns,
            gflops,
            100.0 * gflops / p.gflops(),
            bytes,
            bytes / ns
        );
    }
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
