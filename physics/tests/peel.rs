//! The peel scenes (scenes/peel.toml, scenes/peel_135.toml) at 90°, 45° and 135° against
//! Kendall's energy balance, and at a laboratory speed with mass scaling.

use crate::common::{mean, ruptured_front, slope};
use crate::teaching_scenes::start;
use crate::validation::{curve, record, Tol};
use decohesion_physics::solver::Simulation;

/// The 90° peel (scenes/peel.toml). The strip's end face is lifted at V with x free, so the
/// pulling force is vertical; once the arm is long enough to have a straight part between the
/// bend at the front and the one at the clamped end, the front runs at V/(1 + ε) and the force
/// per width follows Kendall's energy balance, (F/b)(1 − cos θ) + (F/b)²/(2Et) = G_c + ρtV²
/// (the second term is the arm's stretch ε = F/(bEt), the last its kinetic energy: the arm
/// moves at (V_f, V), so it gains ½ρbt(V_f² + V²) per unit of peeled length, ≈ ρbtV²).
///
/// The same strip at 45°, its end pulled along a line (up at V, sideways at 0.28 V, as lesson 3
/// does): Kendall's force is three times that at 90° and the arm stretches by 7.6 %, so the
/// stretch term matters (the plain G_c/(1 − cos θ) is 12 % above).
///
/// The strip at 135° (scenes/peel_135.toml), peeled back over itself: a rigid grip glued to the
/// end turns a free leader over by 135° and then moves along the steady arm's path, so the end
/// turns with the arm (an end face with prescribed components keeps its orientation, and the
/// arm would bend by 135° there). Kendall's force is 0.6 times that at 90°. The three peels run
/// side by side.
#[test]
fn peel_front_runs_and_the_force_is_kendall_s() {
    std::thread::scope(|scope| {
        scope.spawn(|| kendall_peel(start("peel", &[]), "kendall_peel", 90.0, AT_90, End::Face));
        scope.spawn(|| {
            let sim = start(
                "peel",
                &[
                    "displacement=[{faces=\"x-\",component=\"z\",table=[[0.0,0.0],[0.14,0.14]]},\
                     {faces=\"x-\",component=\"x\",table=[[0.0,0.0],[0.14,0.0392]]}]",
                ],
            );
            kendall_peel(sim, "kendall_peel_45", 45.0, AT_45, End::Face)
        });
        scope.spawn(|| {
            let sim = start("peel_135", &[]);
            let grip = End::Grip {
                mould: 1,
                interface: 1,
            };
            kendall_peel(sim, "kendall_peel_135", 135.0, AT_135, grip)
        });
    });
}

/// The same peel at a laboratory speed, 5 mm/s (28 s to lift the end by 0.14 m), with mass
/// scaling (model §6.8) to a target step of 1 ms: about 11 000 times the density, and 160 times
/// fewer steps than the 6·10⁶ the unscaled strip would take. The lifting speed over the scaled
/// bar wave speed is 1 %, as at 1 m/s unscaled, so the peel is as quasi-static, and Kendall's
/// balance holds with the same tolerances (its kinetic term takes the scaled density). The
/// added mass's kinetic energy stays below the 5 % of the stored energy that the warning
/// watches.
#[test]
fn peel_at_laboratory_speed_with_mass_scaling_is_kendall_s() {
    let sim = start(
        "peel",
        &[
            "end_time=28",
            "displacement.0.table=[[0.0, 0.0], [28.0, 0.14]]",
            "mass_scaling.target_step=1e-3",
        ],
    );
    let r = sim.setup.mass_scaling.expect("mass scaling is on");
    assert_eq!(
        r.scaled_elements, r.elements,
        "a uniform strip: every element"
    );
    assert!(
        sim.state.h_crit >= r.target_step,
        "h_crit {:.4e} s",
        sim.state.h_crit
    );
    let sim = kendall_peel(sim, "kendall_peel_mass_scaled", 90.0, AT_90, End::Face);
    let r = sim.setup.mass_scaling.expect("mass scaling is on");
    eprintln!(
        "mass-scaled peel: {} steps, h_crit {:.4e} s, density × {:.0}, added kinetic energy {:.3e} J = {:.3} % of the largest stored {:.3e} J",
        sim.state.step_count,
        sim.state.h_crit,
        r.largest_factor,
        r.added_kinetic_peak,
        100.0 * r.kinetic_share(),
        r.stored_peak
    );
    assert!(
        r.kinetic_share() <= 0.05,
        "added kinetic energy {:.3} % of the stored",
        100.0 * r.kinetic_share()
    );
    assert!(sim.advisories().iter().all(|w| !w.contains("mass scaling")));
}

