//! Grid marking: the "fixed number" strategy of every Chapter IV grid-adaptive run
//! (spec/estimators.md §1.4; deal.II `refine_and_coarsen_fixed_number(tria, η, 0.3, 0.03)`),
//! with the tie band of DESIGN.md.

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
/// **Plateaus** (a tie group of more than [`PLATEAU_CELLS`] cells at a threshold): deal.II's
/// `>=`/`<=` comparisons would flag all of them in exact arithmetic, but in the thesis's runs the
/// indicators of such a plateau differ by rounding noise (quadrature weights computed per cell),
/// so about the requested number of cells was flagged and the noise chose which. tribo flags
/// exactly the requested number (n_ref + 1, resp. n_coa, counting the cells beyond the plateau)
/// and chooses among the plateau cells by a fixed pseudo-random order of their index
/// ([`plateau_order`]) — deterministic, independent of the thread count, and scattered like
/// noise. This reading matters only where whole zones carry one value (IV.64); the measured
/// effect is in that table's notes.
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
        let tie = (thr * (1.0 - TIE_BAND), thr * (1.0 + TIE_BAND));
        for (f, &e) in refine.iter_mut().zip(indicators) {
            *f = e >= tie.0 && e > 0.0;
        }
        let beyond = sorted.partition_point(|&e| e > tie.1);
        thin_plateau(
            &mut refine,
            indicators,
            tie,
            (n_ref + 1).saturating_sub(beyond),
        );
    }
    if n_coa > 0 {
        let thr = sorted[n - n_coa];
        let tie = (thr * (1.0 - TIE_BAND), thr * (1.0 + TIE_BAND));
        for ((f, &e), &r) in coarsen.iter_mut().zip(indicators).zip(&refine) {
            *f = !r && e <= tie.1;
        }
        let beyond = n - sorted.partition_point(|&e| e >= tie.0);
        thin_plateau(&mut coarsen, indicators, tie, n_coa.saturating_sub(beyond));
    }
    Marking { refine, coarsen }
}

/// If the flagged cells with an indicator inside `tie` form a plateau (more than
/// [`PLATEAU_CELLS`]), keep only `wanted` of them, taken in [`plateau_order`].
fn thin_plateau(flags: &mut [bool], indicators: &[f64], tie: (f64, f64), wanted: usize) {
    let mut group: Vec<usize> = (0..flags.len())
        .filter(|&i| flags[i] && indicators[i] >= tie.0 && indicators[i] <= tie.1)
        .collect();
    if group.len() <= PLATEAU_CELLS {
        return;
    }
    group.sort_by_key(|&i| plateau_order(i));
    for &i in &group[wanted.min(group.len())..] {
        flags[i] = false;
    }
}

/// A fixed pseudo-random key for cell `index` (the SplitMix64 finaliser): plateau cells are
/// taken in the order of this key, which scatters the choice over the plateau the way rounding
/// noise does, yet gives the same flags on every machine.
pub fn plateau_order(index: usize) -> u64 {
    let mut z = (index as u64).wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
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
