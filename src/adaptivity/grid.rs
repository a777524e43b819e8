//! Grid marking: the "fixed number" strategy of every Chapter IV grid-adaptive run
//! (docs/estimators.md §1.4; deal.II `refine_and_coarsen_fixed_number(tria, η, 0.3, 0.03)`),
//! with the tie band of docs/estimators.md §1.4.

use rayon::prelude::*;

use crate::fe::quadrature;
use crate::mesh::{CellId, Mesh, MAX_LEVEL};

/// Relative width of the tie band: indicators within this relative distance of a threshold count
/// as equal to it, so groups of symmetric cells are flagged together whatever the rounding noise.
pub const TIE_BAND: f64 = 1e-10;

/// A tie group at a threshold with more than this many cells is a *plateau*, not a symmetry group:
/// e.g. the cavitated zone of the plain gap (IV.64), where ψ_h = 0 and the load is constant, so
/// every cell of one size carries the same indicator. Symmetry groups have 2, 4 or 8 members.
pub const PLATEAU_CELLS: usize = 16;

/// Refinement and coarsening flags (indexed like the indicators).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Marking {
    pub refine: Vec<bool>,
    pub coarsen: Vec<bool>,
}

impl Marking {
    pub fn n_refine(&self) -> usize {
        self.refine.iter().filter(|&&f| f).count()
    }

    pub fn n_coarsen(&self) -> usize {
        self.coarsen.iter().filter(|&&f| f).count()
    }
}

/// Fixed-number marking: flag for refinement every cell whose indicator is at least the
/// (⌊p_r N⌋+1)-th largest, and for coarsening every other cell whose indicator is at most the
/// ⌊p_c N⌋-th smallest; ties (within [`TIE_BAND`]) are all flagged. If every indicator is zero
/// nothing is flagged; a zero refinement threshold is replaced by the smallest positive
/// indicator. Which flags take effect (complete sibling groups, level 0, the 2:1 rule) is decided
/// by [`crate::mesh::Mesh::refine_and_coarsen`].
///
/// **Plateaus** (a tie group of more than [`PLATEAU_CELLS`] cells at a threshold): in exact
/// arithmetic deal.II's `>=`/`<=` comparisons flag all of them. The thesis's cell counts show
/// that its runs did not: the indicators of such a plateau differed by rounding noise, deal.II
/// flagged the plateau cells whose noisy indicator was at or beyond the threshold cell's, and
/// the cells that rounded alike tied and were flagged together (IV.64: 77, 249 and 608 cells
/// more than requested in three cycles, notes of IV.64). tribo cannot have the thesis's bits, so
/// it uses a deterministic stand-in for the noise that has the same structure, a few dozen
/// rounding classes per plateau: the indicator times the cell's relative rounded measure
/// (`measure(i)` of cell `i`, [`rounded_measure`], ≈ 1 ± a few ulp). It ranks the plateau by that key and applies deal.II's
/// rule: with `wanted` = n_ref + 1 (resp. n_coa) minus the cells beyond the plateau, every
/// plateau cell whose key is at least the `wanted`-th largest (resp. at most the `wanted`-th
/// smallest) is flagged. Where tribo's indicators already differ in their last bits (IV.10) the
/// key ranks by them; where they are bitwise equal (ψ_h = 0 and a constant load, IV.64) it ranks
/// by the rounding class. Measures that are all equal flag a plateau whole. The measured effect
/// is in the notes of IV.10, IV.64 and IV.66. `measure` is evaluated only for plateau cells.
///
/// `indicators` may be η_Q or η_Q² (the order is the same); they must be finite and ≥ 0.
pub fn mark_fixed_number(
    indicators: &[f64],
    measure: impl Fn(usize) -> f64,
    refine_fraction: f64,
    coarsen_fraction: f64,
) -> Marking {
    let n = indicators.len();
    let mut refine = vec![false; n];
    let mut coarsen = vec![false; n];
    if n == 0 || indicators.iter().all(|&e| e == 0.0) {
        return Marking { refine, coarsen };
    }
    let mut sorted: Vec<f64> = indicators.to_vec();
    // Descending; equal values under total_cmp are the same bits, so any sort gives this order.
    sorted.par_sort_unstable_by(|a, b| b.total_cmp(a));
    let n_ref = (refine_fraction * n as f64).floor() as usize;
    let n_coa = (coarsen_fraction * n as f64).floor() as usize;
    if n_ref > 0 {
        let mut thr = sorted[n_ref.min(n - 1)];
        if thr == 0.0 {
            thr = sorted
                .iter()
                .rev()
                .copied()
                .find(|&e| e > 0.0)
                .unwrap_or(0.0);
        }
        let tie = (thr * (1.0 - TIE_BAND), thr * (1.0 + TIE_BAND));
        for (f, &e) in refine.iter_mut().zip(indicators) {
            *f = e >= tie.0 && e > 0.0;
        }
        let beyond = sorted.partition_point(|&e| e > tie.1);
        let plateau = Plateau {
            tie,
            wanted: (n_ref + 1).saturating_sub(beyond),
            largest: true,
        };
        plateau.thin(&mut refine, indicators, &measure);
    }
    if n_coa > 0 {
        let thr = sorted[n - n_coa];
        let tie = (thr * (1.0 - TIE_BAND), thr * (1.0 + TIE_BAND));
        for ((f, &e), &r) in coarsen.iter_mut().zip(indicators).zip(&refine) {
            *f = !r && e <= tie.1;
        }
        let beyond = n - sorted.partition_point(|&e| e >= tie.0);
        let plateau = Plateau {
            tie,
            wanted: n_coa.saturating_sub(beyond),
            largest: false,
        };
        plateau.thin(&mut coarsen, indicators, &measure);
    }
    Marking { refine, coarsen }
}

