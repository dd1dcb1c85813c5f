//! The reference pull-off test (model §9) from scenes/pull_off.toml: full rupture at about
//! a third of the run, a free cube afterwards, a ledger that closes, and its residual falling as
//! h² (model §5.10).

use crate::common::scene_file;
use crate::validation::{record, Tol};

use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;

fn run(overrides: &[&str]) -> Simulation {
    let set: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let scene = load_scene(&scene_file("pull_off.toml"), &set).unwrap();
    let mut sim = Simulation::new(scene.model).unwrap();
    sim.run(|_| true).unwrap();
    sim
}

#[test]
fn pull_off_tears_off_at_a_third_and_the_ledger_closes() {
    let sim = run(&[]);
    let end = sim.model.end_time;
    let n_itf = sim.state.interface_nodes.len();
    assert_eq!(n_itf, 64);
    // Paper fig. 6: the whole interface is damaged at about a third of the simulated time.
    let t_rupture = sim
        .stats
        .time_full_rupture
        .expect("the interface must tear off");
    record(
        "pull_off",
        "time of full rupture [s]",
        end / 3.0,
        "paper Fig. 6 (≈ T/3)",
        t_rupture,
        Tol::Between(0.25 * end, 0.45 * end),
    );
    assert!(
        (0.25 * end..0.45 * end).contains(&t_rupture),
        "full rupture at {t_rupture} s of {end} s"
    );
    let t_damage = sim.stats.time_first_damage.unwrap();
    assert!(t_damage < t_rupture);
    assert_eq!(sim.state_counts().ruptured, n_itf);
    // The cube then moves freely: positive gap everywhere at the end.
    for itf in &sim.state.interface_nodes {
        assert!(
            itf.gap > 0.0,
            "node {} still touches the mould (gap {})",
            itf.node,
            itf.gap
        );
    }
    // The pull-off force: the interface carries at most T_max × area = 1 MN; the edges tear
    // first, so the peak is lower, and it must be far above gravity (ρ g V = 10.8 kN).
    let peak = &sim.stats.peaks[0];
    assert!(
        peak.force > 1e5 && peak.force < 1.0e6,
        "peak {}",
        peak.force
    );
    assert!(peak.time < t_rupture);
    // Dissipation by damage: every node ruptured, so Σ W G_c = G_c·A up to the discrete
    // rupture steps.
    assert_full_rupture_dissipation(&sim, "pull_off");
    // Model §5.10: an exact ledger is ~1e-5..1e-4 here; 0.5 % would be a bug.
    record(
        "ledger_pull_off",
        "largest relative residual of the energy balance",
        0.0,
        "energy balance (model §5.10)",
        sim.state.ledger.max_relative_residual,
        Tol::Abs(1e-3),
    );
    assert!(
        sim.state.ledger.max_relative_residual < 1e-3,
        "residual {}",
        sim.state.ledger.max_relative_residual
    );
}

#[test]
fn balance_residual_falls_as_h_squared() {
    // Fixed step (no re-estimate) so only h changes between the runs.
    let a = run(&[
        "scheme.time_step_factor=0.5",
        "scheme.h_crit_update_interval=0",
    ]);
    let b = run(&[
        "scheme.time_step_factor=0.25",
        "scheme.h_crit_update_interval=0",
    ]);
    let (ra, rb) = (
        a.state.ledger.max_relative_residual,
        b.state.ledger.max_relative_residual,
    );
    // Second order: ratio 4 in theory; measured 3.7. Below 2.8 the ledger has an O(h) leak.
    record(
        "ledger_pull_off",
        "residual ratio at h and h/2 (second order)",
        4.0,
        "analytic (O(h²), model §5.10)",
        ra / rb,
        Tol::Between(2.8, f64::INFINITY),
    );
    assert!(
        ra / rb > 2.8,
        "residual {ra:e} at h, {rb:e} at h/2: ratio {}",
        ra / rb
    );
}

#[test]
fn summaries_are_bit_identical_with_one_two_and_three_threads() {
    // 14³ = 2744 elements: above the threshold where the loops run on the thread team; 3
    // threads on this 2-core machine split every loop unevenly and oversubscribe the cores.
    for integration in ["full", "reduced"] {
        let go = |threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            pool.install(|| {
                let rule = format!("scheme.integration=\"{integration}\"");
                let sim = run(&["mesh.cells=[14,14,14]", "end_time=0.03", &rule]);
                let e = sim.energies();
                let alphas: Vec<u64> = sim
                    .state
                    .interface_nodes
                    .iter()
                    .map(|i| i.alpha.to_bits())
                    .collect();
                let u: Vec<u64> = sim.state.u.rows().flatten().map(|x| x.to_bits()).collect();
                let r: Vec<u64> = sim.stats.reactions.iter().map(|x| x.to_bits()).collect();
                (format!("{e:?}"), alphas, u, r, sim.state.step_count)
            })
        };
        let (one, two, three) = (go(1), go(2), go(3));
        assert!(one.4 > 50);
        assert!(one == two, "{integration}: 1 and 2 threads differ");
        assert!(one == three, "{integration}: 1 and 3 threads differ");
    }
}

/// After a run in which every glued node of the first interface ruptured: the damage
/// dissipation D lies within [0.99, 1.08] G_c·A, recorded for the validation report as `case`.
/// Each node dissipates its W·G_c once it ruptures; the band allows the discrete rupture steps
/// (a node's last increment of D overshoots by O(h)) and nothing else.
pub fn assert_full_rupture_dissipation(sim: &Simulation, case: &str) {
    assert_eq!(
        sim.state_counts().ruptured,
        sim.state.interface_nodes.len(),
        "{case}: not every glued node ruptured"
    );
    let gc_area = sim.model.interfaces[0].law.fracture_energy();
    let d = sim.state.ledger.damage_dissipated;
    record(
        case,
        "damage dissipation D [J]",
        gc_area,
        "G_c·A (every node ruptured)",
        d,
        Tol::Between(0.99 * gc_area, 1.08 * gc_area),
    );
    assert!(
        d >= 0.99 * gc_area && d <= 1.08 * gc_area,
        "{case}: damage dissipation {d} vs G_c·A {gc_area}"
    );
}
