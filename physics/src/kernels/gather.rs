//! Moving nodal data between the planes of U and F_int and the lanes of a kernel: gathering a
//! lane group's displacements, scattering its forces (whole rows of elements along x 8 nodes at
//! a time, other groups lane by lane), and prefetching a group's nodes when the nodal fields
//! exceed the last-level cache. Only data moves here: every value keeps its bits.

#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
use super::simd;
#[cfg_attr(not(target_arch = "x86_64"), allow(unused_imports))]
use super::simd::{ISA_AVX2, ISA_AVX512};
use super::PlanesPtr;
use crate::material::F64x8;
use crate::mesh::rows::X_EDGES;
use crate::mesh::{ElementClasses, Mesh};

/// Stages the displacements of the 8 nodes of the 8 elements `group` into lanes,
/// `ul[a][j][l]` = U_j[conn(group[l])[a]] from the planes of U ([`Planes`](super::Planes)): on a row along x
/// (`row`, [`group_is_row`]) node a of lane l is node a of the first element plus l, so each
/// `ul[a][j]` is 8 consecutive numbers of plane j, one vector load; elsewhere element by
/// element. Only data moves, so every value keeps its bits.
///
/// # Safety
/// `group` holds 8 elements; every one and every node of theirs must be in range.
#[inline(always)]
pub(super) unsafe fn gather_group(
    mesh: &Mesh,
    u: [&[f64]; 3],
    group: &[u32],
    row: bool,
    ul: &mut [[[f64; 8]; 3]; 8],
) {
    if row {
        let first = mesh
            .elements
            .get_unchecked(*group.get_unchecked(0) as usize);
        for a in 0..8 {
            for j in 0..3 {
                ul[a][j] = *(u[j].as_ptr().add(first[a] as usize) as *const [f64; 8]);
            }
        }
        return;
    }
    for (l, &e) in group.iter().enumerate() {
        let conn = mesh.elements.get_unchecked(e as usize);
        for a in 0..8 {
            let i = conn[a] as usize;
            for j in 0..3 {
                ul[a][j][l] = *u[j].get_unchecked(i);
            }
        }
    }
}

/// Bytes per node of the fields a step streams: U, V and F_int, 3 f64 each.
pub(super) const NODAL_BYTES: usize = 72;

/// Whether the element loops should prefetch each lane group's nodes ([`prefetch_group`]):
/// when U, V and F_int (72 bytes per node) do not fit in the last-level cache
/// ([`last_level_cache_bytes`]; 32 MiB where it cannot be read). Measured with the full
/// kernel: slower while the nodal fields fit in the cache, faster once they do not: the hints
/// cost issue slots, and only data coming from memory repays them (docs: performance log).
/// Never in the web page: WebAssembly has no prefetch ([`prefetch_group`] is empty there), and
/// its element loops are built without the hints ([`super::simd::simd_dispatch`]).
pub fn prefetch_pays(nodes: usize) -> bool {
    !cfg!(target_arch = "wasm32")
        && nodes.saturating_mul(NODAL_BYTES) > last_level_cache_bytes().unwrap_or(32 << 20)
}

/// The size of CPU 0's largest cache level, from Linux's sysfs
/// (`/sys/devices/system/cpu/cpu0/cache/index*/{level,size}`); None elsewhere (or in a browser).
pub fn last_level_cache_bytes() -> Option<usize> {
    static SIZE: std::sync::OnceLock<Option<usize>> = std::sync::OnceLock::new();
    *SIZE.get_or_init(|| {
        let dir = std::fs::read_dir("/sys/devices/system/cpu/cpu0/cache").ok()?;
        let mut best: Option<(u32, usize)> = None;
        for entry in dir.flatten() {
            let read = |f: &str| std::fs::read_to_string(entry.path().join(f)).ok();
            let (Some(level), Some(size)) = (read("level"), read("size")) else {
                continue;
            };
            let Ok(level) = level.trim().parse::<u32>() else {
                continue;
            };
            if let Some(bytes) = cache_size_bytes(&size) {
                if best.is_none_or(|(l, _)| level > l) {
                    best = Some((level, bytes));
                }
            }
        }
        best.map(|(_, b)| b)
    })
}

/// A cache size as sysfs writes it ("32768K", "1M", "512"), in bytes; None if unreadable.
pub(super) fn cache_size_bytes(size: &str) -> Option<usize> {
    let size = size.trim();
    let (digits, shift) = match size.as_bytes().last() {
        Some(b'K') => (&size[..size.len() - 1], 10),
        Some(b'M') => (&size[..size.len() - 1], 20),
        Some(b'G') => (&size[..size.len() - 1], 30),
        _ => (size, 0),
    };
    digits.parse::<usize>().ok()?.checked_mul(1 << shift)
}

