//! The Hertz check shared by the indentation tests (`mould_indent.rs`, `indent_adhesive.rs`):
//! the pad and sphere of `scenes/indent*.toml`, and the tolerance of its loading curve.

use crate::validation::{curve, record, Tol};

/// The nodal quadrature of the Hertz pressure p(r) = p₀√(1 − r²/a²) on the pad's top-face
/// grid (spacing Δx, tributary areas Δx², halved on the symmetry edges, quartered at the
/// corner), times 4, against its exact integral F = (4/3)E*√R δ^{3/2}: the error a node-based
/// contact makes on this mesh whatever the solver does, q(δ) = |Σ W p(rᵢ)/F − 1|.
fn quadrature_error(delta: f64, r: f64, dx: f64, n: usize) -> f64 {
    let a = (r * delta).sqrt();
    let mut sum = 0.0;
    for i in 0..=n {
        for j in 0..=n {
            let w = dx * dx * if i == 0 { 0.5 } else { 1.0 } * if j == 0 { 0.5 } else { 1.0 };
            let rr = ((i * i + j * j) as f64).sqrt() * dx / a;
            sum += w * (1.0 - rr * rr).max(0.0).sqrt();
        }
    }
    // ∫ p = (2/3)π a² p₀ over the full disc: Σ over the quarter × 4, per unit p₀.
    (4.0 * sum / (2.0 / 3.0 * std::f64::consts::PI * a * a) - 1.0).abs()
}

/// Hertz on loading for the (δ [m], F [N]) samples `load` (F on the full pad), checked for
/// δ ∈ [0.25, 0.95] mm with the tolerance documented on `mould_indent.rs`'s test: the
/// quadrature error q(δ), a/H for the finite pad, 1 % for the dynamics. For the validation
/// report (`case`): the loading curve against Hertz's, and the sample closest to its tolerance.
pub fn check_loading(case: &str, load: &[(f64, f64)]) {
    let (e, nu, r, dx, h) = (1e6f64, 0.3f64, 0.1f64, 2.5e-3, 0.08);
    let e_star = e / (1.0 - nu * nu);
    let hertz = |d: f64| 4.0 / 3.0 * e_star * r.sqrt() * d.powf(1.5);
    let checked_range = |p: &&(f64, f64)| p.0 >= 2.5e-4 && p.0 <= 9.5e-4;
    let tolerance = |d: f64| quadrature_error(d, r, dx, 16) + (r * d).sqrt() / h + 0.01;
    let deltas: Vec<f64> = load.iter().map(|p| 1e3 * p.0).collect();
    curve(
        case,
        "loading",
        &deltas,
        &load.iter().map(|p| p.1).collect::<Vec<_>>(),
        &load.iter().map(|p| hertz(p.0)).collect::<Vec<_>>(),
        "indentation δ [mm]",
        "force F [N]",
    );
    // The sample whose error uses the largest share of its tolerance.
    if let Some(&(d, f)) = load.iter().filter(checked_range).max_by(|p, q| {
        let share = |x: &(f64, f64)| (x.1 / hertz(x.0) - 1.0).abs() / tolerance(x.0);
        share(p).total_cmp(&share(q))
    }) {
        record(
            case,
            &format!(
                "force at δ = {:.3} mm (the sample nearest its tolerance) [N]",
                1e3 * d
            ),
            hertz(d),
            "Hertz 1882 / Johnson 1985 ((4/3)E*√R δ^{3/2})",
            f,
            Tol::Rel(tolerance(d)),
        );
    }
    let mut checked = 0;
    for &(d, f) in load.iter().filter(checked_range) {
        let tol = tolerance(d);
        let ratio = f / hertz(d);
        assert!(
            (ratio - 1.0).abs() <= tol,
            "δ = {d:.4e}: F = {f:.4e} N, Hertz {:.4e} N (ratio {ratio:.4}, tol {tol:.4})",
            hertz(d)
        );
        checked += 1;
    }
    assert!(checked > 1000, "{checked} samples");
}
