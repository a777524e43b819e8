//! Adaptivity: which cells to refine or coarsen ([`grid`], the fixed-number marking of every
//! Chapter IV grid-adaptive run) and which units use which model ([`model`], Algorithms III.2
//! and III.3). The balance of model and discretisation error ((III.93), Algorithm III.25) will
//! be a pure function of the same kind over face ids and indicators.

pub mod grid;
pub mod model;

pub use grid::{
    apply_noise_floor, mark_fixed_number, mark_fixed_number_split, rounded_measure, split_order,
    Marking, PLATEAU_CELLS, TIE_BAND,
};
