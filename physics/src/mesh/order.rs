//! The order of the element loop (model §4.3 on the thread team): slabs across the
//! longest axis, node-disjoint element blocks in two colours, and nodes renumbered slab by slab
//! so that each thread's share of the nodal arrays stays contiguous.

use super::Mesh;

/// Slabs across the longest axis of a mesh ([`Mesh::slabs`]).
#[derive(Debug, Clone, Copy)]
pub struct Slabs {
    /// The axis (0 = x, 1 = y, 2 = z).
    pub axis: usize,
    /// Lowest coordinate along it [m].
    pub lo: f64,
    /// Slab thickness [m], at least the largest element extent along the axis.
    pub width: f64,
    pub count: usize,
}

impl Slabs {
    /// Slab of a coordinate along the axis (clamped to the slabs).
    pub fn of(&self, z: f64) -> usize {
        (((z - self.lo) / self.width).floor().max(0.0) as usize).min(self.count - 1)
    }
}
impl Mesh {
    /// The slabs of [`Mesh::element_blocks`]: across the longest axis, each as thick as the
    /// largest element extent along it (None for a mesh without elements).
    pub fn slabs(&self) -> Option<Slabs> {
        if self.elements.is_empty() {
            return None;
        }
        let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
        for x in &self.nodes {
            for c in 0..3 {
                lo[c] = lo[c].min(x[c]);
                hi[c] = hi[c].max(x[c]);
            }
        }
        // Equal sides: the last (z) wins, the slowest index of a box.
        let axis = (0..3)
            .max_by(|&a, &b| (hi[a] - lo[a]).total_cmp(&(hi[b] - lo[b])))
            .unwrap_or(2);
        let mut thickness = 0.0f64;
        for conn in &self.elements {
            let (mut a, mut b) = (f64::INFINITY, f64::NEG_INFINITY);
            for &n in conn {
                let z = self.nodes[n as usize][axis];
                a = a.min(z);
                b = b.max(z);
            }
            thickness = thickness.max(b - a);
        }
        let span = hi[axis] - lo[axis];
        let count = if thickness > 0.0 && span.is_finite() {
            // The tolerance keeps a layer of a structured mesh whole when the node
            // coordinates make its extent an ulp larger than span/layers.
            ((span / thickness + 1e-9).floor() as usize).clamp(1, self.elements.len())
        } else {
            1
        };
        Some(Slabs {
            axis,
            lo: lo[axis],
            width: span / count as f64,
            count,
        })
    }

    /// The same mesh with node i renamed `new_index[i]` (a permutation of 0..nodes): positions,
    /// connectivity and face sets follow.
    pub fn renumbered(&self, new_index: &[u32]) -> Mesh {
        assert_eq!(new_index.len(), self.nodes.len());
        let mut nodes = vec![[0.0; 3]; self.nodes.len()];
        for (i, x) in self.nodes.iter().enumerate() {
            nodes[new_index[i] as usize] = *x;
        }
        let map = |n: &u32| new_index[*n as usize];
        Mesh {
            nodes,
            elements: self
                .elements
                .iter()
                .map(|e| e.each_ref().map(map))
                .collect(),
            tets: self.tets.iter().map(|e| e.each_ref().map(map)).collect(),
            face_sets: self
                .face_sets
                .iter()
                .map(|(k, q)| (k.clone(), q.iter().map(|f| f.each_ref().map(map)).collect()))
                .collect(),
        }
    }

    /// The same mesh with its nodes renumbered slab by slab across the longest axis ([`Slabs`]),
    /// keeping their order inside a slab. The nodes of an element then sit close together in
    /// memory, and each thread's share of the node loops matches its element blocks. A mesh
    /// already numbered along that axis (a box whose longest side is z, or a cube) keeps its
    /// numbering: the sort is stable and the slab index never decreases along it.
    pub fn with_nodes_in_slabs(self) -> Mesh {
        let Some(slabs) = self.slabs() else {
            return self;
        };
        let mut order: Vec<u32> = (0..self.nodes.len() as u32).collect();
        order.sort_by_key(|&i| slabs.of(self.nodes[i as usize][slabs.axis]));
        let mut new_index = vec![0u32; self.nodes.len()];
        for (new, &old) in order.iter().enumerate() {
            new_index[old as usize] = new as u32;
        }
        self.renumbered(&new_index)
    }

