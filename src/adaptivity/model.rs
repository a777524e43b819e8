//! Model marking: which units use the coarse and which the accurate model — Algorithms III.2
//! (fixed fraction) and III.3 (sorted error) of §III.1, as the Chapter IV runs evidently ran
//! them (docs/estimators.md §2.2, §2.3).
//!
//! A unit is a contact face f ⊂ Γ_C in the contact tables (𝕋_c: z-faces, 𝕋_a: Signorini
//! faces, §IV.2.3) or a cell of Ω₂ in the fluid ones. The functions here see only unit indices
//! in a stable geometric order and one model-error indicator ε^m per unit; they move units
//! between 𝕋_c and 𝕋_a. The global model error is (Σ_{𝕋_c} ε^m²)^{1/2} ([`model_error`]).
//!
//! **Ties** are broken by the geometric order: among equal indicators the unit with the smaller
//! index moves first, in both directions (docs/estimators.md §2.2: with ε^m ≡ 0 the faces are taken in face
//! iteration order, l. 6103).

use std::collections::BTreeSet;

use crate::mesh::{BoundaryFace, CellKey, MAX_LEVEL};

/// A unit of model adaptivity as the mesh names it from cycle to cycle: a contact face
/// (𝕋 = the faces of Γ_C in the contact tables) or a cell (𝕋 = the cells of Ω₂ in the fluid
/// film). Ordered faces before cells, each in its stable geometric order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum ModelUnit {
    Face(BoundaryFace),
    Cell(CellKey),
}

/// The model-error indicators ε^m of one cycle, one per unit, in the order the model marking
/// takes them (its ties go to the earlier unit).
pub type ModelIndicators = Vec<(ModelUnit, f64)>;

impl ModelUnit {
    /// The unit refinement made this one from (`None` on the coarse grid): the parent face, or
    /// the parent cell (one level up, the lower-left corner rounded down to its width).
    pub fn parent(&self) -> Option<ModelUnit> {
        match *self {
            ModelUnit::Face(f) => f.parent().map(ModelUnit::Face),
            ModelUnit::Cell(c) => {
                let level = c.level.checked_sub(1)?;
                let width = 1u64 << (MAX_LEVEL - level);
                Some(ModelUnit::Cell(CellKey {
                    level,
                    x: c.x - c.x % width,
                    y: c.y - c.y % width,
                }))
            }
        }
    }

    /// The contact face, if the unit is one.
    pub fn face(&self) -> Option<BoundaryFace> {
        match *self {
            ModelUnit::Face(f) => Some(f),
            ModelUnit::Cell(_) => None,
        }
    }
}

/// The accurate units among `units` (those of a new mesh) when `accurate` were the accurate
/// units of the old one, by the lineage of the mesh: a unit that was there keeps its model, a
/// refined unit's children inherit it, and a unit made by coarsening is accurate if any unit it
/// replaces was.
pub fn inherit_models(accurate: &BTreeSet<ModelUnit>, units: &[ModelUnit]) -> BTreeSet<ModelUnit> {
    let ancestors = |u: &ModelUnit| std::iter::successors(u.parent(), ModelUnit::parent);
    let ancestors_of_accurate: BTreeSet<ModelUnit> = accurate.iter().flat_map(ancestors).collect();
    units
        .iter()
        .copied()
        .filter(|u| {
            accurate.contains(u)
                || ancestors_of_accurate.contains(u)
                || ancestors(u).any(|a| accurate.contains(&a))
        })
        .collect()
}

/// Which units use the accurate model (𝕋_a); the others use the coarse one (𝕋_c).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Partition {
    accurate: Vec<bool>,
}

impl Partition {
    /// Every one of `n` units coarse: 𝕋_c = 𝕋, 𝕋_a = ∅ (the start of Algorithms III.1–III.3).
    pub fn coarse(n: usize) -> Partition {
        Partition {
            accurate: vec![false; n],
        }
    }

    /// A partition with the given accurate units.
    pub fn from_accurate(accurate: Vec<bool>) -> Partition {
        Partition { accurate }
    }