/// The tolerances of [`kendall_peel`] (its comments justify each): on the force against
/// Kendall, on the front speed against the fed one, on the arm's stretch against F/(bEt).
#[derive(Clone, Copy)]
struct PeelTolerances {
    force: f64,
    angle: f64,
    front_speed: f64,
    stretch: f64,
}

/// At 90° (the shipped peel).
const AT_90: PeelTolerances = PeelTolerances {
    force: 0.03,
    angle: 3.0,
    front_speed: 0.02,
    stretch: 0.05,
};

/// At 135°: as at 90° (the arm stretches by 1.5 %, and 1° on θ moves Kendall's force by 0.7 %),
/// with 4° on the angle: the grip's path puts the end on the straight arm's line as the bend at
/// the front sets it, which the scene states to about 1°, and the arm swings by ±2° about it.
const AT_135: PeelTolerances = PeelTolerances {
    angle: 4.0,
    ..AT_90
};

/// At 45°.
const AT_45: PeelTolerances = PeelTolerances {
    force: 0.05,
    angle: 3.0,
    front_speed: 0.03,
    stretch: 0.10,
};

/// How the peel's end is driven: its end face's prescribed components (their reactions are the
/// pull), or a rigid grip glued to it (mould `mould`, glued by interface `interface`; the force
/// its glue and contact exert on the grip is the pull).
#[derive(Clone, Copy)]
enum End {
    Face,
    Grip { mould: usize, interface: u32 },
}

