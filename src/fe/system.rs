//! Sparse symmetric systems of Q₁ problems: sparsity pattern with hanging dofs condensed,
//! deterministic parallel assembly, fixed dofs (Dirichlet, hanging, active contact or cavitation
//! constraints) and the sparse Cholesky solve with faer.
//!
//! Constrained rows keep their diagonal entry, so the sparsity pattern — and with it the symbolic
//! factorisation — stays the same while only the set of fixed dofs changes (as in deal.II): an
//! active-set iteration costs one numeric factorisation.

use std::mem::MaybeUninit;

use faer::dyn_stack::{MemStack, StackReq};
use faer::perm::PermRef;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, SymbolicCholesky, SymmetricOrdering,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Side};
use rayon::prelude::*;

use super::dofs::DofMap;

/// faer's factorisation and triangular solves run sequentially. Its supernodal Cholesky visits
/// the supernodes one after another and parallelises only inside each dense block; on the 2D
/// meshes here almost all blocks are too small to pay for the synchronisation. Measured on the
/// 2-core machine over the twenty Reynolds tables at full size: 70 s of solve phases against
/// 110 s with `Par::rayon(2)` (same meshes, values equal to 2e-14). Assembly and estimation stay
/// parallel (rayon), and the factorisations do not depend on the size of the thread pool.
const FACTORISATION_PARALLELISM: faer::Par = faer::Par::Seq;

/// Why a linear solve failed.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
pub enum SolveError {
    #[error("sparse Cholesky factorisation failed ({0}); the system is not symmetric positive definite — check the boundary conditions")]
    Factorisation(String),
    #[error("the solution contains a non-finite value at dof {0}")]
    NonFinite(usize),
    #[error("the right-hand side contains a non-finite value at dof {0}")]
    NonFiniteData(usize),
}

/// One local dof of a cell expanded to a global dof with weight 2^(−wexp)
/// (hanging dofs expand to their two parents with weight ½).
#[derive(Clone, Copy, Debug)]
struct Expanded {
    global: u32,
    local: u8,
    wexp: u8,
}

#[derive(Clone, Copy, Debug)]
struct MatEntry {
    pos: u32,
    lij: u16,
    wexp: u8,
}

/// Symmetric sparsity pattern over all dofs (full storage, compressed columns) and the plan to
/// scatter cell matrices into it.
pub struct SparseSystem {
    n: usize,
    n_local: usize,
    col_ptr: Vec<usize>,
    row_idx: Vec<usize>,
    diag: Vec<usize>,
    cell_start: Vec<usize>,
    entries: Vec<MatEntry>,
    rhs_start: Vec<usize>,
    rhs_entries: Vec<Expanded>,
    /// Fill-reducing ordering (new → old dof, old → new dof) from [`nested_dissection`].
    perm_fwd: Vec<usize>,
    perm_inv: Vec<usize>,
    symbolic: Option<SymbolicCholesky<usize>>,
    buffers: SolveBuffers,
}

/// Work arrays of [`SparseSystem::solve_fixed`]: the eliminated matrix values, the values of the
/// Cholesky factor and faer's scratch memory. They are large (the factor holds ~40 M values at
/// 0.7 M dofs), and freshly mapped memory costs a page fault per 4 KiB on first touch, so they
/// are kept between the solves of an active-set iteration and, through
/// [`SparseSystem::into_buffers`] and [`SparseSystem::with_buffers`], from one mesh to the next.
/// Their contents never carry over: every solve overwrites them.
#[derive(Default)]
pub struct SolveBuffers {
    matrix: Vec<f64>,
    factor: Vec<f64>,
    scratch: Vec<MaybeUninit<u8>>,
}

/// faer's scratch memory for `req` in `buffer`, grown if needed.
fn scratch(buffer: &mut Vec<MaybeUninit<u8>>, req: StackReq) -> &mut MemStack {
    let bytes = req.unaligned_bytes_required();
    if buffer.len() < bytes {
        buffer.resize(bytes, MaybeUninit::uninit());
    }
    MemStack::new(buffer)
}