    pub fn len(&self) -> usize {
        self.accurate.len()
    }

    pub fn is_empty(&self) -> bool {
        self.accurate.is_empty()
    }

    /// Whether unit `i` uses the accurate model.
    pub fn is_accurate(&self, i: usize) -> bool {
        self.accurate[i]
    }

    /// |𝕋_c|.
    pub fn n_coarse(&self) -> usize {
        self.len() - self.n_accurate()
    }

    /// |𝕋_a|.
    pub fn n_accurate(&self) -> usize {
        self.accurate.iter().filter(|&&a| a).count()
    }

    /// The flags, indexed like the units.
    pub fn accurate(&self) -> &[bool] {
        &self.accurate
    }

    /// The coarse unit of largest indicator (the smallest index among equals).
    fn top_coarse(&self, eps: &[f64]) -> Option<usize> {
        (0..self.len())
            .filter(|&i| !self.accurate[i])
            .fold(None, |best, i| match best {
                Some(b) if eps[b] >= eps[i] => Some(b),
                _ => Some(i),
            })
    }

    /// The accurate unit of smallest indicator (the smallest index among equals).
    fn bottom_accurate(&self, eps: &[f64]) -> Option<usize> {
        (0..self.len())
            .filter(|&i| self.accurate[i])
            .fold(None, |best, i| match best {
                Some(b) if eps[b] <= eps[i] => Some(b),
                _ => Some(i),
            })
    }
}

/// The global model-error estimate ε^m = (Σ_{Q∈𝕋_c} ε^m(Q)²)^{1/2}, summed over the coarse
/// units only (docs/estimators.md §2: the accurate units carry no model error).
pub fn model_error(partition: &Partition, eps: &[f64]) -> f64 {
    squared_coarse_error(partition, eps).sqrt()
}

fn squared_coarse_error(partition: &Partition, eps: &[f64]) -> f64 {
    (0..partition.len())
        .filter(|&i| !partition.is_accurate(i))
        .map(|i| eps[i] * eps[i])
        .sum()
}

/// What one marking step moved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Moves {
    /// Units moved from 𝕋_c to 𝕋_a by the swap phase of III.3 (0 for III.2).
    pub swapped_to_accurate: usize,
    /// Units moved from 𝕋_a to 𝕋_c by the swap phase of III.3 (0 for III.2).
    pub swapped_to_coarse: usize,
    /// Units moved from 𝕋_c to 𝕋_a by the refinement phase.
    pub refined: usize,
    /// Units moved from 𝕋_a to 𝕋_c by the coarsening phase.
    pub coarsened: usize,
}

/// One marking step of **Algorithm III.2** (fixed fraction strategy), as the Chapter IV runs
/// did it (Tables IV.18, 20, 22, 24, 26, 28; docs/estimators.md §2.2):
/// * move the ⌊p_r·|𝕋_c|⌋ coarse units of largest ε^m to 𝕋_a — also when ε^m = 0 (the printed
///   face counts keep falling in IV.18 with a flat obstacle, so the ε₀ test was not active);
///   the printed loop `while |𝕋_c| > (1 − p_r)|𝕋_c|` would move ⌊p_r·|𝕋_c|⌋ + 1 (11 of 512),
///   the tables show ⌊p_r·|𝕋_c|⌋ (10: 512, 502, 492, 483, …);
/// * then move the ⌊p_c·|𝕋_a|⌋ accurate units of smallest ε^m back (0 while |𝕋_a| < 100 at
///   p_c = 1 %).
pub fn fixed_fraction(
    partition: &mut Partition,
    eps: &[f64],
    refine_fraction: f64,
    coarsen_fraction: f64,
) -> Moves {
    assert_eq!(eps.len(), partition.len(), "one indicator per unit");
    let mut moves = Moves::default();
    let n_refine = (refine_fraction * partition.n_coarse() as f64).floor() as usize;
    for _ in 0..n_refine {
        let Some(top) = partition.top_coarse(eps) else {
            break;
        };
        partition.accurate[top] = true;
        moves.refined += 1;
    }
    let n_coarsen = (coarsen_fraction * partition.n_accurate() as f64).floor() as usize;
    for _ in 0..n_coarsen {
        let Some(bottom) = partition.bottom_accurate(eps) else {
            break;
        };
        partition.accurate[bottom] = false;
        moves.coarsened += 1;
    }
    moves
}