/// Fixed-number marking that flags *exactly* the requested counts: the ⌊p_r N⌋+1 cells with the
/// largest indicators for refinement and, among the others, the ⌊p_c N⌋ with the smallest for
/// coarsening. Where a cut falls inside a tie group (indicators within [`TIE_BAND`] of the cut's
/// value), the group is split: its cells are taken in the order of `order` (smallest key first,
/// [`split_order`]) until the count is reached. Cells with a zero indicator are never flagged
/// for refinement. Which coarsening flags take effect (complete sibling groups) is decided by
/// [`crate::mesh::Mesh::refine_and_coarsen`].
///
/// This is the marking of the SubStokes tables (§IV.3.2, §IV.3.6): all twenty of their row-0
/// meshes have 124 = 64 + 3·20 cells, ⌊0.3·64⌋+1 = 20 refined cells, although most of their
/// scenes are symmetric, so that symmetric groups straddle the cut; the thesis's iterative
/// solver evidently broke every tie (flagging whole groups gives 136 cells for IV.50 and 256 for
/// IV.52). tribo cannot have the thesis's bits: the order of [`split_order`] is a deterministic
/// stand-in.
pub fn mark_fixed_number_split(
    indicators: &[f64],
    order: impl Fn(usize) -> u128,
    refine_fraction: f64,
    coarsen_fraction: f64,
) -> Marking {
    let n = indicators.len();
    let mut refine = vec![false; n];
    let mut coarsen = vec![false; n];
    let n_ref = (refine_fraction * n as f64).floor() as usize;
    let n_coa = (coarsen_fraction * n as f64).floor() as usize;
    if n == 0 || indicators.iter().all(|&e| e == 0.0) {
        return Marking { refine, coarsen };
    }
    let keys: Vec<u128> = (0..n).map(order).collect();
    let tied = |a: f64, b: f64| (a - b).abs() <= TIE_BAND * a.abs().max(b.abs());
    // Cells by indicator, largest first; within the tie band by the split order.
    let mut ranked: Vec<usize> = (0..n).collect();
    ranked.par_sort_by(|&a, &b| indicators[b].total_cmp(&indicators[a]));
    let by_key = |group: &mut [usize]| group.sort_by_key(|&i| keys[i]);
    let take =
        |ranked: &[usize], count: usize, flags: &mut [bool], skip: &dyn Fn(usize) -> bool| {
            let candidates: Vec<usize> = ranked.iter().copied().filter(|&i| !skip(i)).collect();
            let count = count.min(candidates.len());
            let Some(&last) = count.checked_sub(1).map(|k| &candidates[k]) else {
                return;
            };
            let cut = indicators[last];
            // Strictly beyond the tie group of the cut: all flagged.
            let beyond = candidates
                .iter()
                .take_while(|&&i| !tied(indicators[i], cut))
                .count();
            for &i in &candidates[..beyond] {
                flags[i] = true;
            }
            let mut group: Vec<usize> = candidates[beyond..]
                .iter()
                .copied()
                .take_while(|&i| tied(indicators[i], cut))
                .collect();
            by_key(&mut group);
            for &i in group.iter().take(count - beyond) {
                flags[i] = true;
            }
        };
    if n_ref > 0 {
        take(&ranked, n_ref + 1, &mut refine, &|i| indicators[i] == 0.0);
    }
    if n_coa > 0 {
        ranked.reverse();
        // The reversed ranking lists equal indicators in reverse order; ties are re-sorted by key.
        let flagged = refine.clone();
        take(&ranked, n_coa, &mut coarsen, &|i| flagged[i]);
    }
    Marking { refine, coarsen }
}

