//! A general sparse matrix in compressed rows: the blocks A, B, C of the saddle points
//! (III.86) and whatever else needs a plain matrix–vector product of any shape.

/// A sparse matrix in compressed rows (any shape): row `i` has the column indices
/// `col_idx[row_ptr[i]..row_ptr[i + 1]]` (sorted, no duplicates) and the values at the same
/// positions.
#[derive(Clone, Debug, PartialEq)]
pub struct CsrMatrix {
    pub n_rows: usize,
    pub n_cols: usize,
    pub row_ptr: Vec<usize>,
    pub col_idx: Vec<usize>,
    pub values: Vec<f64>,
}

impl CsrMatrix {
    /// From (row, column, value) triplets; duplicates are summed. Panics on an index out of
    /// range.
    pub fn from_triplets(
        n_rows: usize,
        n_cols: usize,
        mut triplets: Vec<(usize, usize, f64)>,
    ) -> CsrMatrix {
        for &(i, j, _) in &triplets {
            assert!(
                i < n_rows && j < n_cols,
                "entry ({i}, {j}) outside {n_rows}×{n_cols}"
            );
        }
        triplets.sort_unstable_by_key(|&(i, j, _)| (i, j));
        let mut row_ptr = vec![0usize; n_rows + 1];
        let mut col_idx = Vec::with_capacity(triplets.len());
        let mut values: Vec<f64> = Vec::with_capacity(triplets.len());
        let mut last = None;
        for (i, j, v) in triplets {
            if last == Some((i, j)) {
                *values.last_mut().expect("a previous entry") += v;
            } else {
                col_idx.push(j);
                values.push(v);
                row_ptr[i + 1] += 1;
                last = Some((i, j));
            }
        }
        for i in 0..n_rows {
            row_ptr[i + 1] += row_ptr[i];
        }
        CsrMatrix {
            n_rows,
            n_cols,
            row_ptr,
            col_idx,
            values,
        }
    }

    /// Stored entries.
    pub fn nnz(&self) -> usize {
        self.values.len()
    }

    /// Row `i` as (column, value) pairs.
    pub fn row(&self, i: usize) -> impl Iterator<Item = (usize, f64)> + '_ {
        let range = self.row_ptr[i]..self.row_ptr[i + 1];
        self.col_idx[range.clone()]
            .iter()
            .copied()
            .zip(self.values[range].iter().copied())
    }

    /// y = M x (sequential: the blocks of the test problem are small).
    pub fn multiply_into(&self, x: &[f64], y: &mut [f64]) {
        debug_assert_eq!(x.len(), self.n_cols);
        debug_assert_eq!(y.len(), self.n_rows);
        for (i, y) in y.iter_mut().enumerate() {
            let mut s = 0.0;
            for p in self.row_ptr[i]..self.row_ptr[i + 1] {
                s += self.values[p] * x[self.col_idx[p]];
            }
            *y = s;
        }
    }

    /// M x.
    pub fn multiply(&self, x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; self.n_rows];
        self.multiply_into(x, &mut y);
        y
    }

    /// Mᵀ as its own compressed rows.
    pub fn transpose(&self) -> CsrMatrix {
        let mut triplets = Vec::with_capacity(self.nnz());
        for i in 0..self.n_rows {
            triplets.extend(self.row(i).map(|(j, v)| (j, i, v)));
        }
        CsrMatrix::from_triplets(self.n_cols, self.n_rows, triplets)
    }

    /// The diagonal entries M_ii, i < min(rows, columns) (0 where not stored).
    pub fn diagonal(&self) -> Vec<f64> {
        (0..self.n_rows.min(self.n_cols))
            .map(|i| self.row(i).find(|&(j, _)| j == i).map_or(0.0, |(_, v)| v))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csr_sums_duplicates_multiplies_and_transposes() {
        let m = CsrMatrix::from_triplets(
            2,
            3,
            vec![
                (1, 2, 4.0),
                (0, 0, 1.0),
                (0, 2, 2.0),
                (1, 2, -1.0),
                (0, 0, 0.5),
            ],
        );
        assert_eq!(m.row_ptr, vec![0, 2, 3]);
        assert_eq!(m.col_idx, vec![0, 2, 2]);
        assert_eq!(m.values, vec![1.5, 2.0, 3.0]);
        assert_eq!(m.multiply(&[1.0, 10.0, 100.0]), vec![201.5, 300.0]);
        let t = m.transpose();
        assert_eq!((t.n_rows, t.n_cols), (3, 2));
        assert_eq!(t.multiply(&[1.0, 10.0]), vec![1.5, 0.0, 32.0]);
        assert_eq!(m.diagonal(), vec![1.5, 0.0]);
    }
}
