//! `decohesion check`: validates a scene without running it and prints derived quantities.

use crate::report::state_bytes;
use crate::scene::load_scene;
use crate::solver::Simulation;
use anyhow::{Context, Result};
use std::path::Path;

/// Loads `path` with the `set` overrides, sets the simulation up and prints what it derives
/// (mesh, material, wave speed, h_crit, the interfaces' laws, memory, advisories).
pub fn check(path: &Path, set: &[String]) -> Result<()> {
    let scene = load_scene(path, set)?;
    let m = &scene.model;
    let mat = &m.material;
    let le = m.mesh.min_edge();
    let sim =
        Simulation::new(m.clone()).with_context(|| format!("setting up {}", path.display()))?;
    println!("{} is valid: {}", scene.file, m.description);
    println!(
        "  mesh                         {} nodes, {} hex8{} elements, smallest edge {:.4e} m",
        m.mesh.nodes.len(),
        m.mesh.elements.len(),
        crate::output::surface::tet_count(&m.mesh),
        le
    );
    println!(
        "  material                     {:?}, E = {:.4e} Pa, ν = {}, ρ = {} kg/m³, λ = {:.4e} Pa, μ = {:.4e} Pa",
        mat.model, mat.young, mat.poisson, mat.density, mat.lambda, mat.mu
    );
    if let Some(r) = &mat.rubber {
        println!("  rubber (model §1.10)         {r}");
        let hourglass = if m.mesh.elements.is_empty() {
            ""
        } else {
            "hourglass modulus 11μ₀; "
        };
        println!("                               (E, ν, λ, μ above: its small-strain limit; {hourglass}no element bound of the stable step, every estimate converged)");
    }
    println!("  wave speed c_d               {:.4} m/s", mat.wave_speed());
    println!(
        "  h_crit (Lanczos, §6)         {:.5e} s   (L_e/c_d = {:.5e} s would be {:+.1} % off)",
        sim.state.h_crit,
        le / mat.wave_speed(),
        100.0 * (le / mat.wave_speed() / sim.state.h_crit - 1.0)
    );
    if let Some(r) = &sim.setup.mass_scaling {
        println!(
            "  mass scaling (§6.8)          target h_t = {:.5e} s; smallest element step {:.5e} s before; {} of {} elements scaled (density × {:.4} at most); {:.6e} kg added to {:.6e} kg ({:.3} %)",
            r.target_step,
            r.smallest_element_step,
            r.scaled_elements,
            r.elements,
            r.largest_factor,
            r.added_mass,
            r.mass,
            100.0 * r.added_share()
        );
    }
    println!(
        "  time step                    h = {:.5e} s = min(factor {}, 1) × h_crit (h never exceeds h_crit)",
        sim.state.h, m.scheme.time_step_factor
    );
    println!(
        "  expected steps               {} to t = {} s",
        (m.end_time / sim.state.h).ceil(),
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
        let law = &itf.law;
        println!(
            "  interface[{k}] on `{}`         {law}, μ_inf = {}",
            itf.faces, itf.mu_inf
        );
        println!(
            "    {}: g_N(0) = {:.4e} Pa/m, α_e = {:.4e} m, u_r = {:.4e} m",
            law.spec().label,
            law.g_n0,
            law.alpha_e,
            law.u_r
        );
        if itf.initial_damage > 0.0 {
            let alpha0 = itf.initial_damage.min(itf.law.u_r);
            println!(
                "    initial damage             α₀ = {alpha0:.4e} m: {:?} from the start, μ(α₀) = {}",
                itf.law.state(alpha0),
                itf.law.mu(alpha0, itf.mu_inf)
            );
        }
        // A mixed-mode law (`bk`): G_c is the mode-I energy; mode II and mixity B differ.
        let mode_ii = match itf.law.values().get("g_iic") {
            Some(crate::law::ParamValue::Number(g)) => format!(
                " in mode I (mode II: G_IIc = {g:.5e} J/m² → {:.5e} J; mixed: Benzeggagh–Kenane)",
                g * area
            ),
            _ => String::new(),
        };
        println!(
            "    peak traction              {:.5e} Pa at δ = {:.4e} m; G_c = {:.5e} J/m²; area {:.4e} m² → {:.5e} J to break{mode_ii}",
            tmax,
            at,
            itf.law.fracture_energy(),
            area,
            itf.law.fracture_energy() * area
        );
    }
    println!(
        "  state memory                 {:.0} bytes per element",
        state_bytes(&sim) as f64 / m.mesh.element_count() as f64
    );
    let surfaces = decohesion_physics::mould::open_surface_warnings(&m.moulds);
    for w in sim.advisories().into_iter().chain(surfaces) {
        println!("  warning                      {w}");
    }
    Ok(())
}