    /// Slab blocks for the parallel element loop: colours → blocks → elements.
    ///
    /// The elements are cut into slabs across the longest axis of the mesh, each slab at least
    /// one element thick (T ≥ the largest element extent along that axis) and holding at least
    /// `min_block` elements (thin slabs are merged with the next). Two elements that share a
    /// node have centroids at most T apart, so slabs k and k + 2 never share a node: the even
    /// slabs form one colour and the odd slabs the other. The colouring is nonetheless done
    /// greedily on the slabs' node sets, so a mesh for which the argument fails (round-off at a
    /// slab boundary) still gets node-disjoint blocks, only with more colours.
    ///
    /// Inside a block the elements run in increasing index, one after another (they share
    /// nodes); blocks of one colour run in parallel. Everything here depends on the mesh alone,
    /// never on the thread count, so every node receives its element forces in the same order
    /// whatever the number of threads. Compared with a colouring of single elements (8 colours
    /// on a box, each touching every node), a colour sweeps half of the nodes once and a step
    /// needs 2 parallel sections instead of 8; the elements of a block also share most of their
    /// nodes with the previous ones, still in cache.
    pub fn element_blocks(&self, min_block: usize) -> Vec<Vec<Vec<u32>>> {
        let Some(slabs) = self.slabs() else {
            return Vec::new();
        };
        let mut layers: Vec<Vec<u32>> = vec![Vec::new(); slabs.count];
        for (e, conn) in self.elements.iter().enumerate() {
            let c = conn
                .iter()
                .fold(0.0, |s, &n| s + self.nodes[n as usize][slabs.axis])
                / 8.0;
            layers[slabs.of(c)].push(e as u32);
        }
        // Merge thin slabs forward until each block holds at least `min_block` elements.
        let mut blocks: Vec<Vec<u32>> = Vec::new();
        let mut open: Vec<u32> = Vec::new();
        for layer in layers {
            open.extend(layer);
            if open.len() >= min_block.max(1) {
                blocks.push(std::mem::take(&mut open));
            }
        }
        if !open.is_empty() {
            match blocks.last_mut() {
                Some(last) => last.extend(open),
                None => blocks.push(open),
            }
        }
        // Greedy colouring of the blocks on their node sets.
        let mut node_colours: Vec<u64> = vec![0; self.nodes.len()];
        let mut colours: Vec<Vec<Vec<u32>>> = Vec::new();
        for block in blocks {
            let used = block
                .iter()
                .flat_map(|&e| self.elements[e as usize])
                .fold(0u64, |m, n| m | node_colours[n as usize]);
            let c = ((!used).trailing_zeros() as usize).min(64);
            if c == 64 {
                // Cannot happen for slabs; keep the invariant by running such a block alone.
                colours.push(vec![block]);
                continue;
            }
            while colours.len() <= c {
                colours.push(Vec::new());
            }
            for &e in &block {
                for &n in &self.elements[e as usize] {
                    node_colours[n as usize] |= 1 << c;
                }
            }
            colours[c].push(block);
        }
        colours
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Renumbering in slabs: the identity on a box numbered along its longest side (z); on a
    /// randomly numbered box, every element and face keeps its coordinates and the slab index
    /// of the nodes never decreases with their number.
    #[test]
    fn nodes_in_slabs_keep_the_geometry_and_sort_the_numbering() {
        let m = Mesh::boxed([0.0; 3], [1.0, 2.0, 3.0], [3, 4, 5]);
        let same = m.clone().with_nodes_in_slabs();
        assert_eq!(same.nodes, m.nodes);
        assert_eq!(same.elements, m.elements);
        let n = m.nodes.len();
        let mut p: Vec<u32> = (0..n as u32).collect();
        let mut state = 12345u64;
        for i in (1..n).rev() {
            state = state.wrapping_mul(6364136223846793005).wrapping_add(1);
            p.swap(i, (state >> 33) as usize % (i + 1));
        }
        let shuffled = m.renumbered(&p);
        let sorted = shuffled.clone().with_nodes_in_slabs();
        let xyz = |mesh: &Mesh, conn: &[u32]| -> Vec<[f64; 3]> {
            conn.iter().map(|&k| mesh.nodes[k as usize]).collect()
        };
        for (a, b) in m.elements.iter().zip(&sorted.elements) {
            assert_eq!(xyz(&m, a), xyz(&sorted, b));
        }
        for (name, quads) in &m.face_sets {
            for (a, b) in quads.iter().zip(&sorted.face_sets[name]) {
                assert_eq!(xyz(&m, a), xyz(&sorted, b));
            }
        }
        let slabs = sorted.slabs().unwrap();
        assert_eq!((slabs.axis, slabs.count), (2, 5));
        let k: Vec<usize> = sorted.nodes.iter().map(|x| slabs.of(x[2])).collect();
        assert!(k.windows(2).all(|w| w[0] <= w[1]));
        assert!(
            shuffled
                .nodes
                .iter()
                .map(|x| slabs.of(x[2]))
                .collect::<Vec<_>>()
                != k
        );
    }
    #[test]
    fn box_counts_classes_and_blocks() {
        let m = Mesh::boxed([0.0; 3], [1.0, 2.0, 3.0], [3, 4, 5]);
        assert_eq!(m.nodes.len(), 4 * 5 * 6);
        assert_eq!(m.elements.len(), 60);
        let cls = m.element_classes().unwrap();
        assert_eq!(cls.data.len(), 1);
        let vol: f64 = cls
            .class_of
            .iter()
            .map(|&c| cls.data[c as usize].volume())
            .sum();
        assert!((vol - 6.0).abs() < 1e-12);
        // Slabs of one layer (z is the longest side): even layers, then odd layers.
        let colours = m.element_blocks(1);
        assert_eq!(colours.len(), 2);
        assert_eq!(colours[0].len() + colours[1].len(), 5);
        let mut count = vec![0; m.elements.len()];
        for colour in &colours {
            let mut owner = std::collections::HashMap::new();
            for (b, block) in colour.iter().enumerate() {
                for &e in block {
                    count[e as usize] += 1;
                    for &n in &m.elements[e as usize] {
                        let first = *owner.entry(n).or_insert(b);
                        assert_eq!(first, b, "two blocks of one colour share node {n}");
                    }
                }
            }
        }
        assert!(
            count.iter().all(|&c| c == 1),
            "every element in exactly one block"
        );
        // Blocks hold at least the minimum (merging layers): 12 elements per layer.
        let merged = m.element_blocks(20);
        assert!(merged.iter().flatten().all(|b| b.len() >= 20));
        assert_eq!(merged.iter().flatten().map(Vec::len).sum::<usize>(), 60);
    }
}
