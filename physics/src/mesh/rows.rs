//! Rows along x of a structured mesh's numbering: which lane groups of 8 consecutive elements
//! share 4 lines of 9 consecutive nodes, so that the element loops ([`crate::kernels`]) gather
//! and scatter them with one vector load and store per line.

/// The hex8 corners in pairs along ξ (a₀, a₁): a₁ is a₀'s neighbour in +x on the element's
/// x-edge (the node order of `Mesh::boxed`).
pub(crate) const X_EDGES: [(usize, usize); 4] = [(0, 1), (3, 2), (4, 5), (7, 6)];

/// Whether the 8 elements `group` are a row along x of a structured mesh numbered x first:
/// element l's node a is node a of the first element plus l, on each x-edge the node a₁ is
/// a₀ + 1, and the 4 lines [a₀, a₀ + 8] of the first element are disjoint. Then the group's
/// nodes are 4 lines of 9 consecutive nodes, node m of a line being a₀ of element m (m < 8)
/// and a₁ of element m − 1 (m > 0), and no other. Only the numbering is read: any mesh whose
/// numbering has this pattern qualifies, whatever its geometry.
///
/// # Safety
/// Every element of `group` must be in range.
#[inline(always)]
pub(crate) unsafe fn is_row(elements: &[[u32; 8]], group: &[u32]) -> bool {
    let c0 = elements.get_unchecked(*group.get_unchecked(0) as usize);
    let mut row = true;
    for (a0, a1) in X_EDGES {
        row &= c0[a1] == c0[a0].wrapping_add(1);
    }
    for (i, &(p, _)) in X_EDGES.iter().enumerate() {
        for &(q, _) in &X_EDGES[i + 1..] {
            row &= c0[p].abs_diff(c0[q]) > 8;
        }
    }
    for l in 1..8 {
        let c = elements.get_unchecked(*group.get_unchecked(l) as usize);
        for a in 0..8 {
            row &= c[a] == c0[a].wrapping_add(l as u32);
        }
    }
    row
}

/// Per element e: whether the elements numbered e, …, e + 7 are a row along x ([`is_row`]);
/// false for the last 7. Computed once per mesh ([`super::ElementClasses::row_start`]),
/// so that the element loops read one flag per lane group (`group_is_row` in [`crate::kernels`]) instead of the 8
/// connectivity rows that [`is_row`] compares, a visible share of a one-point kernel's time
/// (docs: performance log).
pub fn row_starts(elements: &[[u32; 8]]) -> Vec<bool> {
    let n = elements.len();
    (0..n)
        .map(|e| {
            e + 8 <= n && {
                let group: [u32; 8] = std::array::from_fn(|l| (e + l) as u32);
                // SAFETY: e + 7 < n.
                unsafe { is_row(elements, &group) }
            }
        })
        .collect()
}
