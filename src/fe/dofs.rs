//! Vertices of the active mesh, hanging vertices, and the numbering of Q₁ degrees of freedom.
//!
//! Vertices are numbered by their integer position (x first, then y), which is deterministic
//! and independent of the thread count. Every vertex carries `n_components` dofs numbered
//! `vertex · n_components + component`. Hanging vertices keep their dofs (the thesis counts them,
//! as deal.II's `n_dofs()` does); their values follow from the two end points of the coarse edge.

use rayon::prelude::*;

use crate::linalg::joined;
use crate::mesh::{CellId, Face, Mesh, Neighbor, Side, VertexKey, FACES};

/// A vertex in the middle of a coarse cell's edge: value = ½(parent₀ + parent₁).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Hanging {
    pub vertex: u32,
    pub parents: [u32; 2],
}

/// Vertices of the active cells of a mesh.
#[derive(Clone, Debug)]
pub struct Vertices {
    /// Integer positions, sorted (x first, then y).
    pub keys: Vec<VertexKey>,
    /// Physical positions.
    pub coords: Vec<[f64; 2]>,
    /// Four vertex numbers per active cell (lexicographic corners), indexed like `mesh.active()`.
    pub cell_vertices: Vec<[u32; 4]>,
    /// Hanging vertices, sorted by vertex number.
    pub hanging: Vec<Hanging>,
    /// `true` for hanging vertices.
    pub is_hanging: Vec<bool>,
    /// The active cell that holds each vertex where [`Mesh::cell_at_vertex`] finds it (the cell
    /// to its upper right, or below or left of it on the right and top sides of the domain):
    /// the cell that listed the vertex (`vertex_keys`).
    pub owner: Vec<CellId>,
    extent: (u64, u64),
    /// Vertex number by integer position ([`Vertices::find`]).
    index: KeyIndex,
}

impl Vertices {
    pub fn new(mesh: &Mesh) -> Vertices {
        let mut v = Vertices::numbering_only(mesh);
        v.cell_vertices = mesh
            .active()
            .par_iter()
            .map(|&c| {
                mesh.corner_keys(c)
                    .map(|k| v.find(k).expect("corner is a vertex"))
            })
            .collect();
        v.coords = v.keys.par_iter().map(|&k| mesh.point(k)).collect();
        v
    }

    /// The numbering, the hanging vertices and their parents only: no physical positions and
    /// no cell vertices (`coords` and `cell_vertices` are empty). The level meshes of
    /// multigrid need no more ([`super::hierarchy`]).
    pub fn numbering_only(mesh: &Mesh) -> Vertices {
        let (listed, hanging_keys) = vertex_keys(mesh);
        let (keys, owner): (Vec<VertexKey>, Vec<CellId>) = sorted(listed).into_par_iter().unzip();
        assert!(
            keys.windows(2).all(|w| w[0] < w[1]),
            "a vertex listed twice"
        );
        let index = KeyIndex::new(&keys);
        let lookup = |k: VertexKey| index.find(&keys, k).expect("vertex exists");
        let mut hanging: Vec<Hanging> = hanging_keys
            .par_iter()
            .map(|&[v, a, b]| Hanging {
                vertex: lookup(v),
                parents: [lookup(a), lookup(b)],
            })
            .collect();
        hanging.par_sort_unstable_by_key(|h| h.vertex);
        let mut is_hanging = vec![false; keys.len()];
        for h in &hanging {
            is_hanging[h.vertex as usize] = true;
        }
        Vertices {
            keys,
            coords: Vec::new(),
            cell_vertices: Vec::new(),
            hanging,
            is_hanging,
            owner,
            extent: mesh.extent(),
            index,
        }
    }

    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// The vertex at the integer position `key`, if the mesh has one there.
    pub fn find(&self, key: VertexKey) -> Option<u32> {
        self.index.find(&self.keys, key)
    }

    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Whether vertex `v` lies on a side of the domain.
    pub fn on_side(&self, v: u32, side: Side) -> bool {
        let (x, y) = self.keys[v as usize];
        match side {
            Side::Left => x == 0,
            Side::Right => x == self.extent.0,
            Side::Bottom => y == 0,
            Side::Top => y == self.extent.1,
        }
    }

