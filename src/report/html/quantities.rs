//! The engineering quantities of a section (`crate::study::quantities`): the last row's values
//! with their units, one line of a table; every cycle's are in `data/<table>.csv`.

use std::fmt::Write as _;

use super::{escape, fmt_sig};
use crate::results::RunResult;
use crate::study::quantities::label;

/// The quantity columns of `run`'s last row as a one-row table, or nothing where it has none.
pub(super) fn engineering(h: &mut String, run: &RunResult) {
    let Some(row) = run.rows.last() else {
        return;
    };
    let shown: Vec<(String, &str, f64)> = row
        .columns
        .iter()
        .filter_map(|(name, _)| {
            let (text, unit) = label(name)?;
            Some((text, unit, row.value(name)?))
        })
        .collect();
    if shown.is_empty() {
        return;
    }
    let _ = write!(
        h,
        "<h3>Engineering quantities</h3>\n<p>Of the last {} ({}); every {}'s are in \
         <code>data/{}.csv</code>, the formulas in the data guide (report/README.md).</p>\n\
         <div class=\"scroll\"><table>\n<thead><tr>",
        if run.is_load_steps() {
            "load step"
        } else {
            "cycle"
        },
        row.cycle,
        if run.is_load_steps() { "step" } else { "cycle" },
        escape(&crate::report::data::csv_stem(&run.table)),
    );
    for (text, unit, _) in &shown {
        let _ = write!(h, "<th>{} [{}]</th>", escape(text), escape(unit));
    }
    h.push_str("</tr></thead>\n<tbody><tr>");
    for (_, _, value) in &shown {
        let _ = write!(h, "<td>{}</td>", fmt_sig(*value));
    }
    h.push_str("</tr></tbody></table></div>\n");
}
