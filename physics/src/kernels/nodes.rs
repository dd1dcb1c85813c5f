//! Stage 5 on every node (model §4.5): the free velocity and the ledger's dot products.

// The AVX builds exist on x86_64 only (wasm32 runs the portable one).
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
use super::simd::{simd_dispatch, ISA_AVX2, ISA_AVX512};
use crate::material::{row_dot, F64x8, Real};

/// Partial sums of the node loop (stage 5), reduced in a fixed order.
#[derive(Default, Clone, Copy, serde::Serialize, serde::Deserialize)]
pub(crate) struct NodeSums {
    pub(crate) kinetic: f64,
    pub(crate) kinetic_half: f64,
    pub(crate) int_b: f64,
    pub(crate) int_a: f64,
    pub(crate) grav_b: f64,
    pub(crate) grav_a: f64,
}
impl NodeSums {
    pub(crate) fn add(self, o: NodeSums) -> NodeSums {
        NodeSums {
            kinetic: self.kinetic + o.kinetic,
            kinetic_half: self.kinetic_half + o.kinetic_half,
            int_b: self.int_b + o.int_b,
            int_a: self.int_a + o.int_a,
            grav_b: self.grav_b + o.grav_b,
            grav_a: self.grav_a + o.grav_a,
        }
    }
}

simd_dispatch! {
    /// Stage 5 on one chunk of nodes: V_free = V + h̄ M⁻¹(m g − F_int) in place, and the chunk's
    /// ledger sums (½ m V_old·V_free, ½ m V_free·V_free, ½ V·P halves of the internal and gravity
    /// impulses P). `f`: the chunk's F_int, plane by plane ([`super::Planes`]).
    pub(crate) fn free_velocity_chunk / free_velocity_chunk_avx2 / free_velocity_chunk_avx512
        / free_velocity_chunk_builds
        => free_velocity_impl(
            v: [&mut [f64]; 3],
            f: [&[f64]; 3],
            m: &[f64],
            im: &[f64],
            h_bar: f64,
            g: [f64; 3]
        ) -> NodeSums
}

/// Body of [`free_velocity_chunk`]. The velocities use no fused operation (the same bits on
/// every build); the sums are kept in 8 lanes (node i in lane i mod 8) so the loop vectorises,
/// then added lane 0 to 7: a fixed order for a given chunk, whatever the thread count.
#[inline(always)]
unsafe fn free_velocity_impl<const FMA: bool, const ISA: u8>(
    v: [&mut [f64]; 3],
    f: [&[f64]; 3],
    m: &[f64],
    im: &[f64],
    h_bar: f64,
    g: [f64; 3],
) -> NodeSums {
    const L: usize = 8;
    let n = m.len();
    assert!(v.iter().all(|p| p.len() == n) && f.iter().all(|p| p.len() == n) && im.len() == n);
    let mut acc = [F64x8::splat(0.0); 6];
    let whole = n / L * L;
    // Blocks of 8 nodes, node base + l in lane l, then the rest one by one into lane i − whole:
    // the same operations ([`free_velocity_node`]).
    for base in (0..whole).step_by(L) {
        let lanes = |p: &[f64]| F64x8(*(p.as_ptr().add(base) as *const [f64; L]));
        let vo = [lanes(v[0]), lanes(v[1]), lanes(v[2])];
        let fi = [lanes(f[0]), lanes(f[1]), lanes(f[2])];
        let (w, terms) = free_velocity_node(vo, fi, lanes(m), lanes(im), h_bar, g);
        for k in 0..6 {
            acc[k] = acc[k] + terms[k];
        }
        for c in 0..3 {
            *(v[c].as_mut_ptr().add(base) as *mut [f64; L]) = w[c].0;
        }
    }
    for i in whole..n {
        let at = |p: &[f64]| *p.get_unchecked(i);
        let vo = [at(v[0]), at(v[1]), at(v[2])];
        let fi = [at(f[0]), at(f[1]), at(f[2])];
        let (w, terms) = free_velocity_node(vo, fi, at(m), at(im), h_bar, g);
        for k in 0..6 {
            acc[k].0[i - whole] += terms[k];
        }
        for c in 0..3 {
            *v[c].get_unchecked_mut(i) = w[c];
        }
    }
    let sum = |k: usize| acc[k].0.iter().fold(0.0, |s, x| s + x);
    NodeSums {
        kinetic: sum(0),
        kinetic_half: sum(1),
        int_b: sum(2),
        int_a: sum(3),
        grav_b: sum(4),
        grav_a: sum(5),
    }
}

/// Stage 5 at one node, or at 8 in lanes (`T` = [`F64x8`]): V_free = V + (P_int + P_g)/m
/// from V = `vo`, F_int = `f`, m and 1/m = `im`, and the node's ledger terms
/// ½ m V·V_free, ½ m V_free·V_free, ½ V·P_int, ½ V_free·P_int, ½ V·P_g, ½ V_free·P_g
/// (model §4.5, §5.3). No fused operation, so every build and lane gives the same bits.
#[inline(always)]
fn free_velocity_node<T: Real>(
    vo: [T; 3],
    f: [T; 3],
    m: T,
    im: T,
    h_bar: f64,
    g: [f64; 3],
) -> ([T; 3], [T; 6]) {
    let (pi, pg) = internal_and_gravity_impulses(h_bar, f, m, g);
    // (Written out: through `array::map` the lane build kept the maps as calls and spilled.)
    let w = [
        vo[0] + (pi[0] + pg[0]) * im,
        vo[1] + (pi[1] + pg[1]) * im,
        vo[2] + (pi[2] + pg[2]) * im,
    ];
    let dot = |a: [T; 3], b: [T; 3]| row_dot::<T, false>(&a, b);
    let half = T::splat(0.5);
    (
        w,
        [
            half * m * dot(vo, w),
            half * m * dot(w, w),
            half * dot(vo, pi),
            half * dot(w, pi),
            half * dot(vo, pg),
            half * dot(w, pg),
        ],
    )
}

/// The internal and gravity impulses of one node over h̄ (model §4.5):
/// P_int = −h̄ F_int and P_g = h̄ m g [N·s]. Used by the free velocity and by the boundary
/// pass's ledger corrections, so both take the same bits.
#[inline(always)]
pub(crate) fn internal_and_gravity_impulses<T: Real>(
    h_bar: f64,
    f_int: [T; 3],
    m: T,
    g: [f64; 3],
) -> ([T; 3], [T; 3]) {
    let (nh, hm) = (T::splat(-h_bar), T::splat(h_bar) * m);
    (
        [nh * f_int[0], nh * f_int[1], nh * f_int[2]],
        [
            hm * T::splat(g[0]),
            hm * T::splat(g[1]),
            hm * T::splat(g[2]),
        ],
    )
}