    /// Whether vertex `v` lies on the boundary of the domain.
    pub fn on_boundary(&self, v: u32) -> bool {
        [Side::Left, Side::Right, Side::Bottom, Side::Top]
            .into_iter()
            .any(|side| self.on_side(v, side))
    }

    /// Vertices on a side, sorted along it.
    pub fn side_vertices(&self, side: Side) -> Vec<u32> {
        let mut v: Vec<u32> = (0..self.len() as u32)
            .filter(|&v| self.on_side(v, side))
            .collect();
        match side {
            Side::Left | Side::Right => v.sort_by_key(|&v| self.keys[v as usize].1),
            Side::Bottom | Side::Top => v.sort_by_key(|&v| self.keys[v as usize].0),
        }
        v
    }
}

/// The vertices of the active cells, each once, unsorted, and the hanging vertices with the
/// end points of their coarse edges ([position, end, end]), from one pass over the cells that
/// asks for each face's neighbour once.
///
/// Listing the four corners of every cell and removing the duplicates would sort four entries
/// per vertex; instead each cell lists
/// - its lower-left corner;
/// - the midpoints of its left and bottom faces where the neighbour is finer (hanging vertices:
///   the finer cells there have other lower-left corners);
/// - its corners on the right and top sides of the domain (no cell lies beyond them).
///
/// Every other corner is the lower-left corner of the active cell that holds it (cells are
/// half-open, `[x, x + w) × [y, y + w)`, and tile the domain): a corner on the interior of that
/// cell's bottom or left edge would make that face's neighbour finer, and is then its midpoint
/// (2:1 rule). Each vertex therefore appears exactly once. The hanging vertices are the
/// midpoints of every face, of the four, whose neighbour is finer.
fn vertex_keys(mesh: &Mesh) -> VertexLists {
    let (right, top) = mesh.extent();
    let midpoint = |a: VertexKey, b: VertexKey| ((a.0 + b.0) / 2, (a.1 + b.1) / 2);
    let neighbors = mesh.face_neighbors();
    // Listed by blocks of cells in parallel, then joined: the order of the lists does not
    // matter, the vertices are sorted and the hanging ones too.
    let blocks: Vec<VertexLists> = mesh
        .active()
        .par_chunks(CELLS_PER_TASK)
        .map(|cells| {
            let mut listed = Vec::with_capacity(cells.len() + cells.len() / 2);
            let mut hanging = Vec::new();
            for &c in cells {
                let corners = mesh.corner_keys(c);
                let [ll, lr, ul, ur] = corners;
                let finer =
                    FACES.map(|f| matches!(mesh.neighbor_in(&neighbors, c, f), Neighbor::Finer(_)));
                let (at_right, at_top) = (lr.0 == right, ul.1 == top);
                let keys = [
                    Some(ll),
                    finer[Face::Left as usize].then(|| midpoint(ll, ul)),
                    finer[Face::Bottom as usize].then(|| midpoint(ll, lr)),
                    at_right.then_some(lr),
                    at_top.then_some(ul),
                    (at_right && at_top).then_some(ur),
                ];
                listed.extend(keys.into_iter().flatten().map(|k| (k, c)));
                for (f, _) in FACES.into_iter().zip(finer).filter(|&(_, finer)| finer) {
                    let [a, b] = f.vertices().map(|i| corners[i]);
                    hanging.push([midpoint(a, b), a, b]);
                }
            }
            (listed, hanging)
        })
        .collect();
    let listed = joined(blocks.iter().map(|b| &b.0[..]).collect());
    let hanging = joined(blocks.iter().map(|b| &b.1[..]).collect());
    (listed, hanging)
}

/// The vertices with the cells that list them, and the hanging vertices with the end points of
/// their coarse edges ([`vertex_keys`]).
type VertexLists = (Vec<(VertexKey, CellId)>, Vec<[VertexKey; 3]>);

/// Active cells per parallel task of [`vertex_keys`].
const CELLS_PER_TASK: usize = 4096;