/// Asks the cache for the displacements and forces of the lane group `group` (the next one)
/// while the current group computes: the nodes a₀ of its first element's x-edges and a₁ of its
/// last one's, in each plane of U and F_int. On a row ([`group_is_row`]) these are the two
/// ends of its 4 lines of 9 nodes, so every cache line the group touches is asked for; on
/// other groups, some of their lines. Hints only: nothing is read or written, every value keeps
/// its bits. Where the fields exceed the last-level cache the gather and the row adds wait on
/// memory (docs: performance log).
///
/// # Safety
/// `group` holds 8 elements, each in range.
#[inline(always)]
pub(super) unsafe fn prefetch_group(mesh: &Mesh, u: [&[f64]; 3], f: PlanesPtr, group: &[u32]) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_mm_prefetch, _MM_HINT_T0};
        let first = mesh
            .elements
            .get_unchecked(*group.get_unchecked(0) as usize);
        let last = mesh
            .elements
            .get_unchecked(*group.get_unchecked(7) as usize);
        for (a0, a1) in X_EDGES {
            for n in [first[a0] as usize, last[a1] as usize] {
                for j in 0..3 {
                    // Addresses in range (n is a node); `wrapping_add` all the same, a hint
                    // never faults.
                    _mm_prefetch::<_MM_HINT_T0>(u[j].as_ptr().wrapping_add(n) as *const i8);
                    _mm_prefetch::<_MM_HINT_T0>(f.0[j].wrapping_add(n) as *const i8);
                }
            }
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = (mesh, u, f, group);
}

/// Node i's vector from the planes `u`.
///
/// # Safety
/// i must be in range.
#[inline(always)]
pub(super) unsafe fn node_of(u: [&[f64]; 3], i: u32) -> [f64; 3] {
    let i = i as usize;
    [
        *u[0].get_unchecked(i),
        *u[1].get_unchecked(i),
        *u[2].get_unchecked(i),
    ]
}

/// [`is_row`] of the lane group `group` from the flags of [`row_starts`]: its elements are
/// numbered consecutively and the first one starts a row.
///
/// # Safety
/// `group` holds 8 elements, the first in range of `row_start`.
#[inline(always)]
pub(super) unsafe fn group_is_row(row_start: &[bool], group: &[u32]) -> bool {
    let first = *group.get_unchecked(0);
    let mut consecutive = true;
    for l in 1..8 {
        consecutive &= *group.get_unchecked(l) == first.wrapping_add(l as u32);
    }
    consecutive && *row_start.get_unchecked(first as usize)
}

/// Adds the lane forces `fl` of the 8 elements `group` into the global force planes, element
/// after element (lane 0 first), each element node after node: every node receives its
/// contributions in the order of [`scatter_lane`] called for l = 0, …, 7, so the same bits.
///
/// On a row along x (`row`, [`group_is_row`]) the two contributions to a shared node follow
/// each other directly (element m − 1's a₁, then element m's a₀) and no other element of the
/// group touches it; each of the 4 lines of 9 nodes is 9 consecutive numbers of each plane
/// ([`Planes`](super::Planes)), which [`add_line`] updates lane against lane: (F + f_{m−1}[a₁]) + f_m[a₀]
/// per component, as the element-by-element scatter does it.
///
/// # Safety
/// As [`scatter`], for every element of `group` (8 of them).
#[inline(always)]
pub(super) unsafe fn scatter_group<const ISA: u8>(
    f: PlanesPtr,
    elements: &[[u32; 8]],
    group: &[u32],
    row: bool,
    fl: &[[[f64; 8]; 3]; 8],
) {
    if !row {
        for (l, &e) in group.iter().enumerate() {
            scatter_lane(f, elements.get_unchecked(e as usize), fl, l);
        }
        return;
    }
    let c0 = elements.get_unchecked(*group.get_unchecked(0) as usize);
    for (a0, a1) in X_EDGES {
        let start = c0[a0] as usize;
        for j in 0..3 {
            add_line::<ISA>(f.0[j].add(start), &fl[a0][j], &fl[a1][j]);
        }
    }
}

/// One component of a line of 9 nodes of a row along x ([`scatter_group`]): node m receives
/// (F_m + f₁[m − 1]) + f₀[m], where f₁ (the elements' a₁ corner) misses at m = 0 and f₀ (a₀)
/// at m = 8. The AVX-512 and AVX2 builds add nodes 0–7 in vectors with f₁ moved up one lane
/// and a 0 in lane 0 ([`simd::add_line_avx512`]): F_m + 0 = F_m exactly, as F is never −0
/// (it starts at +0, and a sum is −0 only when both terms are), so the same bits.
///
/// # Safety
/// `line` points to 9 numbers no other thread touches meanwhile.
#[inline(always)]
pub(super) unsafe fn add_line<const ISA: u8>(line: *mut f64, f0: &[f64; 8], f1: &[f64; 8]) {
    #[cfg(target_arch = "x86_64")]
    if ISA == ISA_AVX512 {
        return simd::add_line_avx512(line, f0, f1);
    } else if ISA == ISA_AVX2 {
        return simd::add_line_avx2(line, f0, f1);
    }
    *line += f0[0];
    for m in 1..8 {
        *line.add(m) = (*line.add(m) + f1[m - 1]) + f0[m];
    }
    *line.add(8) += f1[7];
}