/// Most iterations of the swap phase of III.3, per unit. Each swap either lowers Σ_{𝕋_c} ε²
/// (a unit to 𝕋_a) or raises it without passing ε₀² (a unit back); a run needing more than
/// this many is an error rather than a silent cycle.
pub const SWAPS_PER_UNIT: usize = 4;

/// The swap phase of III.3 did not settle.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error(
    "the swap phase of Algorithm III.3 did not settle within {cap} moves ({units} units, \
     |𝕋_c| = {coarse}, model error {error:e}, ε₀ = {eps0:e})"
)]
pub struct SwapsExceeded {
    pub cap: usize,
    pub units: usize,
    pub coarse: usize,
    pub error: f64,
    pub eps0: f64,
}

/// One marking step of **Algorithm III.3** (sorted error strategy), as the Chapter IV runs did
/// it (Tables IV.19, 21, 23, 25, 27, 29; docs/estimators.md §2.3, indentation repaired). With
/// E² = Σ_{𝕋_c} ε^m²:
/// 1. **Swap** while max_{𝕋_c} ε^m > min_{𝕋_a} ε^m, where the min over an empty 𝕋_a is 0: if
///    E² + (min_{𝕋_a} ε^m)² > ε₀², move the coarse maximum to 𝕋_a (E² falls), else move the
///    accurate minimum back (E² rises). From 𝕋_a = ∅ this moves exactly the global maximum
///    (IV.29: 512 → 500 is this one plus 11 below; IV.25: 512 → 511, all the error on one face).
/// 2. **Refine**: while E > ε₀ and |𝕋_c| > (1 − p_r)|𝕋_c| (a real bound: ⌈p_r|𝕋_c|⌉ units), move
///    the coarse maximum and subtract its ε² — the update is not printed, but IV.21 stops after 8
///    of 10 (500 → 492).
/// 3. **Coarsen**: while E² + (min_{𝕋_a} ε^m)² ≤ ε₀² and |𝕋_a| > (1 − p_c)|𝕋_a|, move the
///    accurate minimum back and add its ε² (⌈p_c|𝕋_a|⌉ units; IV.27 returns one face per cycle
///    while ε^m ≡ 0: 500/12 → 508/4).
///
/// The outer loop of the thesis runs every cycle even when E ≤ ε₀ (IV.23 and IV.27 keep
/// coarsening); only these inner loops test ε₀. Afterwards max_{𝕋_c} ε^m ≤ min_{𝕋_a} ε^m holds
/// whenever the refinement and coarsening phases moved nothing across it.
pub fn sorted_error(
    partition: &mut Partition,
    eps: &[f64],
    refine_fraction: f64,
    coarsen_fraction: f64,
    eps0: f64,
) -> Result<Moves, SwapsExceeded> {
    assert_eq!(eps.len(), partition.len(), "one indicator per unit");
    let eps0_sq = eps0 * eps0;
    let mut e2 = squared_coarse_error(partition, eps);
    let mut moves = Moves::default();

    // 1. Swap phase.
    let cap = SWAPS_PER_UNIT * partition.len().max(1);
    let mut swaps = 0;
    while let Some(top) = partition.top_coarse(eps) {
        let bottom = partition.bottom_accurate(eps);
        let min_accurate = bottom.map_or(0.0, |b| eps[b]);
        if eps[top] <= min_accurate {
            break;
        }
        swaps += 1;
        if swaps > cap {
            return Err(SwapsExceeded {
                cap,
                units: partition.len(),
                coarse: partition.n_coarse(),
                error: e2.max(0.0).sqrt(),
                eps0,
            });
        }
        if e2 + min_accurate * min_accurate > eps0_sq {
            partition.accurate[top] = true;
            e2 -= eps[top] * eps[top];
            moves.swapped_to_accurate += 1;
        } else if let Some(b) = bottom {
            partition.accurate[b] = false;
            e2 += eps[b] * eps[b];
            moves.swapped_to_coarse += 1;
        } else {
            // E ≤ ε₀ with 𝕋_a empty: nothing to move in either direction.
            break;
        }
    }

    // 2. Limited refinement.
    let keep = (1.0 - refine_fraction) * partition.n_coarse() as f64;
    while e2 > eps0_sq && partition.n_coarse() as f64 > keep {
        let Some(top) = partition.top_coarse(eps) else {
            break;
        };
        partition.accurate[top] = true;
        e2 -= eps[top] * eps[top];
        moves.refined += 1;
    }

    // 3. Limited coarsening.
    let keep = (1.0 - coarsen_fraction) * partition.n_accurate() as f64;
    while partition.n_accurate() as f64 > keep {
        let Some(bottom) = partition.bottom_accurate(eps) else {
            break;
        };
        let back = eps[bottom] * eps[bottom];
        if e2 + back > eps0_sq {
            break;
        }
        partition.accurate[bottom] = false;
        e2 += back;
        moves.coarsened += 1;
    }
    Ok(moves)
}