/// Vertices (with their cells) sorted by their distinct keys (x first, then y): a
/// least-significant-digit radix sort, by y and then, stably, by x, over the bits in which the
/// keys differ (on a quadtree their low bits are zero below the finest level: one or two passes
/// of [`RADIX_BITS`] per coordinate). The order is the one of any sort, the keys being
/// distinct; a comparison sort took most of the numbering of a mesh.
fn sorted(mut keys: Vec<(VertexKey, CellId)>) -> Vec<(VertexKey, CellId)> {
    let mut spare = vec![((0, 0), 0); keys.len()];
    type Item = (VertexKey, CellId);
    for coordinate in [|k: &Item| k.0 .1, |k: &Item| k.0 .0] {
        let (any, all) = keys.iter().fold((0u64, u64::MAX), |(any, all), k| {
            (any | coordinate(k), all & coordinate(k))
        });
        // The bits that differ between keys.
        let differ = any & !all;
        if differ == 0 {
            continue;
        }
        let (low, high) = (differ.trailing_zeros(), 64 - differ.leading_zeros());
        let mut shift = low;
        while shift < high {
            let digit = |k: &Item| ((coordinate(k) >> shift) & RADIX_MASK) as usize;
            let mut start = vec![0usize; RADIX_MASK as usize + 2];
            for k in &keys {
                start[digit(k) + 1] += 1;
            }
            for d in 0..=RADIX_MASK as usize {
                start[d + 1] += start[d];
            }
            for k in &keys {
                let d = digit(k);
                spare[start[d]] = *k;
                start[d] += 1;
            }
            std::mem::swap(&mut keys, &mut spare);
            shift += RADIX_BITS;
        }
    }
    keys
}

/// Bits per pass of [`sorted`].
const RADIX_BITS: u32 = 11;
const RADIX_MASK: u64 = (1 << RADIX_BITS) - 1;

/// Vertex numbers by integer position: the lookups of every corner of every cell, of the
/// multigrid prolongations and of the warm start dominated the setup of a mesh.
///
/// * **Grid** — a table over the lattice of the finest vertex spacing of the keys, column by
///   column like the numbering, wherever that lattice has at most [`GRID_FILL`] times as many
///   points as there are vertices (uniform and gently graded meshes, the level meshes of
///   multigrid): one load per lookup, and keys that lie close together, as the corners of
///   neighbouring cells do, are close together in the table, so most lookups hit the cache.
/// * **Hashed** — otherwise (deep local refinement): open addressing with linear probing, at
///   most half full, one or two cache lines per lookup where a binary search of the sorted keys
///   touches about log₂ n.
#[derive(Clone, Debug)]
enum KeyIndex {
    Grid {
        /// Vertex number per lattice point ([`KeyIndex::EMPTY`] where none), column-major.
        slots: Vec<u32>,
        /// log₂ of the lattice spacing in integer units.
        shift: u32,
        /// Lattice points per column.
        height: u64,
        /// Columns.
        width: u64,
    },
    Hashed {
        /// Vertex number per slot, [`KeyIndex::EMPTY`] where none; the length is a power of
        /// two.
        slots: Vec<u32>,
        /// 64 − log₂(slots.len()): the hash keeps the top bits of the product.
        shift: u32,
    },
}

/// The most lattice points per vertex for which [`KeyIndex`] keeps a grid (4 bytes each).
const GRID_FILL: u64 = 4;

impl KeyIndex {
    const EMPTY: u32 = u32::MAX;

