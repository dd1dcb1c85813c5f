//! Is the stick–slip of the `shear` pad at high friction the model's or the discretisation's?
//!
//! Runs `scenes/shear.toml` with μ_inf, the mesh and the time-step factor varied, and measures,
//! over the steady sliding window 70–90 ms (every node ruptured, the top pushed at 0.2 m/s):
//! the mean tangential reaction of the pushed face over the normal load (μ for steady Coulomb
//! sliding), its standard deviation, the dominant frequency of its oscillation (discrete
//! Fourier transform of the reaction, 100 Hz – 20 kHz), the share of the nodes in contact that
//! stick, and the share of the bottom nodes that have lifted off (gap > 0).
//!
//! A mesh-converged frequency and ratio mean a property of the continuum model (friction-
//! induced instability of an elastic body sliding with Coulomb friction); a frequency that
//! follows the element size or the time step would mean a numerical artefact.
//!
//! ```sh
//! cargo run --release --example stick_slip -- [MU,...] [CELLS,...] [FACTOR,...]
//! # defaults: 0.3,0.4,0.5  8,16,32 (in x and y; z gets a quarter)  0.5
//! ```

use decohesion::interface::contact::ContactStatus;
use decohesion::scene::load_scene;
use decohesion::solver::Simulation;

/// Sliding window [s]: after full rupture (≈ 64 ms at μ = 0.3), before the push stops (90 ms).
const WINDOW: (f64, f64) = (0.07, 0.09);
/// Normal load: 0.1 MPa on 100 × 100 mm [N].
const NORMAL: f64 = 1.0e3;

fn list<T: std::str::FromStr>(arg: Option<String>, default: &str) -> Vec<T> {
    arg.unwrap_or_else(|| default.into())
        .split(',')
        .map(|s| {
            s.trim()
                .parse()
                .unwrap_or_else(|_| panic!("cannot read `{s}` in `{default}`-like list"))
        })
        .collect()
}

/// Frequency [Hz] of the largest DFT amplitude of `x` (mean removed), sampled every `dt`,
/// scanned from 100 Hz to 20 kHz (or Nyquist) in steps of 1/(2 × duration).
fn dominant_frequency(x: &[f64], dt: f64) -> f64 {
    let n = x.len();
    let mean = x.iter().sum::<f64>() / n as f64;
    let duration = n as f64 * dt;
    let df = 0.5 / duration;
    let f_max = (0.5 / dt).min(2.0e4);
    let (mut best, mut best_p) = (0.0, -1.0);
    let mut f = 100.0;
    while f <= f_max {
        let w = 2.0 * std::f64::consts::PI * f * dt;
        let (mut re, mut im) = (0.0, 0.0);
        for (k, v) in x.iter().enumerate() {
            let a = w * k as f64;
            re += (v - mean) * a.cos();
            im -= (v - mean) * a.sin();
        }
        let p = re * re + im * im;
        if p > best_p {
            best_p = p;
            best = f;
        }
        f += df;
    }
    best
}

fn main() {
    let mut args = std::env::args().skip(1);
    let mus: Vec<f64> = list(args.next(), "0.3,0.4,0.5");
    let cells: Vec<usize> = list(args.next(), "8,16,32");
    let factors: Vec<f64> = list(args.next(), "0.5");
    println!(
        "{:>5} {:>9} {:>6} {:>8} {:>7} {:>10} {:>10} {:>9} {:>8} {:>8} {:>7}",
        "mu",
        "mesh",
        "h/hc",
        "h s",
        "steps",
        "mean R/N",
        "std R/N",
        "f Hz",
        "stick",
        "lifted",
        "wall s"
    );
    for &mu in &mus {
        for &c in &cells {
            for &factor in &factors {
                let nz = (c / 4).max(1);
                let set = vec![
                    format!("interface.mu_inf={mu}"),
                    format!("mesh.cells=[{c},{c},{nz}]"),
                    format!("scheme.time_step_factor={factor}"),
                ];
                let scene = load_scene("scenes/shear.toml".as_ref(), &set)
                    .unwrap_or_else(|e| panic!("{e}"));
                let started = std::time::Instant::now();
                let mut sim = Simulation::new(scene.model).unwrap_or_else(|e| panic!("{e}"));
                let (mut r, mut stick, mut lifted) = (Vec::new(), Vec::new(), Vec::new());
                let mut h = sim.state.h;
                let outcome = sim.run(|s| {
                    if s.state.time >= WINDOW.0 && s.state.time <= WINDOW.1 {
                        h = s.state.h;
                        r.push(s.stats.reactions[0]);
                        let (mut touching, mut sticking, mut up) = (0usize, 0usize, 0usize);
                        for itf in &s.state.interface_nodes {
                            match itf.contact {
                                ContactStatus::Stick => {
                                    touching += 1;
                                    sticking += 1
                                }
                                ContactStatus::Slip => touching += 1,
                                _ => {}
                            }
                            if itf.gap > 0.0 {
                                up += 1;
                            }
                        }
                        stick.push(sticking as f64 / touching.max(1) as f64);
                        lifted.push(up as f64 / s.state.interface_nodes.len() as f64);
                    }
                    true
                });
                let wall = started.elapsed().as_secs_f64();
                if let Err(e) = outcome {
                    println!("{mu:>5} {c:>4}×{c}×{nz} {factor:>6}: {e}");
                    continue;
                }
                let n = r.len() as f64;
                let mean = r.iter().sum::<f64>() / n;
                let std = (r.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n).sqrt();
                let avg = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
                println!(
                    "{:>5} {:>9} {:>6} {:>8.2e} {:>7} {:>10.4} {:>10.4} {:>9.0} {:>8.3} {:>8.3} {:>7.1}",
                    mu,
                    format!("{c}×{c}×{nz}"),
                    factor,
                    h,
                    sim.state.step_count,
                    mean.abs() / NORMAL,
                    std / NORMAL,
                    dominant_frequency(&r, h),
                    avg(&stick),
                    avg(&lifted),
                    wall
                );
            }
        }
    }
}