#[cfg(test)]
mod tests {
    use super::*;

    const P_R: f64 = 0.02;
    const P_C: f64 = 0.01;
    const EPS0: f64 = 1e-7;

    /// The parent of a cell unit is the cell the mesh refined it from, on a graded mesh of a
    /// 3×2 coarse grid; coarse cells have none.
    #[test]
    fn a_cell_unit_names_its_parent_cell() {
        let mut mesh = crate::mesh::Mesh::new([0.0, 3.0], [0.0, 2.0], 3, 2);
        mesh.refine_global().unwrap();
        let refine: Vec<bool> = (0..mesh.n_active()).map(|k| k % 5 == 0).collect();
        let none = vec![false; refine.len()];
        mesh.refine_and_coarsen(&refine, &none).unwrap();
        let mut children = 0;
        for &c in mesh.active() {
            let unit = ModelUnit::Cell(mesh.cell_key(c));
            let parent = mesh.parent(c).map(|p| ModelUnit::Cell(mesh.cell_key(p)));
            assert_eq!(unit.parent(), parent);
            children += usize::from(mesh.level(c) == 2);
        }
        assert!(children > 0);
        assert_eq!(ModelUnit::Cell(mesh.cell_key(0)).parent(), None);
    }

    /// The coarse counts of cycles 0–9 when every cycle sees the indicators `eps(cycle)` and
    /// marks with `step`.
    fn coarse_counts(
        eps: impl Fn(usize) -> Vec<f64>,
        mut step: impl FnMut(&mut Partition, &[f64]),
    ) -> Vec<usize> {
        let mut p = Partition::coarse(512);
        let mut counts = vec![p.n_coarse()];
        for cycle in 0..9 {
            step(&mut p, &eps(cycle));
            counts.push(p.n_coarse());
        }
        counts
    }

    fn sorted(p: &mut Partition, eps: &[f64]) {
        sorted_error(p, eps, P_R, P_C, EPS0).unwrap();
    }

    /// Distinct indicators well above ε₀: every unit's error matters.
    fn spread(_: usize) -> Vec<f64> {
        (0..512)
            .map(|i| 1e-3 * (1.0 + ((i * 37) % 512) as f64))
            .collect()
    }

    #[test]
    fn fixed_fraction_moves_the_printed_counts() {
        // IV.18, 20, 22, 24, 26, 28: whatever the indicators, even all zero.
        let printed = vec![512, 502, 492, 483, 474, 465, 456, 447, 439, 431];
        let fixed = |p: &mut Partition, eps: &[f64]| {
            fixed_fraction(p, eps, P_R, P_C);
        };
        assert_eq!(coarse_counts(spread, fixed), printed);
        assert_eq!(coarse_counts(|_| vec![0.0; 512], fixed), printed);
    }