/// The split order of [`mark_fixed_number_split`] for active cell `c`: first the cell's position
/// among its siblings (lower-left, lower-right, upper-left, upper-right; 0 on level 0), then
/// its lower-left corner by rows (x₂, then x₁). The order does not follow the tree, so a tie
/// group split for coarsening takes one cell of each sibling group before it takes a second
/// (tied coarsening flags do not complete sibling groups), and a group split for refinement
/// spreads over the tied region.
pub fn split_order(mesh: &Mesh, c: CellId) -> u128 {
    let key = mesh.cell_key(c);
    let width = 1u64 << (MAX_LEVEL - key.level);
    let child = if key.level == 0 {
        0
    } else {
        ((key.x / width) & 1) + 2 * ((key.y / width) & 1)
    };
    // Positions are below 2⁵⁶ (module docs of `crate::mesh`): 2 + 56 + 56 bits.
    ((child as u128) << 112) | ((key.y as u128) << 56) | key.x as u128
}

/// The tie group at one threshold: `wanted` of its cells are asked for, the largest
/// (refinement) or the smallest (coarsening).
struct Plateau {
    tie: (f64, f64),
    wanted: usize,
    largest: bool,
}

impl Plateau {
    /// If the flagged cells inside the tie band form a plateau (more than [`PLATEAU_CELLS`]),
    /// keep those whose key, indicator × measure, is at or beyond the `wanted`-th one's.
    fn thin(&self, flags: &mut [bool], indicators: &[f64], measure: &impl Fn(usize) -> f64) {
        let group: Vec<usize> = (0..flags.len())
            .filter(|&i| flags[i] && indicators[i] >= self.tie.0 && indicators[i] <= self.tie.1)
            .collect();
        if group.len() <= PLATEAU_CELLS {
            return;
        }
        let Some(k) = self.wanted.checked_sub(1) else {
            group.iter().for_each(|&i| flags[i] = false);
            return;
        };
        let keys: Vec<f64> = group.iter().map(|&i| indicators[i] * measure(i)).collect();
        let mut ranked = keys.clone();
        if self.largest {
            ranked.sort_by(|a, b| b.total_cmp(a));
        } else {
            ranked.sort_by(|a, b| a.total_cmp(b));
        }
        let cut = ranked[k.min(ranked.len() - 1)];
        for (&i, &key) in group.iter().zip(&keys) {
            flags[i] = if self.largest { key >= cut } else { key <= cut };
        }
    }
}

/// The rounded measure of active cell `c` relative to its exact area: Σ_q det J(ξ_q) w_q as a
/// Q1 mapping sums it, with the Jacobian at each point of the 2×2 Gauss rule (the estimators'
/// volume rule) accumulated from the four vertices in lexicographic order,
/// J = Σ_k x_k ⊗ ∇̂φ_k(ξ_q), divided by the exact area. The quotient is 1 up to a few ulp that
/// depend on where the cell lies. It is the stand-in rounding noise of [`mark_fixed_number`];
/// it is not deal.II's own noise, which reuses the Jacobian of translated cells (its
/// `CellSimilarity`) and so got its noise from elsewhere.
pub fn rounded_measure(mesh: &Mesh, c: CellId) -> f64 {
    let vertices = mesh.corner_keys(c).map(|key| mesh.point(key));
    let mut measure = 0.0;
    for (xi, eta, w) in quadrature::square(2) {
        let gradients = [
            [-(1.0 - eta), -(1.0 - xi)],
            [1.0 - eta, -xi],
            [-eta, 1.0 - xi],
            [eta, xi],
        ];
        let mut j = [[0.0f64; 2]; 2];
        for (x, g) in vertices.iter().zip(&gradients) {
            for (row, &xa) in j.iter_mut().zip(x) {
                row[0] += xa * g[0];
                row[1] += xa * g[1];
            }
        }
        measure += (j[0][0] * j[1][1] - j[1][0] * j[0][1]) * w;
    }
    measure / mesh.cell_shape(c).area()
}

/// Indicators below `floor` are rounding noise: set them to zero (used for problems whose
/// exact solution the discretisation reproduces, where the estimate itself is noise).
pub fn apply_noise_floor(indicators: &mut [f64], floor: f64) {
    for e in indicators.iter_mut() {
        if *e < floor {
            *e = 0.0;
        }
    }
}