impl SparseSystem {
    /// Pattern of a Q₁ problem on `dofs`: every pair of dofs that share a cell (after
    /// expanding hanging dofs) plus every diagonal entry.
    pub fn new(dofs: &DofMap) -> SparseSystem {
        let n = dofs.n_dofs();
        let nc = dofs.n_components;
        let n_local = 4 * nc;
        let v = &dofs.vertices;
        let hang = |vert: u32| -> Option<[u32; 2]> {
            if v.is_hanging[vert as usize] {
                let i = v
                    .hanging
                    .binary_search_by_key(&vert, |h| h.vertex)
                    .expect("hanging");
                Some(v.hanging[i].parents)
            } else {
                None
            }
        };
        // Expanded local dofs of every cell, flat: cell k owns rhs_entries[rhs_start[k]..rhs_start[k + 1]].
        let n_cells = v.cell_vertices.len();
        let expand = |k: usize, push: &mut dyn FnMut(Expanded)| {
            for (lv, &vert) in v.cell_vertices[k].iter().enumerate() {
                for c in 0..nc {
                    let local = (lv * nc + c) as u8;
                    match hang(vert) {
                        None => push(Expanded {
                            global: (vert as usize * nc + c) as u32,
                            local,
                            wexp: 0,
                        }),
                        Some(p) => {
                            for q in p {
                                push(Expanded {
                                    global: (q as usize * nc + c) as u32,
                                    local,
                                    wexp: 1,
                                });
                            }
                        }
                    }
                }
            }
        };
        let counts: Vec<usize> = (0..n_cells)
            .into_par_iter()
            .map(|k| {
                let mut m = 0;
                expand(k, &mut |_| m += 1);
                m
            })
            .collect();
        let mut rhs_start = Vec::with_capacity(n_cells + 1);
        let mut cell_start = Vec::with_capacity(n_cells + 1);
        rhs_start.push(0);
        cell_start.push(0);
        for &m in &counts {
            rhs_start.push(rhs_start.last().unwrap() + m);
            cell_start.push(cell_start.last().unwrap() + m * m);
        }
        drop(counts);
        let mut rhs_entries = vec![
            Expanded {
                global: 0,
                local: 0,
                wexp: 0
            };
            rhs_start[n_cells]
        ];
        split_by_offsets(&mut rhs_entries, &rhs_start)
            .into_par_iter()
            .enumerate()
            .for_each(|(k, out)| {
                let mut i = 0;
                expand(k, &mut |e| {
                    out[i] = e;
                    i += 1;
                });
            });
        // Cells touching each global dof (after expansion), in cell order.
        let mut touch_start = vec![0usize; n + 1];
        for e in &rhs_entries {
            touch_start[e.global as usize + 1] += 1;
        }
        for j in 0..n {
            touch_start[j + 1] += touch_start[j];
        }
        let mut touch = vec![0u32; rhs_entries.len()];
        {
            let mut next = touch_start[..n].to_vec();
            for k in 0..n_cells {
                for e in &rhs_entries[rhs_start[k]..rhs_start[k + 1]] {
                    let g = e.global as usize;
                    touch[next[g]] = k as u32;
                    next[g] += 1;
                }
            }
        }
        // Column j: every dof sharing a cell with j, plus j itself; built in parallel blocks of
        // columns and stitched in column order.
        const BLOCK: usize = 4096;
        let blocks: Vec<(Vec<usize>, Vec<usize>)> = (0..n.div_ceil(BLOCK))
            .into_par_iter()
            .map(|b| {
                let cols = b * BLOCK..((b + 1) * BLOCK).min(n);
                let mut lens = Vec::with_capacity(cols.len());
                let mut rows = Vec::with_capacity(cols.len() * 10 * nc);
                let mut buf: Vec<usize> = Vec::new();
                for j in cols {
                    buf.clear();
                    buf.push(j);
                    for &k in &touch[touch_start[j]..touch_start[j + 1]] {
                        let k = k as usize;
                        buf.extend(
                            rhs_entries[rhs_start[k]..rhs_start[k + 1]]
                                .iter()
                                .map(|e| e.global as usize),
                        );
                    }
                    buf.sort_unstable();
                    buf.dedup();
                    lens.push(buf.len());
                    rows.extend_from_slice(&buf);
                }
                (lens, rows)
            })
            .collect();
        drop(touch);
        drop(touch_start);
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0usize);
        for (lens, _) in &blocks {
            for &l in lens {
                col_ptr.push(col_ptr.last().unwrap() + l);
            }
        }
        let nnz = col_ptr[n];
        let mut row_idx = Vec::with_capacity(nnz);
        for (_, rows) in blocks {
            row_idx.extend_from_slice(&rows);
        }
        assert!(
            nnz < u32::MAX as usize,
            "matrix too large for 32-bit positions"
        );
        let find = |i: usize, j: usize| -> usize {
            let col = &row_idx[col_ptr[j]..col_ptr[j + 1]];
            col_ptr[j] + col.binary_search(&i).expect("entry in pattern")
        };
        let diag: Vec<usize> = (0..n).into_par_iter().map(|i| find(i, i)).collect();
        let mut entries = vec![
            MatEntry {
                pos: 0,
                lij: 0,
                wexp: 0
            };
            cell_start[n_cells]
        ];
        split_by_offsets(&mut entries, &cell_start)
            .into_par_iter()
            .enumerate()
            .for_each(|(k, out)| {
                let e = &rhs_entries[rhs_start[k]..rhs_start[k + 1]];
                let mut i = 0;
                for a in e {
                    for b in e {
                        out[i] = MatEntry {
                            pos: find(a.global as usize, b.global as usize) as u32,
                            lij: (a.local as usize * n_local + b.local as usize) as u16,
                            wexp: a.wexp + b.wexp,
                        };
                        i += 1;
                    }
                }
            });
        let order = nested_dissection(&v.keys, &col_ptr, &row_idx, nc);
        let perm_fwd: Vec<usize> = order
            .iter()
            .flat_map(|&v| (0..nc).map(move |c| v as usize * nc + c))
            .collect();
        let mut perm_inv = vec![0usize; n];
        for (new, &old) in perm_fwd.iter().enumerate() {
            perm_inv[old] = new;
        }
        SparseSystem {
            n,
            n_local,
            col_ptr,
            row_idx,
            diag,
            cell_start,
            entries,
            rhs_start,
            rhs_entries,
            perm_fwd,
            perm_inv,
            symbolic: None,
            buffers: SolveBuffers::default(),
        }
    }

    /// The pattern of [`SparseSystem::new`], solving in the work arrays of an earlier system.
    pub fn with_buffers(dofs: &DofMap, buffers: SolveBuffers) -> SparseSystem {
        SparseSystem {
            buffers,
            ..SparseSystem::new(dofs)
        }
    }

    /// The work arrays, for the system of the next mesh.
    pub fn into_buffers(self) -> SolveBuffers {
        self.buffers
    }

    pub fn n(&self) -> usize {
        self.n
    }

    pub fn nnz(&self) -> usize {
        self.row_idx.len()
    }

    /// Column pointers of the (full, symmetric) compressed-column pattern.
    pub fn col_ptr(&self) -> &[usize] {
        &self.col_ptr
    }

    /// Row indices of the pattern, sorted within each column.
    pub fn row_idx(&self) -> &[usize] {
        &self.row_idx
    }

    /// Position of entry (i, j) in the value array, if it is in the pattern.
    pub fn position(&self, i: usize, j: usize) -> Option<usize> {
        let col = &self.row_idx[self.col_ptr[j]..self.col_ptr[j + 1]];
        col.binary_search(&i).ok().map(|p| self.col_ptr[j] + p)
    }

    /// Assemble cell matrices and vectors. `cell(k, ke, fe)` fills the `n_local × n_local`
    /// matrix (row-major) and the `n_local` vector of active cell `k`; it runs in parallel,
    /// the summation into the global system runs in cell order (bitwise deterministic).
    pub fn assemble<F>(&self, n_cells: usize, cell: F) -> (Vec<f64>, Vec<f64>)
    where
        F: Fn(usize, &mut [f64], &mut [f64]) + Sync,
    {
        let nl = self.n_local;
        // Cells are computed in parallel blocks into one reused buffer and summed block by
        // block: no cell-matrix array of the whole mesh.
        const BLOCK: usize = 8192;
        let mut ke = vec![0.0; BLOCK.min(n_cells) * nl * nl];
        let mut fe = vec![0.0; BLOCK.min(n_cells) * nl];
        // Written, not calloc'ed: a fresh zero page that is read before it is written costs a
        // copy-on-write fault with a TLB shootdown on every page.
        let mut values = zeros(self.nnz());
        let mut rhs = zeros(self.n);
        for first in (0..n_cells).step_by(BLOCK) {
            let len = BLOCK.min(n_cells - first);
            ke[..len * nl * nl].fill(0.0);
            fe[..len * nl].fill(0.0);
            ke[..len * nl * nl]
                .par_chunks_mut(nl * nl)
                .zip(fe[..len * nl].par_chunks_mut(nl))
                .enumerate()
                .for_each(|(i, (m, f))| cell(first + i, m, f));
            for i in 0..len {
                let k = first + i;
                let m = &ke[i * nl * nl..(i + 1) * nl * nl];
                for e in &self.entries[self.cell_start[k]..self.cell_start[k + 1]] {
                    values[e.pos as usize] += m[e.lij as usize] * weight(e.wexp);
                }
                let f = &fe[i * nl..(i + 1) * nl];
                for e in &self.rhs_entries[self.rhs_start[k]..self.rhs_start[k + 1]] {
                    rhs[e.global as usize] += f[e.local as usize] * weight(e.wexp);
                }
            }
        }
        (values, rhs)
    }

    /// y = A x for assembled (unconstrained) values.
    pub fn multiply(&self, values: &[f64], x: &[f64]) -> Vec<f64> {
        // Symmetric: row i of A = column i.
        (0..self.n)
            .into_par_iter()
            .map(|i| {
                (self.col_ptr[i]..self.col_ptr[i + 1])
                    .map(|p| values[p] * x[self.row_idx[p]])
                    .sum()
            })
            .collect()
    }

    /// Diagonal of the assembled matrix.
    pub fn diagonal(&self, values: &[f64]) -> Vec<f64> {
        self.diag.iter().map(|&p| values[p]).collect()
    }

    /// Solve A u = f where the dofs in `fixed` take the given values (Dirichlet data, hanging
    /// dofs, active constraints); `is_fixed` flags the same dofs. Rows and columns of fixed dofs
    /// are eliminated keeping a scaled diagonal entry, so the pattern and the symbolic
    /// factorisation are reused between calls.
    pub fn solve_fixed(
        &mut self,
        values: &[f64],
        rhs: &[f64],
        fixed: &[(usize, f64)],
    ) -> Result<Vec<f64>, SolveError> {
        if let Some(i) = rhs.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFiniteData(i));
        }
        if self.symbolic.is_none() {
            let perm = PermRef::new_checked(&self.perm_fwd, &self.perm_inv, self.n);
            self.symbolic = Some(
                factorize_symbolic_cholesky(
                    self.symbolic_ref(),
                    Side::Lower,
                    SymmetricOrdering::Custom(perm),
                    Default::default(),
                )
                .map_err(|e| SolveError::Factorisation(format!("{e:?}")))?,
            );
        }
        let mut buffers = std::mem::take(&mut self.buffers);
        let result = self.solve_in(&mut buffers, values, rhs, fixed);
        self.buffers = buffers;
        result
    }

    /// [`SparseSystem::solve_fixed`] once the symbolic factorisation exists, in `buffers`.
    fn solve_in(
        &self,
        buffers: &mut SolveBuffers,
        values: &[f64],
        rhs: &[f64],
        fixed: &[(usize, f64)],
    ) -> Result<Vec<f64>, SolveError> {
        let SolveBuffers {
            matrix: a,
            factor,
            scratch: work,
        } = buffers;
        a.clear();
        a.extend_from_slice(values);
        let mut b = rhs.to_vec();
        let mut is_fixed = vec![false; self.n];
        for &(d, _) in fixed {
            is_fixed[d] = true;
        }
        // Diagonal scale of the free rows, for conditioning of the eliminated rows.
        let (sum, count) = (0..self.n)
            .filter(|&i| !is_fixed[i])
            .fold((0.0, 0usize), |(s, c), i| {
                (s + values[self.diag[i]].abs(), c + 1)
            });
        let scale = if count > 0 && sum > 0.0 {
            sum / count as f64
        } else {
            1.0
        };
        for &(d, val) in fixed {
            for p in self.col_ptr[d]..self.col_ptr[d + 1] {
                let i = self.row_idx[p];
                if !is_fixed[i] {
                    b[i] -= a[p] * val;
                }
                a[p] = 0.0;
                // The mirrored entry (d, i) in column i.
                let col = &self.row_idx[self.col_ptr[i]..self.col_ptr[i + 1]];
                a[self.col_ptr[i] + col.binary_search(&d).expect("symmetric pattern")] = 0.0;
            }
        }
        for &(d, val) in fixed {
            a[self.diag[d]] = scale;
            b[d] = scale * val;
        }
        let symbolic = self.symbolic.as_ref().expect("symbolic factorisation");
        let mat = SparseColMatRef::new(self.symbolic_ref(), &a[..]);
        let par = FACTORISATION_PARALLELISM;
        // faer overwrites every value of the factor (it fills it with zeros first).
        factor.resize(symbolic.len_val(), 0.0);
        let llt = symbolic
            .factorize_numeric_llt(
                factor,
                mat,
                Side::Lower,
                Default::default(),
                par,
                scratch(
                    work,
                    symbolic.factorize_numeric_llt_scratch::<f64>(par, Default::default()),
                ),
                Default::default(),
            )
            .map_err(|e| SolveError::Factorisation(format!("{e:?}")))?;
        let mut x = b;
        llt.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut x, self.n, 1),
            par,
            scratch(work, symbolic.solve_in_place_scratch::<f64>(1, par)),
        );
        if let Some(i) = x.iter().position(|v| !v.is_finite()) {
            return Err(SolveError::NonFinite(i));
        }
        for &(d, val) in fixed {
            x[d] = val;
        }
        Ok(x)
    }

    fn symbolic_ref(&self) -> SymbolicSparseColMatRef<'_, usize> {
        SymbolicSparseColMatRef::new_checked(self.n, self.n, &self.col_ptr, None, &self.row_idx)
    }
}

