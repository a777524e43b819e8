//! Fill-reducing ordering for the sparse factorisations: geometric nested dissection on the
//! integer vertex positions of the quadtree mesh.

use crate::mesh::VertexKey;

/// A symmetric permutation of the dofs: `fwd[new] = old`, `inv[old] = new`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Ordering {
    pub fwd: Vec<usize>,
    pub inv: Vec<usize>,
}

impl Ordering {
    /// The identity (no reordering).
    pub fn identity(n: usize) -> Ordering {
        Ordering {
            fwd: (0..n).collect(),
            inv: (0..n).collect(),
        }
    }

    /// Nested dissection of the vertices (see the function below) with the `nc` dofs of each
    /// vertex kept together (dof = vertex · nc + component).
    pub fn nested_dissection(
        keys: &[VertexKey],
        col_ptr: &[usize],
        row_idx: &[u32],
        nc: usize,
    ) -> Ordering {
        let order = nested_dissection(keys, col_ptr, row_idx, nc);
        let fwd: Vec<usize> = order
            .iter()
            .flat_map(|&v| (0..nc).map(move |c| v as usize * nc + c))
            .collect();
        let mut inv = vec![0usize; fwd.len()];
        for (new, &old) in fwd.iter().enumerate() {
            inv[old] = new;
        }
        Ordering { fwd, inv }
    }

    pub fn len(&self) -> usize {
        self.fwd.len()
    }

    pub fn is_empty(&self) -> bool {
        self.fwd.is_empty()
    }
}

/// Vertex sets at most this large are not bisected further.
const ND_LEAF: usize = 64;
/// Vertex sets at least this large bisect their halves in parallel.
const ND_PARALLEL: usize = 4096;

/// Geometric nested-dissection ordering of the vertices (fill-reducing ordering for the
/// Cholesky factor): bisect the vertex set at the median of its integer positions along the
/// axis whose cut has the smaller separator (the longer side of its bounding box on a tie),
/// take the vertices of the upper half coupled to the lower half as separator, order both
/// halves recursively and the separator last.
///
/// The cut had been along the longer side alone. On the contact strips, refined towards their
/// contact side, a subset long across the coarse cells holds most of its vertices in the fine
/// layer, and its median cut ran through the layer: Table IV.9's last mesh (109 928 unknowns)
/// had 26.3 M nonzeros in L, its reference mesh (387 862) 178 M, and the reference solve took
/// 48 s. With the smaller of the two separators: 3.87 M and 23.0 M nonzeros, 2.3 s.
///
/// On the quadtree meshes of the thesis this gives less fill than AMD and costs a fraction of
/// its time. The result depends only on the mesh (the halves are concatenated in a fixed order),
/// not on the thread count. Returns the vertices in elimination order.
fn nested_dissection(
    keys: &[VertexKey],
    col_ptr: &[usize],
    row_idx: &[u32],
    nc: usize,
) -> Vec<u32> {
    use std::sync::atomic::{AtomicBool, Ordering};
    let removed: Vec<AtomicBool> = (0..keys.len()).map(|_| AtomicBool::new(false)).collect();

    struct Ctx<'a> {
        keys: &'a [VertexKey],
        col_ptr: &'a [usize],
        row_idx: &'a [u32],
        nc: usize,
        removed: &'a [AtomicBool],
        leaf: usize,
    }

    fn coord(k: VertexKey, axis: usize) -> u64 {
        if axis == 0 {
            k.0
        } else {
            k.1
        }
    }

    /// Whether `v`, of the upper half of a cut at `m` along `axis`, is coupled to a (not yet
    /// removed) vertex below `m`: a vertex of the separator.
    fn is_separator(ctx: &Ctx<'_>, v: u32, axis: usize, m: u64) -> bool {
        let d = v as usize * ctx.nc;
        ctx.row_idx[ctx.col_ptr[d]..ctx.col_ptr[d + 1]]
            .iter()
            .any(|&d| {
                let w = d as usize / ctx.nc;
                coord(ctx.keys[w], axis) < m && !ctx.removed[w].load(Ordering::Relaxed)
            })
    }

    /// The cut of `verts` at the median of their positions along `axis` (above it where the
    /// median ties with the lowest position) and its separator; `None` if all positions along
    /// `axis` are equal. Reorders `verts`.
    fn split(ctx: &Ctx<'_>, verts: &mut [u32], axis: usize) -> Option<(u64, Vec<u32>)> {
        let mid = verts.len() / 2;
        let key = |v: &u32| coord(ctx.keys[*v as usize], axis);
        verts.select_nth_unstable_by_key(mid, key);
        let mut m = key(&verts[mid]);
        if verts.iter().all(|v| key(v) >= m) {
            m = verts.iter().map(key).filter(|&c| c > m).min()?;
        }
        let separator = verts
            .iter()
            .copied()
            .filter(|&v| key(&v) >= m && is_separator(ctx, v, axis, m))
            .collect();
        Some((m, separator))
    }

    fn dissect(ctx: &Ctx<'_>, mut verts: Vec<u32>) -> Vec<u32> {
        if verts.len() <= ctx.leaf {
            verts.sort_unstable();
            return verts;
        }
        let (mut lo, mut hi) = ([u64::MAX; 2], [0u64; 2]);
        for &v in &verts {
            let k = ctx.keys[v as usize];
            for (a, c) in [k.0, k.1].into_iter().enumerate() {
                lo[a] = lo[a].min(c);
                hi[a] = hi[a].max(c);
            }
        }
        // Both cuts are tried and the one with the smaller separator taken (the longer side
        // on a tie): on a mesh graded towards a side, a subset is often long across the coarse
        // cells but holds most of its vertices in the fine layer, where a cut along the longer
        // side runs through the layer (see the function's docs).
        let longer = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
        let Some(first) = split(ctx, &mut verts, longer) else {
            verts.sort_unstable();
            return verts;
        };
        let ((m, mut separator), axis) = match split(ctx, &mut verts, 1 - longer) {
            Some(other) if other.1.len() < first.1.len() => (other, 1 - longer),
            _ => (first, longer),
        };
        let key = |v: &u32| coord(ctx.keys[*v as usize], axis);
        let (low, high): (Vec<u32>, Vec<u32>) = verts.into_iter().partition(|v| key(v) < m);
        for &v in &separator {
            ctx.removed[v as usize].store(true, Ordering::Relaxed);
        }
        let high: Vec<u32> = high
            .into_iter()
            .filter(|&v| !ctx.removed[v as usize].load(Ordering::Relaxed))
            .collect();
        let (mut a, b) = if low.len() + high.len() >= ND_PARALLEL {
            rayon::join(|| dissect(ctx, low), || dissect(ctx, high))
        } else {
            (dissect(ctx, low), dissect(ctx, high))
        };
        a.extend(b);
        separator.sort_unstable();
        a.extend(separator);
        a
    }

    let ctx = Ctx {
        keys,
        col_ptr,
        row_idx,
        nc,
        removed: &removed,
        leaf: ND_LEAF,
    };
    dissect(&ctx, (0..keys.len() as u32).collect())
}
