//! Stage 5 on every node (PHYSICS.md §4): the free velocity and the ledger's dot products.

// The AVX builds exist on x86_64 only (wasm32 runs the portable one).
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
use super::simd::{simd_dispatch, ISA_AVX2, ISA_AVX512, ISA_PORTABLE};
use crate::mesh::dot;

/// Partial sums of the node loop (stage 5), reduced in a fixed order.
#[derive(Default, Clone, Copy)]
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
    /// impulses P).
    pub(crate) fn free_velocity_chunk / free_velocity_chunk_avx2 / free_velocity_chunk_avx512
        / free_velocity_chunk_builds
        => free_velocity_impl(
            v: &mut [[f64; 3]],
            f: &[[f64; 3]],
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
    v: &mut [[f64; 3]],
    f: &[[f64; 3]],
    m: &[f64],
    im: &[f64],
    h_bar: f64,
    g: [f64; 3],
) -> NodeSums {
    const L: usize = 8;
    let n = v.len();
    assert!(f.len() == n && m.len() == n && im.len() == n);
    let mut acc = [[0.0f64; L]; 6];
    let mut node = |i: usize, l: usize, acc: &mut [[f64; L]; 6]| {
        let (vo, fi) = (*v.get_unchecked(i), *f.get_unchecked(i));
        let (mi, imi) = (*m.get_unchecked(i), *im.get_unchecked(i));
        let (pi, pg) = internal_and_gravity_impulses(h_bar, fi, mi, g);
        let vn = [
            vo[0] + (pi[0] + pg[0]) * imi,
            vo[1] + (pi[1] + pg[1]) * imi,
            vo[2] + (pi[2] + pg[2]) * imi,
        ];
        acc[0][l] += 0.5 * mi * dot(vo, vn);
        acc[1][l] += 0.5 * mi * dot(vn, vn);
        acc[2][l] += 0.5 * dot(vo, pi);
        acc[3][l] += 0.5 * dot(vn, pi);
        acc[4][l] += 0.5 * dot(vo, pg);
        acc[5][l] += 0.5 * dot(vn, pg);
        *v.get_unchecked_mut(i) = vn;
    };
    let whole = n / L * L;
    for base in (0..whole).step_by(L) {
        for l in 0..L {
            node(base + l, l, &mut acc);
        }
    }
    for i in whole..n {
        node(i, i - whole, &mut acc);
    }
    let sum = |k: usize| acc[k].iter().fold(0.0, |s, x| s + x);
    NodeSums {
        kinetic: sum(0),
        kinetic_half: sum(1),
        int_b: sum(2),
        int_a: sum(3),
        grav_b: sum(4),
        grav_a: sum(5),
    }
}

/// The internal and gravity impulses of one node over h̄ (PHYSICS.md §4 stage 5):
/// P_int = −h̄ F_int and P_g = h̄ m g [N·s]. Used by the free velocity and by the boundary
/// pass's ledger corrections, so both take the same bits.
#[inline(always)]
pub(crate) fn internal_and_gravity_impulses(
    h_bar: f64,
    f_int: [f64; 3],
    m: f64,
    g: [f64; 3],
) -> ([f64; 3], [f64; 3]) {
    (
        [-h_bar * f_int[0], -h_bar * f_int[1], -h_bar * f_int[2]],
        [h_bar * m * g[0], h_bar * m * g[1], h_bar * m * g[2]],
    )
}