    #[test]
    fn fixed_fraction_takes_ties_in_geometric_order() {
        let mut p = Partition::coarse(512);
        fixed_fraction(&mut p, &[0.0; 512], P_R, P_C);
        assert!((0..10).all(|i| p.is_accurate(i)) && (10..512).all(|i| !p.is_accurate(i)));
    }

    #[test]
    fn sorted_error_moves_the_counts_of_iv_29() {
        assert_eq!(
            coarse_counts(spread, sorted),
            vec![512, 500, 490, 480, 470, 460, 450, 441, 432, 423]
        );
    }

    #[test]
    fn all_the_error_on_one_face_moves_that_face_only_iv_25() {
        let one = |_| {
            let mut e = vec![0.0; 512];
            e[300] = 2.0;
            e
        };
        let counts = coarse_counts(one, sorted);
        assert_eq!(counts[0], 512);
        assert!(counts[1..].iter().all(|&c| c == 511), "{counts:?}");
    }

    #[test]
    fn zero_error_returns_one_face_per_cycle_iv_27() {
        // Cycle 0 has an error (512 → 500), every later cycle none.
        let eps = |cycle| {
            if cycle == 0 {
                spread(0)
            } else {
                vec![0.0; 512]
            }
        };
        let mut p = Partition::coarse(512);
        let mut rows = vec![(p.n_coarse(), p.n_accurate())];
        for cycle in 0..9 {
            sorted(&mut p, &eps(cycle));
            rows.push((p.n_coarse(), p.n_accurate()));
        }
        assert_eq!(rows[1], (500, 12));
        assert_eq!(rows[9], (508, 4));
        assert!(
            rows[1..].windows(2).all(|w| w[1].0 == w[0].0 + 1),
            "{rows:?}"
        );
    }

    #[test]
    fn refinement_stops_once_the_error_is_below_eps0_iv_21() {
        // After cycle 0 (512 → 500) eight coarse faces carry all the error: cycle 1 moves those
        // eight and stops, 500 → 492, though ⌈0.02·500⌉ = 10 were allowed.
        let mut p = Partition::coarse(512);
        sorted(&mut p, &spread(0));
        assert_eq!(p.n_coarse(), 500);
        let mut eps = vec![0.0; 512];
        let coarse: Vec<usize> = (0..512).filter(|&i| !p.is_accurate(i)).collect();
        for &i in &coarse[100..108] {
            eps[i] = 1e-3;
        }
        for i in (0..512).filter(|&i| p.is_accurate(i)) {
            eps[i] = 1.0;
        }
        let moves = sorted_error(&mut p, &eps, P_R, P_C, EPS0).unwrap();
        assert_eq!(p.n_coarse(), 492, "{moves:?}");
        assert_eq!(moves.refined, 8);
        assert_eq!(model_error(&p, &eps), 0.0);
    }

    #[test]
    fn after_sorted_error_no_coarse_unit_exceeds_an_accurate_one() {
        // Indicators that change from cycle to cycle, so that the swap phase has work.
        let mut p = Partition::coarse(200);
        for cycle in 0..20usize {
            let eps: Vec<f64> = (0..200)
                .map(|i| 1e-4 * (((i * 7919 + cycle * 104_729) % 211) as f64))
                .collect();
            let moves = sorted_error(&mut p, &eps, P_R, P_C, EPS0).unwrap();
            let max_c = (0..200)
                .filter(|&i| !p.is_accurate(i))
                .map(|i| eps[i])
                .fold(0.0, f64::max);
            let min_a = (0..200)
                .filter(|&i| p.is_accurate(i))
                .map(|i| eps[i])
                .fold(f64::INFINITY, f64::min);
            assert!(
                max_c <= min_a,
                "cycle {cycle}: {max_c} > {min_a} ({moves:?})"
            );
        }
    }

    #[test]
    fn no_error_moves_nothing_from_the_start() {
        let mut p = Partition::coarse(64);
        let moves = sorted_error(&mut p, &[0.0; 64], P_R, P_C, EPS0).unwrap();
        assert_eq!((p.n_coarse(), moves), (64, Moves::default()));
        assert_eq!(model_error(&p, &[0.0; 64]), 0.0);
    }
}
