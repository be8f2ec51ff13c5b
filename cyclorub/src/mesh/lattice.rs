//! A structured block of 20-node hexahedra: the quadratic lattice of
//! `(2a+1) × (2b+1) × (2c+1)` points for `a × b × c` elements, of which the
//! serendipity element uses those with at most one odd index (corners and
//! mid-edges; no face or body centres).

use super::hexahedron::{HEX20_NATURAL, HEX20_NODES};

/// Node numbers of a block's lattice points (`None` for face and body
/// centres, and before numbering).
pub(crate) struct Lattice {
    /// Elements per direction.
    pub elements: [usize; 3],
    ids: Vec<Option<usize>>,
}

impl Lattice {
    /// An unnumbered block of `elements[0] × elements[1] × elements[2]` elements.
    pub fn new(elements: [usize; 3]) -> Self {
        let points = (2 * elements[0] + 1) * (2 * elements[1] + 1) * (2 * elements[2] + 1);
        Self {
            elements,
            ids: vec![None; points],
        }
    }

    /// Lattice points per direction.
    pub fn points(&self) -> [usize; 3] {
        self.elements.map(|e| 2 * e + 1)
    }

    /// Whether lattice point `(i, j, k)` is a node of the serendipity element.
    pub fn is_node(i: usize, j: usize, k: usize) -> bool {
        i % 2 + j % 2 + k % 2 <= 1
    }

    fn index(&self, [i, j, k]: [usize; 3]) -> usize {
        let [_, pj, pk] = self.points();
        (i * pj + j) * pk + k
    }

    /// The node number at lattice point `p`.
    pub fn get(&self, p: [usize; 3]) -> Option<usize> {
        self.ids[self.index(p)]
    }

    /// Sets the node number at lattice point `p`.
    pub fn set(&mut self, p: [usize; 3], id: usize) {
        let at = self.index(p);
        self.ids[at] = Some(id);
    }

    /// Node lattice points in numbering order (i slowest, k fastest).
    pub fn node_points(&self) -> Vec<[usize; 3]> {
        let [pi, pj, pk] = self.points();
        let mut out = Vec::new();
        for i in 0..pi {
            for j in 0..pj {
                for k in 0..pk {
                    if Self::is_node(i, j, k) {
                        out.push([i, j, k]);
                    }
                }
            }
        }
        out
    }

    /// The 20 lattice points of element `e`, in [`HEX20_NATURAL`] order.
    pub fn element_points(e: [usize; 3]) -> [[usize; 3]; HEX20_NODES] {
        let mut out = [[0; 3]; HEX20_NODES];
        for (p, nat) in out.iter_mut().zip(HEX20_NATURAL.iter()) {
            for d in 0..3 {
                // Natural −1, 0, 1 → lattice 2e, 2e + 1, 2e + 2.
                p[d] = (2 * e[d] as i64 + 1 + nat[d] as i64) as usize;
            }
        }
        out
    }

    /// Every element index, i slowest.
    pub fn element_indices(&self) -> Vec<[usize; 3]> {
        let [a, b, c] = self.elements;
        let mut out = Vec::with_capacity(a * b * c);
        for i in 0..a {
            for j in 0..b {
                for k in 0..c {
                    out.push([i, j, k]);
                }
            }
        }
        out
    }
}
