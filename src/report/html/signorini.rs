//! The linearised Signorini solution against the converged one (`crate::study::signorini`): a
//! small table per section with Signorini faces, one line per cycle, under the table's rows.
//! The same numbers are the `signorini_*` columns of `data/<table>.csv`, which the section's
//! own table leaves out.

use std::fmt::Write as _;

use super::{escape, fmt_sig};
use crate::results::{Row, RunResult, Value};
use crate::study::signorini::columns::{
    is_comparison, ENERGY_DISTANCE, ITERATIONS, PENETRATION, PENETRATION_CONVERGED,
    RELATIVE_DISTANCE,
};

/// Whether a column of the section's own table is one of the comparison's (shown here instead).
pub(super) fn is_signorini_column(name: &str) -> bool {
    is_comparison(name)
}

/// The reading the table's rows use, from the file's `signorini` key (left out: linearised).
fn rows_are_converged(run: &RunResult) -> bool {
    run.parameters
        .iter()
        .any(|p| p.key == "signorini" && p.value.contains("converged"))
}

/// A real column of a row as a table cell (— where the row has none).
fn cell(row: &Row, column: &str) -> String {
    match row.value(column) {
        Some(v) => format!("<td>{}</td>", fmt_sig(v)),
        None => "<td class=\"na\">—</td>".into(),
    }
}

/// The comparison of a run with Signorini faces: a legend, one line per cycle (the cycles
/// without a comparison say why: no Signorini face, or the fixed point failed, see the notes),
/// and the ranges over the cycles. Nothing for a run without the columns.
pub(super) fn signorini_comparison(h: &mut String, run: &RunResult) {
    let compared: Vec<&Row> = run
        .rows
        .iter()
        .filter(|r| r.count_of(ITERATIONS).is_some())
        .collect();
    if compared.is_empty() {
        return;
    }
    let rows_use = if rows_are_converged(run) {
        "The table's rows use the converged solution (<code>signorini = \"converged\"</code>)."
    } else {
        "The table's rows use the linearised solution (the thesis's reading); the converged one \
         is computed beside it and not used further."
    };
    let _ = writeln!(
        h,
        "<h3>Signorini: the linearised solution against the converged one</h3>\n\
         <p class=\"legend\">§IV.2.2 linearises the Signorini condition once per cycle about a \
         previous solution s₀. Here the linearisation point is also iterated to a fixed point on \
         the same mesh (the contact set unchanged and the relative change of the displacement at \
         the contact vertices ≤ 1e-10). Per cycle: the iterations to the fixed point, the energy \
         distance ‖s_lin − s_conv‖_a (and relative to ‖s_conv‖_a), and the largest vertical depth \
         of a Signorini contact vertex beyond the obstacle (the exact condition) for each \
         solution. {rows_use} Data: the <code>signorini_*</code> columns of \
         <code>data/{}.csv</code>.</p>",
        escape(&run.table)
    );
    h.push_str(
        "<div class=\"scroll\"><table><thead><tr><th>cycle</th><th>iterations</th>\
         <th>‖s_lin − s_conv‖_a</th><th>relative</th><th>penetration, linearised</th>\
         <th>penetration, converged</th></tr></thead><tbody>\n",
    );
    for row in &run.rows {
        let _ = write!(h, "<tr><td>{}</td>", row.cycle);
        match row.count_of(ITERATIONS) {
            Some(n) => {
                let _ = write!(
                    h,
                    "<td>{n}</td>{}{}{}{}",
                    cell(row, ENERGY_DISTANCE),
                    cell(row, RELATIVE_DISTANCE),
                    cell(row, PENETRATION),
                    cell(row, PENETRATION_CONVERGED)
                );
            }
            None => {
                let why = if no_signorini_faces(row) {
                    "no Signorini face in this cycle"
                } else {
                    "no fixed point: see the notes"
                };
                let _ = write!(h, "<td class=\"text na\" colspan=\"5\">{why}</td>");
            }
        }
        h.push_str("</tr>\n");
    }
    h.push_str("</tbody></table></div>\n");
    ranges(h, &compared);
}

/// Whether a model-adaptive row has no Signorini face (its count column is 0).
fn no_signorini_faces(row: &Row) -> bool {
    ["accurate_faces", "s_faces"]
        .iter()
        .any(|c| matches!(row.get(c), Some(Value::Count(0))))
}

/// The ranges over the compared cycles, as one sentence.
fn ranges(h: &mut String, rows: &[&Row]) {
    let range = |column: &str| {
        let values: Vec<f64> = rows.iter().filter_map(|r| r.value(column)).collect();
        let lo = values.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    let (i0, i1) = range(ITERATIONS);
    let (r0, r1) = range(RELATIVE_DISTANCE);
    let (p0, p1) = range(PENETRATION);
    let (_, c1) = range(PENETRATION_CONVERGED);
    let _ = writeln!(
        h,
        "<p>Over the {} compared cycles: {}–{} iterations, relative energy distance {}–{}, \
         penetration of the linearised solution {}–{}, of the converged one at most {}.</p>",
        rows.len(),
        i0,
        i1,
        fmt_sig(r0),
        fmt_sig(r1),
        fmt_sig(p0),
        fmt_sig(p1),
        fmt_sig(c1)
    );
}
