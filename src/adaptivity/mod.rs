//! Adaptivity: which cells to refine or coarsen ([`grid`], the fixed-number marking of every
//! Chapter IV grid-adaptive run). The model strategies (Algorithms III.1–III.3) and the balance of
//! model and discretisation error ((III.93), Algorithm III.25) are pure functions of the same kind
//! over face ids and indicators.

pub mod grid;

pub use grid::{
    apply_noise_floor, mark_fixed_number, rounded_measure, Marking, PLATEAU_CELLS, TIE_BAND,
};