    /// The index of `keys` (sorted by column, then row).
    fn new(keys: &[VertexKey]) -> KeyIndex {
        let bits = keys.iter().fold(0, |b, &(x, y)| b | x | y);
        let shift = bits.trailing_zeros().min(63);
        let (width, height) = keys.iter().fold((0, 0), |(w, h), &(x, y)| {
            (w.max((x >> shift) + 1), h.max((y >> shift) + 1))
        });
        let points = width.checked_mul(height);
        if points.is_some_and(|p| p <= GRID_FILL * keys.len().max(1) as u64) {
            let mut slots = vec![KeyIndex::EMPTY; (width * height) as usize];
            for (v, &(x, y)) in keys.iter().enumerate() {
                slots[((x >> shift) * height + (y >> shift)) as usize] = v as u32;
            }
            return KeyIndex::Grid {
                slots,
                shift,
                height,
                width,
            };
        }
        let len = (2 * keys.len()).max(2).next_power_of_two();
        let mut slots = vec![KeyIndex::EMPTY; len];
        let shift = 64 - len.trailing_zeros();
        let mask = len - 1;
        for (v, &key) in keys.iter().enumerate() {
            let mut slot = KeyIndex::home(shift, key);
            while slots[slot] != KeyIndex::EMPTY {
                slot = (slot + 1) & mask;
            }
            slots[slot] = v as u32;
        }
        KeyIndex::Hashed { slots, shift }
    }

    /// The home slot of `key` in a hashed index (multiplicative hashing of both coordinates).
    #[inline]
    fn home(shift: u32, key: VertexKey) -> usize {
        let h = key
            .0
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(key.1.wrapping_mul(0xC2B2_AE3D_27D4_EB4F));
        (h >> shift) as usize
    }

    /// The number of the vertex at `key` among `keys` (those the index was built from).
    #[inline]
    fn find(&self, keys: &[VertexKey], key: VertexKey) -> Option<u32> {
        match self {
            KeyIndex::Grid {
                slots,
                shift,
                height,
                width,
            } => {
                let (x, y) = (key.0 >> shift, key.1 >> shift);
                let on_lattice = (x << shift, y << shift) == key;
                if !on_lattice || x >= *width || y >= *height {
                    return None;
                }
                let v = slots[(x * height + y) as usize];
                (v != KeyIndex::EMPTY).then_some(v)
            }
            KeyIndex::Hashed { slots, shift } => {
                let mask = slots.len() - 1;
                let mut slot = KeyIndex::home(*shift, key);
                loop {
                    let v = slots[slot];
                    if v == KeyIndex::EMPTY {
                        return None;
                    }
                    if keys[v as usize] == key {
                        return Some(v);
                    }
                    slot = (slot + 1) & mask;
                }
            }
        }
    }
}

/// Degrees of freedom: `n_components` per vertex.
#[derive(Clone, Debug)]
pub struct DofMap {
    pub vertices: Vertices,
    pub n_components: usize,
}

impl DofMap {
    pub fn new(mesh: &Mesh, n_components: usize) -> DofMap {
        DofMap {
            vertices: Vertices::new(mesh),
            n_components,
        }
    }

    /// Number of dofs, hanging and Dirichlet dofs included.
    pub fn n_dofs(&self) -> usize {
        self.vertices.len() * self.n_components
    }

    #[inline]
    pub fn dof(&self, vertex: u32, component: usize) -> usize {
        vertex as usize * self.n_components + component
    }

    /// Local dofs of an active cell (index into `mesh.active()`), vertex-major:
    /// local `vertex · n_components + component`.
    pub fn cell_dofs(&self, k: usize) -> impl Iterator<Item = usize> + '_ {
        let nc = self.n_components;
        self.vertices.cell_vertices[k]
            .into_iter()
            .flat_map(move |v| (0..nc).map(move |c| v as usize * nc + c))
    }

    /// Components 0 and 1 of the field `u` at `vertex` (the displacement of an elasticity field).
    #[inline]
    pub fn vector(&self, u: &[f64], vertex: u32) -> [f64; 2] {
        [u[self.dof(vertex, 0)], u[self.dof(vertex, 1)]]
    }

    /// The position of `vertex` moved by `scale` times the displacement `u` there, x + scale·u
    /// (scale 1: the deformed position).
    #[inline]
    pub fn displaced(&self, u: &[f64], vertex: u32, scale: f64) -> [f64; 2] {
        let x = self.vertices.coords[vertex as usize];
        let d = self.vector(u, vertex);
        [x[0] + scale * d[0], x[1] + scale * d[1]]
    }

    /// Corner values of component `c` of the field `u` on active cell `k`.
    #[inline]
    pub fn corner_values(&self, u: &[f64], k: usize, c: usize) -> [f64; 4] {
        self.vertices.cell_vertices[k].map(|v| u[v as usize * self.n_components + c])
    }
}

