//! A mould in rigid motion (model §7), `scenes/roller_peel.toml`: a turning, translating roller (a
//! capped-cylinder `[[mould]]`) peels a rubber strip off a fixed plate and winds it up: the clamp's
//! glue anchors follow the roller's rotation about its moving pivot, the peel force is Kendall's,
//! the front follows the roller, the damage is G_c per peeled area, no node goes into a mould, and
//! the ledger closes with the roller's work.

use crate::common::{mean, scene_file, slope};
use crate::validation::{curve, record, Tol};
use decohesion_physics::model::PiecewiseLinear;
use decohesion_physics::scene::load_scene;
use decohesion_physics::solver::Simulation;

/// The value at t of a piecewise-linear history given by its rows: linear between rows,
/// constant before the first and after the last.
fn value(f: &PiecewiseLinear<3>, t: f64) -> [f64; 3] {
    let p = &f.points;
    match p.iter().position(|q| q.0 > t) {
        Some(0) => p[0].1,
        None => p[p.len() - 1].1,
        Some(k) => {
            let ((t0, a), (t1, b)) = (p[k - 1], p[k]);
            let w = (t - t0) / (t1 - t0);
            std::array::from_fn(|c| a[c] + w * (b[c] - a[c]))
        }
    }
}

/// ∫₀ᵗ f dτ by the trapezoid rule between the rows, exact for the piecewise-linear f.
fn integral(f: &PiecewiseLinear<3>, t: f64) -> [f64; 3] {
    let mut knots = vec![0.0];
    knots.extend(f.points.iter().map(|q| q.0).filter(|&s| s > 0.0 && s < t));
    knots.push(t);
    let mut acc = [0.0; 3];
    for w in knots.windows(2) {
        let (a, b) = (value(f, w[0]), value(f, w[1]));
        for c in 0..3 {
            acc[c] += 0.5 * (a[c] + b[c]) * (w[1] - w[0]);
        }
    }
    acc
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// One step's record: time, front (largest reference x of a ruptured plate node), the force F
/// on the roller from the strip [N], the damage dissipated [J].
struct Sample {
    t: f64,
    front: f64,
    force: [f64; 3],
    damage: f64,
}

/// The force and moment (about the pivot c) that the strip exerts on mould `k` over the last
/// step: W R_d at each glued node's anchor (the glue acts on the solid as −W R_d), −W R_c/h at
/// the node for each contact impulse.
fn roller_load(sim: &Simulation, k: usize, c: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let (mut f, mut m) = ([0.0; 3], [0.0; 3]);
    let x = |n: u32| -> [f64; 3] {
        std::array::from_fn(|i| {
            sim.model.mesh.nodes[n as usize][i] + sim.state.u.get(n as usize)[i]
        })
    };
    let mut add = |p: [f64; 3], fr: [f64; 3]| {
        let mm = cross(std::array::from_fn(|i| p[i] - c[i]), fr);
        for i in 0..3 {
            f[i] += fr[i];
            m[i] += mm[i];
        }
    };
    for itf in &sim.state.interface_nodes {
        if sim.model.interfaces[itf.interface as usize].plane != k {
            continue;
        }
        let anchor: [f64; 3] = std::array::from_fn(|i| x(itf.node)[i] - itf.jump[i]);
        add(anchor, itf.cohesive_traction.map(|r| r * itf.area));
        add(
            x(itf.node),
            itf.contact_impulse.map(|r| -r * itf.area / sim.state.h),
        );
    }
    for cn in sim
        .state
        .contact_nodes
        .iter()
        .filter(|cn| cn.plane as usize == k)
    {
        add(
            x(cn.node),
            cn.contact_impulse.map(|r| -r * cn.area / sim.state.h),
        );
    }
    (f, m)
}

/// The run, step by step, and what is checked at every step.
struct Run {
    sim: Simulation,
    samples: Vec<Sample>,
    /// Largest distance between a clamp node's anchor and the analytic one [m].
    anchor_error: f64,
    /// Smallest gap of any node to its mould, in units of that step's travel.
    worst_gap: f64,
    /// Σ h (F·V + M_y ω_y) with the force and moment the roller gives the strip [J].
    roller_work: f64,
    /// Largest damage of a clamp node [m].
    clamp_alpha: f64,
}

/// The run with the scene's `--set` overrides `set`.
fn run(set: &[String]) -> Run {
    let scene = load_scene(&scene_file("roller_peel.toml"), set).unwrap_or_else(|e| panic!("{e}"));
    let mut sim = Simulation::new(scene.model).unwrap_or_else(|e| panic!("{e}"));
    let roller = 1;
    assert_eq!(sim.model.moulds[roller].name, "roller");
    let u_r = sim.model.interfaces[0].law.u_r;
    let mould = sim.model.moulds[roller].clone();
    let (vel, omega) = (mould.velocity.unwrap(), mould.angular_velocity.unwrap());
    let (c0, radius) = (mould.pivot.unwrap_or(mould.point), 0.015);
    let mesh = sim.model.mesh.clone();
    let (mut samples, mut anchor_error, mut worst_gap) = (vec![], 0.0f64, f64::INFINITY);
    let (mut roller_work, mut clamp_alpha) = (0.0, 0.0f64);
    while !sim.finished() {
        sim.step().unwrap();
        let t = sim.state.time;
        let d = integral(&vel, t);
        let c: [f64; 3] = std::array::from_fn(|i| c0[i] + d[i]);
        let phi = integral(&omega, t)[1];
        // The clamp's anchors: y(t) = c(t) + R_y(φ)(y₀ − c₀), φ = ∫ω_y, R_y the rotation about
        // +y: (x, z) ↦ (x cos φ + z sin φ, −x sin φ + z cos φ).
        for itf in sim
            .state
            .interface_nodes
            .iter()
            .filter(|i| i.interface == 1)
        {
            let r: [f64; 3] = std::array::from_fn(|i| itf.bonded_point[i] - c0[i]);
            let y = [
                c[0] + r[0] * phi.cos() + r[2] * phi.sin(),
                c[1] + r[1],
                c[2] - r[0] * phi.sin() + r[2] * phi.cos(),
            ];
            let n = itf.node as usize;
            for (i, yi) in y.into_iter().enumerate() {
                let anchor = mesh.nodes[n][i] + sim.state.u.get(n)[i] - itf.jump[i];
                anchor_error = anchor_error.max((anchor - yi).abs());
            }
            clamp_alpha = clamp_alpha.max(itf.alpha);
        }
        // One step's travel: the node's speed plus the fastest point of the roller
        // (|V| + |ω|R), times h.
        let (v_now, w_now) = (value(&vel, t), value(&omega, t)[1]);
        let surface = dot(v_now, v_now).sqrt() + w_now.abs() * radius;
        let travel = |n: u32| {
            sim.state.h
                * (dot(sim.state.v.get(n as usize), sim.state.v.get(n as usize)).sqrt() + surface)
        };
        let gaps = (sim.state.interface_nodes.iter().map(|i| (i.gap, i.node)))
            .chain(sim.state.contact_nodes.iter().map(|c| (c.gap, c.node)));
        for (g, n) in gaps {
            worst_gap = worst_gap.min(g / travel(n));
        }
        let (force, moment) = roller_load(&sim, roller, c);
        roller_work -= sim.state.h * (dot(force, v_now) + moment[1] * w_now);
        let front = (sim.state.interface_nodes.iter())
            .filter(|i| i.interface == 0 && i.alpha >= u_r)
            .map(|i| mesh.nodes[i.node as usize][0])
            .fold(0.0, f64::max);
        let damage = sim.state.ledger.damage_dissipated;
        samples.push(Sample {
            t,
            front,
            force,
            damage,
        });
    }
    Run {
        sim,
        samples,
        anchor_error,
        worst_gap,
        roller_work,
        clamp_alpha,
    }
}

/// The turning mould's glue, contact and work, checked at every step of the run.
#[test]
fn the_clamp_turns_with_the_roller_and_the_ledger_closes() {
    let r = run(&[]);
    let sim = &r.sim;
    let works = sim.mould_works();
    eprintln!(
        "roller_peel: {} steps; anchor error {:.2e} m; worst gap {:.3} steps' travel; clamp α \
         ≤ {:.3e} m; roller work {:.6e} J (ledger {:.6e}), plate {:.1e}; max relative \
         residual {:.2e}",
        sim.state.step_count,
        r.anchor_error,
        r.worst_gap,
        r.clamp_alpha,
        r.roller_work,
        works[1].1,
        works[0].1,
        sim.state.ledger.max_relative_residual,
    );
    // A turning mould's glue anchors are material points of it: the analytic rotation about
    // the moving pivot to round-off (≈ 2·10⁴ composed step rotations, each exact to a few ε,
    // on a 15 mm lever: ~1e-13 m; measured 5e-15).
    let err = r.anchor_error;
    assert!(err <= 1e-12, "anchor error {err:e} m");
    // The clamp does not tear: its largest opening stays inside the elastic range α_e (no
    // damage, so all of D is the plate's).
    let clamp = &sim.model.interfaces[1].law;
    assert!(r.clamp_alpha < clamp.alpha_e, "clamp α {:e}", r.clamp_alpha);
    // No node inside a mould (the plate or the roller) by more than one step's travel.
    let gap = r.worst_gap;
    assert!(gap >= -1.0, "a node {:.3} steps' travel inside", -gap);
    // The ledger closes with the roller's work, which is the force·velocity plus moment·ω
    // rebuilt here from the impulses: to 1e-3 (the rebuild pairs each step's impulses with
    // the velocity at tₙ₊₁, the ledger with the chords of the intervals either side: an
    // O(h) difference on the start-up's fast transients; measured 1.4e-5). The plate is
    // fixed: no work. Model §5.10: the ledger closes to ~1e-5; 1e-4.
    assert_eq!(works[1].0, "roller");
    let (rebuilt, ledger) = (r.roller_work, works[1].1);
    assert!(
        (rebuilt / ledger - 1.0).abs() <= 1e-3,
        "rebuilt {rebuilt} J, ledger {ledger} J"
    );
    assert_eq!(works[0].1, 0.0);
    assert!(sim.state.ledger.max_relative_residual <= 1e-4);
}

/// A contact held on the turning roller stays out of it whatever the step (`contact_impulse`,
/// "a held contact stays a candidate while its gap is open"). The clamp's two end nodes slide
/// on the roller pressed by ~56 N; the velocity-level constraint lets their gap drift by
/// ~1e-10 m per step, in or out depending on the trajectory. Before the fix, at time-step
/// factor 0.5001 the gap drifted open (3e-11 m at step ~8400), eq. 19 released the nodes for
/// a step with their free velocity of −29 m/s, and they stayed 1.3e-4 m (12 steps' travel)
/// inside the roller: contact dissipation 7.6e-3 J against 4.8e-5 J at 0.5, the ledger's
/// largest residual 1.8e-4 (0.499, another trajectory, did not drift open). Now: no node
/// inside by one step's travel, the contact dissipation ≤ 1e-4 J (about 2× the default
/// factor's 4.8e-5 J, 1/76 of the defect's; measured 5.0e-5 and 4.8e-5 J) and the residual
/// ≤ 1e-5 (measured 3.9e-6 and 1.1e-6).
#[test]
fn a_contact_held_on_the_turning_roller_stays_out_of_it() {
    for factor in ["0.5001", "0.499"] {
        let r = run(&[format!("scheme.time_step_factor={factor}")]);
        let sim = &r.sim;
        let contact = sim.energies().contact_normal_dissipated;
        let residual = sim.state.ledger.max_relative_residual;
        eprintln!(
            "factor {factor}: worst gap {:.3} steps' travel, contact dissipation {contact:.3e} J, \
             residual {residual:.2e}",
            r.worst_gap
        );
        assert!(
            r.worst_gap >= -1.0,
            "factor {factor}: {:.3} steps' travel inside",
            -r.worst_gap
        );
        assert!(
            contact <= 1e-4,
            "factor {factor}: contact dissipation {contact:e} J"
        );
        assert!(residual <= 1e-5, "factor {factor}: residual {residual:e}");
    }
}

/// The steady peel, from 60 ms (ω constant from 55 ms) to the end: Kendall's force at the
/// measured angle, the front following the roller, G_c per peeled area.
#[test]
fn the_steady_peel_is_kendall_s_and_follows_the_roller() {
    let r = run(&[]);
    let sim = &r.sim;
    let law = &sim.model.interfaces[0].law;
    let gc = law.fracture_energy();
    let (b, t, radius, v) = (0.02, 0.003, 0.015, 1.0);
    let (young, rho) = (sim.model.material.young, sim.model.material.density);
    let roller = &sim.model.moulds[1];
    let omega = value(roller.angular_velocity.as_ref().unwrap(), 0.1)[1];
    let steady: Vec<&Sample> = r.samples.iter().filter(|s| s.t >= 0.06).collect();
    let f: [f64; 3] = std::array::from_fn(|c| mean(steady.iter().map(|s| s.force[c])));
    let f_abs = dot(f, f).sqrt();
    let cos_theta = f[0] / f_abs;
    let v_front = slope(&steady.iter().map(|s| (s.t, s.front)).collect::<Vec<_>>());
    let per_area =
        slope(&steady.iter().map(|s| (s.t, s.damage)).collect::<Vec<_>>()) / (b * v_front);
    let eps = f_abs / (young * b * t);
    // Kendall's balance at the front with the arm's stretch and the kinetic energy it carries
    // away: (F/b)(1 − cos θ) + (F/b)²/(2Et) = G_c + ρtV²(1 − cos θ), solved for F. (In the
    // frame of the front, the peeled strip runs along the arm at V: its velocity is
    // V(e_x + d), d the arm's direction, |·|² = 2V²(1 − cos θ).)
    let (a, c1) = (1.0 / (2.0 * young * t), 1.0 - cos_theta);
    let rhs = gc + rho * t * v * v * c1;
    let kendall = b * (-c1 + (c1 * c1 + 4.0 * a * rhs).sqrt()) / (2.0 * a);
    // The peeled area: ruptured nodes (α ≥ u_r), and the transition zone (0 < α < u_r) that
    // has dissipated part of its G_c.
    let area = |keep: &dyn Fn(f64) -> bool| -> f64 {
        (sim.state.interface_nodes.iter())
            .filter(|i| i.interface == 0 && keep(i.alpha))
            .map(|i| i.area)
            .sum()
    };
    let ruptured = area(&|a| a >= law.u_r);
    let transition = area(&|a| a > 0.0 && a < law.u_r);
    let (first, last) = (steady[0], *steady.last().unwrap());
    let travel = |s: &Sample| integral(roller.velocity.as_ref().unwrap(), s.t)[0];
    let (lag0, lag1) = (travel(first) - first.front, travel(last) - last.front);
    let fed = omega * (radius + t / 2.0) / (1.0 + eps);
    let d = sim.energies().damage_dissipated;
    eprintln!(
        "roller_peel steady {:.3}..{:.3} s: F = ({:.3}, {:.3}) N, θ = {:.2}°, |F| = {f_abs:.3} \
         N vs Kendall {kendall:.3} N ({:+.2} %), |F|(1 − cos θ) = {:.3} N (G_c b = {:.3}); \
         front {:.4} → {:.4} m at {v_front:.4} m/s (fed ω(R + t/2)/(1 + ε) = {fed:.4}, ε = \
         {eps:.4}); lag {lag0:.4} → {lag1:.4} m; dD/dt/(b v_front) = {per_area:.2} J/m²; D = \
         {d:.4} J = {:.4} G_c·A ruptured (+ {transition:.2e} m² in transition)",
        first.t,
        last.t,
        f[0],
        f[2],
        cos_theta.acos().to_degrees(),
        100.0 * (f_abs / kendall - 1.0),
        f_abs * c1,
        gc * b,
        first.front,
        last.front,
        d / (gc * ruptured),
    );
    // The steady peel force against Kendall at the measured angle. 3 %, as the peel scene's:
    // the force drops by ~half each time a node pair lets go (2 mm apart), and the window
    // holds ~20 of them; the direction of the mean force is the arm's to the same accuracy.
    let ts: Vec<f64> = r.samples.iter().map(|s| s.t).collect();
    curve(
        "roller_peel",
        "peel force",
        &ts,
        &r.samples
            .iter()
            .map(|s| dot(s.force, s.force).sqrt())
            .collect::<Vec<_>>(),
        &r.samples
            .iter()
            .map(|s| if s.t >= 0.06 { kendall } else { f64::NAN })
            .collect::<Vec<_>>(),
        "t [s]",
        "|F| on the roller [N]",
    );
    record(
        "roller_peel",
        "steady peel force |F| [N]",
        kendall,
        "Kendall 1975 (with stretch and kinetic terms, at the measured θ)",
        f_abs,
        Tol::Rel(0.03),
    );
    assert!(
        (f_abs / kendall - 1.0).abs() <= 0.03,
        "peel force {f_abs:.3} N, Kendall {kendall:.3} N at θ = {:.2}°",
        cos_theta.acos().to_degrees()
    );
    // A peel, not a shear: the arm leans over the roller's back, 90° < θ < 150°.
    assert!((-0.866..0.0).contains(&cos_theta), "cos θ = {cos_theta}");
    // The front follows the roller: it runs at the speed the roller frees the strip at,
    // ω(R + t/2)/(1 + ε) (the wound mid-surface, stretched by ε = F/(bEt)), and at the
    // roller's V, to 2 % (a least-squares slope over 4 cm of 2 mm steps; the mid-surface is
    // the wound strip's neutral one to O((t/2R)²) = 1 %); the lag between the roller's travel
    // and the front moves by at most two elements (each end of the window is known to one).
    let rel = |a: f64, b: f64| (a / b - 1.0).abs();
    record(
        "roller_peel",
        "front speed [m/s]",
        fed,
        "analytic (ω(R + t/2)/(1 + ε), the wound strip)",
        v_front,
        Tol::Rel(0.02),
    );
    assert!(
        rel(v_front, fed) <= 0.02,
        "front {v_front} m/s, fed {fed} m/s"
    );
    assert!(
        rel(v_front, v) <= 0.02,
        "front {v_front} m/s, roller {v} m/s"
    );
    assert!((lag1 - lag0).abs() <= 4e-3, "lag {lag0} → {lag1} m");
    // Damage: G_c per unit of peeled area in the steady state (2 %, as the front speed), and
    // in all between G_c times the ruptured area and G_c times it plus the transition zone's,
    // with the pull-off test's margins for the discrete rupture steps (0.99, 1.08).
    record(
        "roller_peel",
        "dissipation per peeled area [J/m²]",
        gc,
        "G_c (steady front)",
        per_area,
        Tol::Rel(0.02),
    );
    assert!(rel(per_area, gc) <= 0.02, "{per_area} J/m² vs G_c = {gc}");
    assert!(
        d >= 0.99 * gc * ruptured && d <= 1.08 * gc * (ruptured + transition),
        "D = {d} J, G_c·A ruptured {} J, + transition {} J",
        gc * ruptured,
        gc * (ruptured + transition)
    );
}

/// `[[mesh.face_set]]`, which the scene's clamp and contact faces use: the faces of a face set
/// whose centre lies in a box; bad input named by key and value with what is admissible.
#[test]
fn face_sets_selected_by_a_box() {
    use decohesion_physics::scene::parse_scene;
    let scene = |sets: &str| {
        let text = format!(
            "end_time = 0.1\n[mesh]\nsize = [0.1, 0.02, 0.003]\ncells = [50, 1, 2]\n{sets}\n\
             [material]\nyoung = 5e6\npoisson = 0.45\ndensity = 1100.0\n"
        );
        parse_scene(&text, "scenes/t.toml", &[])
    };
    let set = |name: &str, of: &str, min: &str, max: &str| {
        format!("[[mesh.face_set]]\nname = {name:?}\nof = {of:?}\nmin = {min}\nmax = {max}\n")
    };
    let clamp = set("clamp", "z+", "[-1, -1, -1]", "[0.002, 1, 1]");
    let top = set("top", "z+", "[0.004, -1, -1]", "[1, 1, 1]");
    let m = scene(&format!("{clamp}{top}")).unwrap().model;
    let mesh = &m.mesh;
    // The first face of the top (centre x = 1 mm), and the 48 from x = 4 mm on.
    assert_eq!(mesh.face_sets["clamp"].len(), 1);
    assert_eq!(mesh.face_sets["top"].len(), 48);
    let xs: Vec<f64> = (mesh.face_set_nodes(&mesh.face_sets["clamp"]).iter())
        .map(|&n| mesh.nodes[n as usize][0])
        .collect();
    assert!(
        xs.iter().all(|&x| x == 0.0 || (x - 0.002).abs() < 1e-15),
        "{xs:?}"
    );
    // Each selected face is a face of `of`, unchanged (outward order kept).
    assert!(mesh.face_sets["top"]
        .iter()
        .all(|q| mesh.face_sets["z+"].contains(q)));
    let error = |sets: String| scene(&sets).map(|_| ()).expect_err("refused").to_string();
    let e = error(set("z-", "z+", "[0, 0, 0]", "[1, 1, 1]"));
    assert!(
        e.contains("mesh.face_set[0].name") && e.contains("exists already"),
        "{e}"
    );
    let e = error(set("a", "bottom", "[0, 0, 0]", "[1, 1, 1]"));
    assert!(
        e.contains("mesh.face_set[0].of") && e.contains("`z+`"),
        "{e}"
    );
    let e = error(set("a", "z+", "[0, 0.5, 0]", "[1, 0.1, 1]"));
    assert!(
        e.contains("mesh.face_set[0].min") && e.contains("min ≤ max"),
        "{e}"
    );
    let e = error(format!(
        "{clamp}{}",
        set("b", "z+", "[0.2, 0, 0]", "[1, 1, 1]")
    ));
    assert!(
        e.contains("mesh.face_set[1].max") && e.contains("no face of `z+`"),
        "{e}"
    );
    // A set selected before can be selected from.
    let m = scene(format!("{top}{}", set("far", "top", "[0.05, -1, -1]", "[1, 1, 1]")).as_str());
    assert_eq!(m.unwrap().model.mesh.face_sets["far"].len(), 25);
}
