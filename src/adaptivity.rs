//! Grid marking: the "fixed number" strategy of every Chapter IV grid-adaptive run
//! (spec/estimators.md §1.4; deal.II `refine_and_coarsen_fixed_number(tria, η, 0.3, 0.03)`),
//! with the tie band of DESIGN.md.

/// Relative width of the tie band: indicators within this relative distance of a threshold count
/// as equal to it, so groups of symmetric cells are flagged together whatever the rounding noise.
pub const TIE_BAND: f64 = 1e-10;

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
/// `indicators` may be η_Q or η_Q² (the order is the same); they must be finite and ≥ 0.
pub fn mark_fixed_number(
    indicators: &[f64],
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
    sorted.sort_by(|a, b| b.total_cmp(a)); // descending
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
        let band = thr * (1.0 - TIE_BAND);
        for (f, &e) in refine.iter_mut().zip(indicators) {
            *f = e >= band && e > 0.0;
        }
    }
    if n_coa > 0 {
        let thr = sorted[n - n_coa];
        let band = thr * (1.0 + TIE_BAND);
        for ((f, &e), &r) in coarsen.iter_mut().zip(indicators).zip(&refine) {
            *f = !r && e <= band;
        }
    }
    Marking { refine, coarsen }
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