#[inline]
fn weight(wexp: u8) -> f64 {
    match wexp {
        0 => 1.0,
        1 => 0.5,
        2 => 0.25,
        w => 0.5f64.powi(w as i32),
    }
}

/// Vertex sets at most this large are not bisected further.
const ND_LEAF: usize = 64;
/// Vertex sets at least this large bisect their halves in parallel.
const ND_PARALLEL: usize = 4096;

/// Geometric nested-dissection ordering of the vertices (fill-reducing ordering for the
/// Cholesky factor): bisect the vertex set at the median of its integer positions along the
/// longer side of its bounding box, take the vertices of the upper half coupled to the lower
/// half as separator, order both halves recursively and the separator last.
///
/// On the quadtree meshes of the thesis this gives less fill than AMD and costs a fraction of
/// its time. The result depends only on the mesh (the halves are concatenated in a fixed order),
/// not on the thread count. Returns the vertices in elimination order.
fn nested_dissection(
    keys: &[(u32, u32)],
    col_ptr: &[usize],
    row_idx: &[usize],
    nc: usize,
) -> Vec<u32> {
    use std::sync::atomic::{AtomicBool, Ordering};
    let removed: Vec<AtomicBool> = (0..keys.len()).map(|_| AtomicBool::new(false)).collect();

    struct Ctx<'a> {
        keys: &'a [(u32, u32)],
        col_ptr: &'a [usize],
        row_idx: &'a [usize],
        nc: usize,
        removed: &'a [AtomicBool],
        leaf: usize,
    }

    fn coord(k: (u32, u32), axis: usize) -> u32 {
        if axis == 0 {
            k.0
        } else {
            k.1
        }
    }

    fn dissect(ctx: &Ctx<'_>, mut verts: Vec<u32>) -> Vec<u32> {
        if verts.len() <= ctx.leaf {
            verts.sort_unstable();
            return verts;
        }
        let (mut lo, mut hi) = ([u32::MAX; 2], [0u32; 2]);
        for &v in &verts {
            let k = ctx.keys[v as usize];
            for (a, c) in [k.0, k.1].into_iter().enumerate() {
                lo[a] = lo[a].min(c);
                hi[a] = hi[a].max(c);
            }
        }
        let axis = usize::from(hi[1] - lo[1] > hi[0] - lo[0]);
        let mid = verts.len() / 2;
        let key = |v: &u32| coord(ctx.keys[*v as usize], axis);
        verts.select_nth_unstable_by_key(mid, key);
        let mut m = key(&verts[mid]);
        if verts.iter().all(|v| key(v) >= m) {
            // Ties at the lower end: split above the median value instead.
            match verts.iter().map(key).filter(|&c| c > m).min() {
                Some(next) => m = next,
                None => {
                    verts.sort_unstable();
                    return verts;
                }
            }
        }
        let (low, high): (Vec<u32>, Vec<u32>) = verts.into_iter().partition(|v| key(v) < m);
        // Separator: vertices of the upper half coupled to a (not yet removed) vertex below m.
        let is_separator = |&v: &u32| {
            let d = v as usize * ctx.nc;
            ctx.row_idx[ctx.col_ptr[d]..ctx.col_ptr[d + 1]]
                .iter()
                .any(|&d| {
                    let w = d / ctx.nc;
                    coord(ctx.keys[w], axis) < m && !ctx.removed[w].load(Ordering::Relaxed)
                })
        };
        let separator: Vec<u32> = high.iter().copied().filter(is_separator).collect();
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
        let mut separator = separator;
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

/// Split `data` into the consecutive pieces `offsets[k]..offsets[k + 1]`.
fn split_by_offsets<'a, T>(mut data: &'a mut [T], offsets: &[usize]) -> Vec<&'a mut [T]> {
    let mut out = Vec::with_capacity(offsets.len().saturating_sub(1));
    for w in offsets.windows(2) {
        let (head, tail) = data.split_at_mut(w[1] - w[0]);
        out.push(head);
        data = tail;
    }
    out
}

/// A vector of `len` zeros, written (in parallel) rather than allocated zeroed.
fn zeros(len: usize) -> Vec<f64> {
    (0..len).into_par_iter().map(|_| 0.0).collect()
}