/// The local dofs of a cell, vertex-major: local index `vertex · n_components + component` for
/// the cell's four vertices in lexicographic order (the layout of the cell matrices and vectors
/// of every assembler and of [`DofMap::cell_dofs`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LocalDofs {
    pub n_components: usize,
}

impl LocalDofs {
    pub fn new(n_components: usize) -> LocalDofs {
        LocalDofs { n_components }
    }

    /// Number of local dofs (4 vertices × components).
    pub fn len(&self) -> usize {
        4 * self.n_components
    }

    pub fn is_empty(&self) -> bool {
        self.n_components == 0
    }

    /// Local index of component `component` at local vertex `vertex`.
    #[inline]
    pub fn index(&self, vertex: usize, component: usize) -> usize {
        vertex * self.n_components + component
    }

    /// Position of entry (local `i`, local `j`) in a row-major cell matrix.
    #[inline]
    pub fn entry(&self, i: usize, j: usize) -> usize {
        i * self.len() + j
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The radix sort gives the order of a comparison sort: keys spread over many digits, keys
    /// that differ only in high or only in low bits, a coordinate that is the same for all.
    #[test]
    fn radix_sort_of_vertex_keys_is_the_sorted_order() {
        let mut state = 0x2545_F491_4F6C_DD1Du64;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let cases: Vec<Vec<VertexKey>> = vec![
            (0..5000).map(|_| (next() >> 20, next() >> 30)).collect(),
            (0..5000)
                .map(|_| ((next() % 64) << 40, (next() % 4096) << 13))
                .collect(),
            (0..3000).map(|_| (7, next())).collect(),
            (0..3000).map(|_| (next() % 1000, 12)).collect(),
            vec![(3, 4)],
            Vec::new(),
        ];
        for mut keys in cases {
            keys.sort_unstable();
            keys.dedup();
            // The cell of each key goes with it.
            let items: Vec<(VertexKey, CellId)> = keys
                .iter()
                .map(|&k| (k, (k.0 ^ k.1.rotate_left(7)) as CellId))
                .collect();
            let mut shuffled = items.clone();
            shuffled.reverse();
            let third = shuffled.len() / 3;
            shuffled.rotate_left(third);
            assert_eq!(sorted(shuffled), items);
        }
    }

    /// Both kinds of [`KeyIndex`] find every key at its number, and nothing at a position that
    /// is not a key: off the lattice of the keys, past its extent, or a lattice point without a
    /// vertex.
    #[test]
    fn key_index_finds_the_keys_and_only_them() {
        // A uniform lattice of spacing 4 (a grid), the same with one far-away key (hashed), and
        // a lattice with every other point missing (a grid with holes).
        let uniform: Vec<VertexKey> = (0..9u64)
            .flat_map(|x| (0..5u64).map(move |y| (4 * x, 4 * y)))
            .collect();
        let mut sparse = uniform.clone();
        sparse.push((1 << 40, 0));
        let holes: Vec<VertexKey> = uniform
            .iter()
            .copied()
            .filter(|&(x, y)| (x + y) % 8 == 0)
            .collect();
        for (keys, grid) in [(&uniform, true), (&sparse, false), (&holes, true)] {
            let index = KeyIndex::new(keys);
            assert_eq!(matches!(index, KeyIndex::Grid { .. }), grid, "{keys:?}");
            for (v, &k) in keys.iter().enumerate() {
                assert_eq!(index.find(keys, k), Some(v as u32), "{k:?}");
            }
            for k in [(2, 0), (0, 2), (36, 0), (0, 20), (4, 4 << 20), (1 << 41, 0)] {
                assert_eq!(index.find(keys, k), None, "{k:?}");
            }
        }
        let index = KeyIndex::new(&holes);
        assert_eq!(index.find(&holes, (4, 0)), None);
        assert_eq!(KeyIndex::new(&[]).find(&[], (0, 0)), None);
    }
}
