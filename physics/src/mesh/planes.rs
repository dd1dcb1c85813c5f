//! A nodal vector field stored by component: the layout of the solver's displacements U,
//! velocities V and internal forces F_int (stages 1, 3 and 5: model §4.1, §4.3, §4.5).

/// A nodal vector field stored by component ("planes"): plane c holds component c of every
/// node, x₀ x₁ … x_{n−1} | y₀ … | z₀ …, in one allocation.
///
/// Why not rows of `[f64; 3]`: a row of 8 elements along x of a structured mesh shares 4 lines
/// of 9 consecutive nodes, and in a plane each line is 9 consecutive numbers, so the element
/// loop loads each lane vector of displacements with one 8-wide load
/// ([`crate::kernels::gather_group`]) and adds the forces of the 8 elements lane against lane, 8 nodes
/// per vector ([`crate::kernels::scatter_group`]); with rows both needed a transpose (docs:
/// performance log). The node loops run plane against plane.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Planes {
    data: Vec<f64>,
    n: usize,
}

impl Planes {
    /// n nodes, every component 0.
    pub fn zeros(n: usize) -> Planes {
        Planes {
            data: vec![0.0; 3 * n],
            n,
        }
    }

    /// The field of the rows `rows` (node i's components in `rows[i]`).
    pub fn from_rows(rows: &[[f64; 3]]) -> Planes {
        let n = rows.len();
        let mut p = Planes::zeros(n);
        for (i, r) in rows.iter().enumerate() {
            for (c, &x) in r.iter().enumerate() {
                p.data[c * n + i] = x;
            }
        }
        p
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.n
    }

    /// Whether there is no node.
    pub fn is_empty(&self) -> bool {
        self.n == 0
    }

    /// Node i's vector.
    #[inline(always)]
    pub fn get(&self, i: usize) -> [f64; 3] {
        [
            self.data[i],
            self.data[self.n + i],
            self.data[2 * self.n + i],
        ]
    }

    /// Sets node i's vector.
    #[inline(always)]
    pub fn set(&mut self, i: usize, x: [f64; 3]) {
        let n = self.n;
        (self.data[i], self.data[n + i], self.data[2 * n + i]) = (x[0], x[1], x[2]);
    }

    /// The nodes' vectors in order.
    pub fn rows(&self) -> impl ExactSizeIterator<Item = [f64; 3]> + '_ {
        (0..self.n).map(|i| self.get(i))
    }

    /// The three planes, x, y, z.
    pub fn planes(&self) -> [&[f64]; 3] {
        let (x, yz) = self.data.split_at(self.n);
        let (y, z) = yz.split_at(self.n);
        [x, y, z]
    }

    /// The three planes, mutable.
    pub fn planes_mut(&mut self) -> [&mut [f64]; 3] {
        let (x, yz) = self.data.split_at_mut(self.n);
        let (y, z) = yz.split_at_mut(self.n);
        [x, y, z]
    }

    /// Every component of every node, plane after plane.
    pub fn as_slice(&self) -> &[f64] {
        &self.data
    }

    /// Every component set to 0.
    pub fn fill_zero(&mut self) {
        self.data.fill(0.0);
    }

    /// The rows (node i's components in element i).
    pub fn to_rows(&self) -> Vec<[f64; 3]> {
        (0..self.n).map(|i| self.get(i)).collect()
    }

    /// Where each plane starts, for the element loop's blocks, which write disjoint nodes.
    pub(crate) fn ptr(&mut self) -> PlanesPtr {
        let n = self.n;
        let p = self.data.as_mut_ptr();
        // SAFETY: the planes start at 0, n and 2n of a 3n allocation.
        PlanesPtr(unsafe { [p, p.add(n), p.add(2 * n)] })
    }
}

/// A nodal vector field, whatever its layout: node i's vector by [`NodalField::at`]. Rows of
/// `[f64; 3]` (what a recording's frames keep) and [`Planes`] (the solver's) both are, so the
/// functions that read a few nodes of either (F at an element's centre, a surface's positions)
/// take it.
pub trait NodalField {
    /// Node i's vector.
    fn at(&self, i: usize) -> [f64; 3];
}

impl NodalField for [[f64; 3]] {
    #[inline(always)]
    fn at(&self, i: usize) -> [f64; 3] {
        self[i]
    }
}

impl NodalField for Planes {
    #[inline(always)]
    fn at(&self, i: usize) -> [f64; 3] {
        self.get(i)
    }
}

/// Raw pointers to the three planes of a [`Planes`], shared by the blocks of one colour (which
/// write disjoint nodes).
#[derive(Clone, Copy)]
pub(crate) struct PlanesPtr(pub(crate) [*mut f64; 3]);
unsafe impl Send for PlanesPtr {}
unsafe impl Sync for PlanesPtr {}

impl PlanesPtr {
    /// Node i's vector.
    ///
    /// # Safety
    /// i in range; no other thread writes node i meanwhile.
    #[inline(always)]
    pub(crate) unsafe fn get(&self, i: usize) -> [f64; 3] {
        [*self.0[0].add(i), *self.0[1].add(i), *self.0[2].add(i)]
    }

    /// Sets node i's vector.
    ///
    /// # Safety
    /// i in range; no other thread touches node i meanwhile.
    #[inline(always)]
    pub(crate) unsafe fn set(&self, i: usize, x: [f64; 3]) {
        for (c, p) in self.0.iter().enumerate() {
            *p.add(i) = x[c];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_round_trip_and_planes_hold_one_component_each() {
        let rows: Vec<[f64; 3]> = (0..5)
            .map(|i| [i as f64, 10.0 + i as f64, -(i as f64)])
            .collect();
        let p = Planes::from_rows(&rows);
        assert_eq!(p.len(), 5);
        assert_eq!(p.to_rows(), rows);
        assert_eq!(p.planes()[1], &[10.0, 11.0, 12.0, 13.0, 14.0]);
        assert_eq!(p.get(3), [3.0, 13.0, -3.0]);
        let [x, _, z] = p.planes();
        assert_eq!((x[4], z[4]), (4.0, -4.0));
    }
}