/// Adds lane `l` of the lane forces `fl` into the nodes `conn` of the global force planes.
///
/// # Safety
/// As [`scatter`].
#[inline(always)]
pub(super) unsafe fn scatter_lane(
    f: PlanesPtr,
    conn: &[u32; 8],
    fl: &[[[f64; 8]; 3]; 8],
    l: usize,
) {
    for a in 0..8 {
        let i = conn[a] as usize;
        for j in 0..3 {
            *f.0[j].add(i) += fl[a][j][l];
        }
    }
}

/// Keeps the smallest J seen and its element; `!(j >= min_j)` also keeps a NaN (non-finite
/// displacements).
#[inline(always)]
pub(super) fn keep_min_j(j: f64, e: u32, min_j: &mut f64, min_e: &mut usize) {
    if !(j >= *min_j) {
        *min_j = j;
        *min_e = e as usize;
    }
}

/// [`gather_group`] for a group of n ≤ 8 elements whose lane kernel runs all 8 lanes (F-bar,
/// the physical one point): lanes n to 7 repeat the group's last element, whose results the
/// caller drops. Returns whether the group is a row along x ([`group_is_row`], full groups
/// only).
///
/// # Safety
/// `group` holds 1 to 8 elements; every one and every node of theirs must be in range.
#[inline(always)]
pub(super) unsafe fn gather_padded(
    mesh: &Mesh,
    classes: &ElementClasses,
    u: [&[f64]; 3],
    group: &[u32],
    ul: &mut [[[f64; 8]; 3]; 8],
) -> bool {
    let n = group.len();
    let row = n == 8 && group_is_row(&classes.row_start, group);
    if n == 8 {
        gather_group(mesh, u, group, row, ul);
    } else {
        for l in 0..8 {
            let conn = mesh.elements.get_unchecked(group[l.min(n - 1)] as usize);
            for a in 0..8 {
                let x = node_of(u, conn[a]);
                for j in 0..3 {
                    ul[a][j][l] = x[j];
                }
            }
        }
    }
    row
}

/// Adds the lane forces `fl` of the group gathered by [`gather_padded`] (`row` its answer)
/// into the global force planes: a full group by [`scatter_group`], a shorter one element by
/// element (its spare lanes dropped).
///
/// # Safety
/// As [`scatter_group`]: no other thread may write these nodes meanwhile.
#[inline(always)]
pub(super) unsafe fn scatter_padded<const ISA: u8>(
    f: PlanesPtr,
    mesh: &Mesh,
    group: &[u32],
    row: bool,
    fl: &[[F64x8; 3]; 8],
) {
    if group.len() == 8 {
        // SAFETY: `[[F64x8; 3]; 8]` is `[[[f64; 8]; 3]; 8]` more aligned (F64x8 is `repr(C)`
        // over `[f64; 8]`).
        let fv = &*(fl as *const [[F64x8; 3]; 8] as *const [[[f64; 8]; 3]; 8]);
        scatter_group::<ISA>(f, &mesh.elements, group, row, fv);
    } else {
        for (l, &e) in group.iter().enumerate() {
            let fe: [[f64; 3]; 8] = std::array::from_fn(|a| std::array::from_fn(|j| fl[a][j].0[l]));
            scatter(f, mesh.elements.get_unchecked(e as usize), &fe);
        }
    }
}

/// Adds one element's nodal forces `fe` into the nodes `conn` of the global force planes.
///
/// # Safety
/// No other thread may write these nodes meanwhile (blocks of one colour share no node).
#[inline(always)]
pub(super) unsafe fn scatter(f: PlanesPtr, conn: &[u32; 8], fe: &[[f64; 3]; 8]) {
    for a in 0..8 {
        let i = conn[a] as usize;
        for j in 0..3 {
            *f.0[j].add(i) += fe[a][j];
        }
    }
}

/// A lane group's values at its 8 nodes, `[node][component][lane]` (the gathered U, the element
/// forces), aligned to a cache line: each `[f64; 8]` row is then one 64-byte line, so the
/// kernels' vector loads and stores of a row never straddle two lines. As a plain array its
/// alignment is 8 and its place in the stack frame is the compiler's, moved by unrelated
/// changes (docs: performance log, a one-point kernel 5 % slower for that alone).
#[repr(C, align(64))]
pub(crate) struct NodeLanes(pub [[[f64; 8]; 3]; 8]);

impl NodeLanes {
    #[inline(always)]
    pub(crate) fn zeros() -> NodeLanes {
        NodeLanes([[[0.0; 8]; 3]; 8])
    }
}
