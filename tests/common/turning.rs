//! A turning mould for the output tests: the indent scene with a box mould above the pad
//! (never touching it) that turns at a constant ω about a pivot off its centre while the pivot
//! moves at a constant v; and its analytic pose, x = R(t)(x₀ − c₀) + c₀ + v t with
//! R(t) = exp([ω t]×).

use std::path::{Path, PathBuf};

/// ω [rad/s], |ω| = 13.
pub const OMEGA: [f64; 3] = [3.0, 4.0, 12.0];
/// v of the pivot [m/s].
pub const VELOCITY: [f64; 3] = [0.0, 0.0, 0.5];
/// The pivot c₀ [m].
pub const PIVOT: [f64; 3] = [0.25, 0.3, 0.3];
/// A coarse, short run: 0.05 s, 0.65 rad.
pub const OVERRIDES: [&str; 2] = ["mesh.cells=[2,2,4]", "end_time=0.05"];

/// Writes the scene to `dir/turning.toml` (the mould is called `paddle`).
pub fn scene(dir: &Path) -> PathBuf {
    let path = dir.join("turning.toml");
    let row = |a: [f64; 3]| format!("[[0.0, {:?}, {:?}, {:?}]]", a[0], a[1], a[2]);
    let text = std::fs::read_to_string("scenes/indent.toml").unwrap()
        + &format!(
            "\n[[mould]]\nname = \"paddle\"\nshape = \"box\"\ncentre = [0.3, 0.3, 0.3]\n\
             size = [0.04, 0.02, 0.01]\npivot = {:?}\nvelocity = {}\nangular_velocity = {}\n",
            PIVOT,
            row(VELOCITY),
            row(OMEGA)
        );
    std::fs::write(&path, text).unwrap();
    path
}

/// The analytic pose at t: x = R(t)(x₀ − c₀) + c₀ + v t.
pub fn place(t: f64, x0: [f64; 3]) -> [f64; 3] {
    let r = rotation(OMEGA.map(|w| w * t));
    let d: [f64; 3] = std::array::from_fn(|i| x0[i] - PIVOT[i]);
    std::array::from_fn(|i| {
        (0..3).map(|j| r[i][j] * d[j]).sum::<f64>() + PIVOT[i] + VELOCITY[i] * t
    })
}

/// R = exp([θ k]×) = I + sin θ K + (1 − cos θ) K², K = [k]× (Rodrigues), for the rotation
/// vector φ = θ k.
pub fn rotation(phi: [f64; 3]) -> [[f64; 3]; 3] {
    let theta = (phi[0] * phi[0] + phi[1] * phi[1] + phi[2] * phi[2]).sqrt();
    if theta == 0.0 {
        return std::array::from_fn(|i| std::array::from_fn(|j| f64::from(u8::from(i == j))));
    }
    let k = phi.map(|c| c / theta);
    let kx = [[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]];
    std::array::from_fn(|i| {
        std::array::from_fn(|j| {
            let k2: f64 = (0..3).map(|m| kx[i][m] * kx[m][j]).sum();
            f64::from(u8::from(i == j)) + theta.sin() * kx[i][j] + (1.0 - theta.cos()) * k2
        })
    })
}