/// Runs the peel `sim` (scenes/peel.toml, its end face pulled along z and, for an angle other
/// than 90°, along x; or scenes/peel_135.toml, its end held by a grip) to its end and checks it
/// against Kendall's balance (doc of [`peel_front_runs_and_the_force_is_kendall_s`]) and the
/// arm's angle against `angle` (in degrees), recording the comparisons as `case`; the kinetic
/// term takes the density of the mass actually moving (mass scaling included).
///
/// The balance at any angle: once steady, the straight arm moves as a rigid body at the end's
/// velocity v, and per unit of peeled length the pull's work F(1 − cos θ + ε) pays for G_c b,
/// the arm's strain energy Fε/2 and the kinetic energy ½ρbt|v|² of the material it takes up:
/// (F/b)(1 − cos θ) + (F/b)²/(2Et) = G_c + ½ρt|v|². With x free (90°) the end follows the front,
/// v = (V_f, V); with x prescribed (or a grip), v is the prescribed velocity. The front runs at
/// V_f = V_z/((1 + ε) sin θ) (the end is (1 + ε) s along the arm from the front, s the peeled
/// length).
fn kendall_peel(
    mut sim: Simulation,
    case: &str,
    angle: f64,
    tol: PeelTolerances,
    end: End,
) -> Simulation {
    let law = sim.model.interfaces[0].law.clone();
    let gc = law.fracture_energy();
    let young = sim.model.material.young;
    let rho = sim.model.material.density
        * sim
            .setup
            .mass_scaling
            .map_or(1.0, |r| 1.0 + r.added_mass / r.mass);
    let mesh = sim.model.mesh.clone();
    // The strip: 200 × 10 × 4 mm, 100 × 1 × 2 elements (element e = i + nx·k).
    let (length, b, t, nx) = (0.2, 0.01, 0.004, 100);
    assert_eq!(mesh.elements.len(), 2 * nx);
    // The end's prescribed velocity components once steady (constant speeds): z always, x if
    // prescribed.
    let speed = |component: usize| match end {
        End::Face => {
            let d = sim
                .model
                .displacements
                .iter()
                .find(|d| d.component == component)?;
            Some(d.history.value(0.1)[0] / 0.1)
        }
        End::Grip { mould, .. } => {
            let v = sim.model.moulds[mould].velocity.as_ref()?;
            Some(v.value(sim.model.end_time)[component])
        }
    };
    let v_lift = speed(2).expect("the end is lifted along z");
    let v_side = speed(0);
    // (t, front, |F|/b, θ, stretch of the arm, damage dissipated)
    let mut samples: Vec<[f64; 6]> = vec![];
    let mut front_went_back = None;
    while !sim.finished() {
        sim.step().unwrap();
        // The front: the largest reference x of a ruptured interface node.
        let front = ruptured_front(&sim, 0.0);
        if samples.last().is_some_and(|s| front < s[1]) {
            front_went_back.get_or_insert(sim.state.time);
        }
        // The arm's angle. Per column of elements, the mean F·e_x of its two layers is the
        // mid-surface's material direction; the arm's direction from the front to the end is
        // −F·e_x, so cos θ = (F·e_x)_x/|F·e_x| (θ = 0 would be lap shear, 180° peeling back over
        // the strip), and |F·e_x| − 1 is its stretch. Both bends turn their neighbourhood from
        // the arm's θ towards 0 (the bonded strip at the front, the end face, which keeps its
        // orientation, at the end): the straight part is the column of largest θ.
        let (mut theta, mut stretch) = (f64::NAN, f64::NAN);
        for i in 0..nx {
            let xc = (i as f64 + 0.5) * length / nx as f64;
            if xc < 0.01 || xc > front - 0.01 {
                continue;
            }
            let mut fx = [0.0; 3];
            for k in 0..2 {
                let f = mesh.centre_deformation_gradient(i + nx * k, &sim.state.u);
                for c in 0..3 {
                    fx[c] += 0.5 * f[c][0];
                }
            }
            let len = (fx[0] * fx[0] + fx[1] * fx[1] + fx[2] * fx[2]).sqrt();
            let th = (fx[0] / len).acos();
            if theta.is_nan() || th > theta {
                (theta, stretch) = (th, len - 1.0);
            }
        }
        // The pull: every prescribed component's reaction on the end face, or the force on the
        // grip (its glue's W R_d and its contact's −W R_c/h at each glued node).
        let pull = match end {
            End::Face => sim
                .stats
                .reactions
                .iter()
                .map(|r| r * r)
                .sum::<f64>()
                .sqrt(),
            End::Grip { interface, .. } => {
                let mut f = [0.0; 3];
                for itf in sim.state.interface_nodes.iter() {
                    if itf.interface == interface {
                        for (c, fc) in f.iter_mut().enumerate() {
                            *fc += itf.area
                                * (itf.cohesive_traction[c] - itf.contact_impulse[c] / sim.state.h);
                        }
                    }
                }
                (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt()
            }
        };
        samples.push([
            sim.state.time,
            front,
            pull / b,
            theta,
            stretch,
            sim.state.ledger.damage_dissipated,
        ]);
    }
    // Steady window: the front past 8 cm. Before, the arm is too short for a straight part
    // between the two bends (elastica length √(D b/F) ≈ 1 cm each, longer with the bending
    // stiffness of two full-integration hex8 through the thickness) and still swings.
    let steady: Vec<&[f64; 6]> = samples.iter().filter(|s| s[1] >= 0.08).collect();
    let force = mean(steady.iter().map(|s| s[2]));
    let theta = mean(steady.iter().map(|s| s[3]));
    let eps = mean(steady.iter().map(|s| s[4]));
    let v_front = slope(&steady.iter().map(|s| (s[0], s[1])).collect::<Vec<_>>());
    let d_rate = slope(&steady.iter().map(|s| (s[0], s[5])).collect::<Vec<_>>());
    let (theta_min, theta_max) = steady.iter().fold((f64::INFINITY, 0.0f64), |(a, z), s| {
        (a.min(s[3]), z.max(s[3]))
    });
    // Kendall's balance solved for F/b at the measured θ.
    let v_x = v_side.unwrap_or(v_front);
    let rhs = gc + 0.5 * rho * t * (v_lift * v_lift + v_x * v_x);
    let (a, c1) = (1.0 / (2.0 * young * t), 1.0 - theta.cos());
    let kendall = (-c1 + (c1 * c1 + 4.0 * a * rhs).sqrt()) / (2.0 * a);
    // The front speed the end's motion feeds: the end moves at V_f(1 + ε) along the arm
    // relative to the point of the strip at the front, which runs at V_f along x, so
    // |v − V_f e_x| = V_f (1 + ε): with x free (v_x = V_f), V_f = V_z/(1 + ε); with x
    // prescribed, the root of V_f²((1 + ε)² − 1) + 2 v_x V_f − |v|² = 0. No θ in it.
    let v_feed = match v_side {
        None => v_lift / (1.0 + eps),
        Some(vx) => {
            let qa = (1.0 + eps) * (1.0 + eps) - 1.0;
            let v2 = vx * vx + v_lift * v_lift;
            (-vx + (vx * vx + qa * v2).sqrt()) / qa
        }
    };
    let last = samples.last().unwrap();
    let ts: Vec<f64> = samples.iter().map(|s| s[0]).collect();
    curve(
        case,
        "peel force",
        &ts,
        &samples.iter().map(|s| s[2]).collect::<Vec<_>>(),
        &samples
            .iter()
            .map(|s| if s[1] >= 0.08 { kendall } else { f64::NAN })
            .collect::<Vec<_>>(),
        "t [s]",
        "F/b [N/m]",
    );
    eprintln!(
        "peel at {angle}°: front at {:.4} m after {:.3} s, steady window {:.4}..{:.4} s ({} steps): \
         F/b = {force:.2} N/m, θ = {:.2}° ({:.2}..{:.2}°), arm stretch {eps:.4} (F/(bEt) = \
         {:.4}); Kendall {kendall:.2} N/m ({:+.2} %; plain G_c/(1 − cos θ) = {:.2}); front speed \
         {v_front:.4} m/s (fed {:.4}, {:+.2} %); dD/dt / (b v_front) = {:.2} J/m² \
         (G_c = {gc}); max relative residual {:.2e}",
        last[1],
        last[0],
        steady[0][0],
        last[0],
        steady.len(),
        theta.to_degrees(),
        theta_min.to_degrees(),
        theta_max.to_degrees(),
        force / (young * t),
        100.0 * (force / kendall - 1.0),
        gc / c1,
        v_feed,
        100.0 * (v_front / v_feed - 1.0),
        d_rate / (b * v_front),
        sim.state.ledger.max_relative_residual,
    );

    // The front only advances (damage is irreversible), and it got far: 12 cm of 20.
    assert_eq!(front_went_back, None, "the front moved back");
    assert!(last[1] >= 0.12, "the front reached only {:.4} m", last[1]);
    // Large rotation: the arm's straight part is turned by `angle` from the bonded strip
    // (upright at 90°), within `tol.angle` all along the window (it swings by up to 2°; with x
    // prescribed, the angle is set by the end's path and the arm's stretch).
    assert!(
        (theta_min.to_degrees() - angle).abs() <= tol.angle
            && (theta_max.to_degrees() - angle).abs() <= tol.angle,
        "arm angle {:.2}..{:.2}°",
        theta_min.to_degrees(),
        theta_max.to_degrees()
    );
    // The peel force per width against Kendall at the measured angle, within `tol.force`. At 90°,
    // 3 %: the force drops by ~10 % each time a node pair lets go (2 mm apart); the mean over
    // the ~25 of the window is good to ~1 %; θ is a mean over its swing, and 1° on θ moves
    // Kendall's force by 1.7 % at 90°. At 45°, 5 %: 1° on θ moves it by 3.3 % (sin θ over
    // 1 − cos θ + ε), and the arm's 7.6 % stretch is past the linear elasticity Kendall's
    // stretch term assumes.
    record(
        case,
        "steady peel force per width F/b [N/m]",
        kendall,
        "Kendall 1975 (with stretch and kinetic terms, at the measured θ)",
        force,
        Tol::Rel(tol.force),
    );
    assert!(
        (force / kendall - 1.0).abs() <= tol.force,
        "peel force {force:.2} N/m, Kendall {kendall:.2} N/m at θ = {:.2}°",
        theta.to_degrees()
    );
    // The front runs at the speed the arm is fed (above), within `tol.front_speed`: at 90°
    // 2 %, a least-squares slope over 5 cm of 2 mm steps; at 45° 3 %, as the fed speed there
    // moves by ~1.5 % per 0.005 of the arm's stretch, which is the stretch of one column and
    // varies by that much along the arm.
    record(
        case,
        "front speed [m/s]",
        v_feed,
        "analytic (|v − V_f e_x| = V_f (1 + ε), inextensible feed)",
        v_front,
        Tol::Rel(tol.front_speed),
    );
    assert!(
        (v_front / v_feed - 1.0).abs() <= tol.front_speed,
        "front speed {v_front:.4} m/s, fed {v_feed:.4} m/s"
    );
    // The arm's stretch is the tension's: ε = F/(bEt), within `tol.stretch`: 5 % at 90°
    // (neo-Hookean at 2.5 %: 1st order); 10 % at 45°, where the arm stretches by 7.6 % and a
    // neo-Hookean bar is softer than E by about as much (incompressible: P = μ(λ − λ⁻²)
    // against 3με).
    assert!(
        (eps / (force / (young * t)) - 1.0).abs() <= tol.stretch,
        "stretch {eps:.4}, F/(bEt) = {:.4}",
        force / (young * t)
    );
    // Steady state: the energy dissipated per unit of peeled area is G_c (the cohesive zone
    // travels with the front). 2 %, as the front speed.
    record(
        case,
        "dissipation per peeled area [J/m²]",
        gc,
        "G_c (steady front)",
        d_rate / (b * v_front),
        Tol::Rel(0.02),
    );
    assert!(
        (d_rate / (b * v_front) / gc - 1.0).abs() <= 0.02,
        "dissipation rate {:.2} J/m² of peeled area, G_c = {gc}",
        d_rate / (b * v_front)
    );
    // Model §5.10: the ledger closes to ~1e-5; 1e-4.
    record(
        &format!("ledger_{}", case.trim_start_matches("kendall_")),
        "largest relative residual of the energy balance",
        0.0,
        "energy balance (model §5.10)",
        sim.state.ledger.max_relative_residual,
        Tol::Abs(1e-4),
    );
    assert!(sim.state.ledger.max_relative_residual <= 1e-4);
    sim
}
