//! The tables of a section: tribo's rows beside the printed ones (comparison), the rows of a
//! figure experiment or a run that is not compared, and the alternative readings of a scene.

use super::signorini::is_signorini_column;
use super::*;

/// Names of tribo's columns the thesis does not print, in first-appearance order.
pub(super) fn tribo_only_columns(rows: &[Row], thesis_columns: &[String]) -> Vec<(String, bool)> {
    let mut out: Vec<(String, bool)> = Vec::new();
    // The energy J(u_h) is the measurement behind `error` (in data/<table>.csv), not a result;
    // the engineering quantities have a table of their own.
    let known = |n: &str| {
        thesis_columns.iter().any(|c| c == n)
            || is_signorini_column(n)
            || n == columns::ENERGY
            || crate::study::quantities::label(n).is_some()
    };
    for r in rows {
        for (name, value) in &r.columns {
            if !known(name) && !out.iter().any(|(n, _)| n == name) {
                out.push((name.to_string(), matches!(value, Value::Count(_))));
            }
        }
    }
    out
}

/// What one row of a run is: a load step of the forming (§IV.2.4.7), or a cycle.
pub(super) fn row_noun(run: &RunResult) -> &'static str {
    if run.is_load_steps() {
        "load steps"
    } else {
        "cycles"
    }
}

/// The columns of a load-step run that its section shows, in this order and where the run has
/// them (`data/<table>.csv` has every column).
pub(super) const LOAD_STEP_COLUMNS: [&str; 11] = [
    columns::Z_FACES,
    columns::S_FACES,
    columns::DOFS,
    columns::MODEL_ERROR,
    columns::PENETRATION,
    "contact_force_top",
    "contact_force_bottom",
    columns::TIP_X,
    columns::TIP_Y,
    "z_iterations",
    "mixed_iterations",
];

/// The rows of a figure experiment, which the thesis prints no table for (the forming of
/// §IV.2.4.7 shows only the pictures of Fig. IV.54): tribo's values alone, no thesis columns,
/// no ratio to the thesis and no convergence verdict. A load-step run shows one row per step
/// with [`LOAD_STEP_COLUMNS`], any other run every column; then the seconds of the row. Without
/// `figure` (a scene of the user's own, an edited thesis experiment) the rows come without the
/// sentence about the thesis's figure.
pub(super) fn figure_rows(h: &mut String, run: &RunResult, figure: bool) {
    let name = thesis_figure(&run.table).unwrap_or_else(|| "a figure".into());
    if figure {
        let _ = writeln!(
            h,
            "<p>The thesis prints no table for this result, only the pictures of {}, so these rows \
             have nothing to compare with: they are tribo's alone. Every column is in \
             <code>data/{}.csv</code>.</p>",
            escape(&name),
            escape(&super::super::data::csv_stem(&run.table))
        );
    }
    let shown: Vec<String> = if run.is_load_steps() {
        LOAD_STEP_COLUMNS
            .iter()
            .filter(|c| run.rows.iter().any(|r| r.get(c).is_some()))
            .map(|c| c.to_string())
            .collect()
    } else {
        tribo_only_columns(&run.rows, &[])
            .into_iter()
            .map(|(n, _)| n)
            .collect()
    };
    let _ = write!(
        h,
        "<div class=\"scroll\"><table>\n<thead><tr><th>{}</th>",
        super::super::data::first_column(run)
    );
    for c in &shown {
        let _ = write!(h, "<th>{}</th>", escape(c));
    }
    h.push_str("<th>seconds</th></tr></thead>\n<tbody>\n");
    for r in &run.rows {
        let _ = write!(h, "<tr><td>{}</td>", r.cycle);
        for c in &shown {
            h.push_str(&opt_cell(match r.get(c) {
                Some(Value::Count(n)) => Some(n.to_string()),
                Some(Value::Real(Some(v))) if v.is_finite() => Some(fmt_sig(v)),
                _ => None,
            }));
        }
        let total = r.seconds.total();
        let _ = writeln!(
            h,
            "{}</tr>",
            opt_cell(total.is_finite().then(|| format!("{total:.3}")))
        );
    }
    h.push_str("</tbody></table></div>\n");
}

/// How much an alternative reading changes the table: dofs and estimate of both runs per cycle
/// and the relative change, plus the range of the change in the heading.
pub(super) fn alternative_table(
    h: &mut String,
    run: &RunResult,
    thesis: &ThesisTable,
    label: &str,
    alt: &RunResult,
) {
    let pairs: Vec<(&Row, &Row)> = run
        .rows
        .iter()
        .filter_map(|r| Some((r, alt.rows.iter().find(|a| a.cycle == r.cycle)?)))
        .collect();
    let range = |f: &dyn Fn(&Row) -> f64| {
        pairs.iter().filter_map(|(r, a)| rel_diff(f(a), f(r))).fold(
            None,
            |acc: Option<(f64, f64)>, d| {
                Some(acc.map_or((d, d), |(lo, hi)| (lo.min(d), hi.max(d))))
            },
        )
    };
    let span = |r: Option<(f64, f64)>| match r {
        Some((lo, hi)) => format!("{} … {}", fmt_pct(lo), fmt_pct(hi)),
        None => "—".into(),
    };
    // The headline columns: dofs and estimate of the grid-adaptive tables, the face split and
    // the model error of the model-adaptive ones (whose mesh is fixed).
    let model_adaptive = run.is_model_adaptive();
    let (count, value) = if model_adaptive {
        (columns::COARSE_FACES, columns::MODEL_ERROR)
    } else {
        (columns::DOFS, columns::ESTIMATE)
    };
    let _ = write!(
        h,
        "<h3>Alternative reading: {}</h3>\n<p class=\"legend\">Computed in this run. Against the \
         table above: {value} {}, {count} {}.</p>\n<div class=\"scroll\"><table><thead><tr>\
         <th>cycle</th><th>{count}</th><th>{count} (alt.)</th><th>Δ</th><th>{value}</th>\
         <th>{value} (alt.)</th><th>Δ</th><th>tribo/thesis</th><th>alt./thesis</th>\
         </tr></thead><tbody>\n",
        escape(label),
        span(range(&|r| r.value(value).unwrap_or(f64::NAN))),
        span(range(&|r| r.value(count).unwrap_or(f64::NAN))),
    );
    // The ratio to the printed row, compared as in the table above.
    let to_thesis = |rows: &[Row], cycle: usize| {
        let i = rows.iter().position(|r| r.cycle == cycle)?;
        let printed = thesis.value(cycle, value);
        let ratio = if model_adaptive {
            Some(rows[i].value(value)? / printed?).filter(|q| q.is_finite())
        } else {
            estimate_ratio(rows, i, printed)
        };
        ratio.map(fmt_sig)
    };
    for (r, a) in &pairs {
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td>{}<td>{}</td><td>{}</td>{}{}{}</tr>",
            r.cycle,
            opt_count(r.value(count).map(|v| v as usize)),
            opt_count(a.value(count).map(|v| v as usize)),
            diff_cell(
                count,
                rel_diff(nan_or(a.value(count)), nan_or(r.value(count)))
            ),
            fmt_sig(nan_or(r.value(value))),
            fmt_sig(nan_or(a.value(value))),
            diff_cell(
                value,
                rel_diff(nan_or(a.value(value)), nan_or(r.value(value)))
            ),
            opt_cell(to_thesis(&run.rows, r.cycle)),
            opt_cell(to_thesis(&alt.rows, r.cycle)),
        );
    }
    h.push_str("</tbody></table></div>\n");
}

/// A value that may be missing, as NaN (which every formatter shows as missing).
pub(super) fn nan_or(v: Option<f64>) -> f64 {
    v.unwrap_or(f64::NAN)
}

/// A count that may be missing.
pub(super) fn opt_count(v: Option<usize>) -> String {
    v.map_or_else(|| "—".into(), |n| n.to_string())
}

/// tribo beside the thesis: for each printed column tribo | thesis | Δ, then the estimate ratio,
/// tribo-only columns and seconds per phase. Rows are the union of computed and printed cycles,
/// so a quick tier that stops early still shows what the thesis printed further on; of the
/// printed rows, the first [`MAX_SHOWN_THESIS_ROWS`] are shown and the legend counts the rest.
///
/// The time is linear in the rows shown: each cycle's row of tribo is found through a map built
/// once, and each printed value directly by its cycle ([`ThesisTable::value`]).
pub(super) fn comparison_table(h: &mut String, s: &Section) {
    let run = s.run;
    let thesis = s.thesis;
    let compared: Vec<&str> = thesis
        .columns
        .iter()
        .map(String::as_str)
        .filter(|c| *c != "cycle")
        .collect();
    let has_estimate = compared.contains(&"estimate");
    let shifted = compares_previous_estimate(run);
    let part = thesis.additive_part.as_ref().filter(|_| has_estimate);
    let extra = tribo_only_columns(&run.rows, &thesis.columns);
    // With the shifted comparison, tribo's estimate on the printed mesh is a tribo-only column.
    let extra_label = |n: &str| match n {
        PREVIOUS_ESTIMATE if shifted => "estimate on this mesh".to_string(),
        THEOREM_ESTIMATE => "estimate of the theorem as stated, this mesh".to_string(),
        _ => n.to_string(),
    };
    let phases = ["setup", "assemble", "solve", "estimate", "refine", "total"];

    let cycles: BTreeSet<usize> = run
        .rows
        .iter()
        .map(|r| r.cycle)
        .chain(
            thesis
                .rows
                .iter()
                .take(MAX_SHOWN_THESIS_ROWS)
                .filter_map(|r| r.first().copied())
                .filter(|c| c.is_finite() && *c >= 0.0)
                .map(|c| c as usize),
        )
        .collect();
    // The first row of each cycle, as a search from the front would find it.
    let mut row_of_cycle: HashMap<usize, usize> = HashMap::with_capacity(run.rows.len());
    for (i, r) in run.rows.iter().enumerate() {
        row_of_cycle.entry(r.cycle).or_insert(i);
    }

    comparison_legends(h, s, shifted, &extra, part);
    h.push_str("<div class=\"scroll\"><table>\n<thead><tr><th rowspan=\"2\">cycle</th>");
    for c in &compared {
        let label = if shifted && matches!(*c, "estimate" | "ratio") {
            format!("{c} (of the solve before)")
        } else {
            c.to_string()
        };
        let _ = write!(
            h,
            "<th class=\"group\" colspan=\"3\">{}</th>",
            escape(&label)
        );
    }
    if has_estimate {
        h.push_str("<th class=\"group\" rowspan=\"2\">tribo/thesis<br>(estimate)</th>");
    }
    if let Some(p) = part {
        let _ = write!(
            h,
            "<th class=\"group\" rowspan=\"2\">tribo/√(thesis² − {}²)</th>",
            escape(&p.table)
        );
    }
    if !extra.is_empty() {
        let _ = write!(
            h,
            "<th class=\"group\" colspan=\"{}\">tribo only</th>",
            extra.len()
        );
    }
    h.push_str("<th class=\"group\" colspan=\"6\">seconds</th></tr>\n<tr>");
    for _ in &compared {
        h.push_str("<th>tribo</th><th>thesis</th><th>Δ</th>");
    }
    for (n, _) in &extra {
        let _ = write!(h, "<th>{}</th>", escape(&extra_label(n)));
    }
    for p in phases {
        let _ = write!(h, "<th>{p}</th>");
    }
    h.push_str("</tr></thead>\n<tbody>\n");

    let ratio_cell = |q: Option<f64>| match q {
        Some(q) if (q - 1.0).abs() > tolerance("estimate") => {
            format!("<td class=\"first off\">{}</td>", fmt_sig(q))
        }
        Some(q) => format!("<td class=\"first\">{}</td>", fmt_sig(q)),
        None => "<td class=\"first na\">—</td>".into(),
    };
    for cycle in cycles {
        let index = row_of_cycle.get(&cycle).copied();
        let row = index.map(|i| &run.rows[i]);
        let compared_at = |c: &str| index.and_then(|i| compared_value(&run.rows, i, c));
        let _ = write!(h, "<tr><td>{cycle}</td>");
        for c in &compared {
            let t = compared_at(c);
            let p = thesis.value(cycle, c);
            // The thesis prints `inf` for the first ratio; tribo has none there. Both mean "no
            // previous cycle", shown as an en dash rather than a number.
            let is_first_ratio = *c == "ratio" && row.is_some_and(|r| r.ratio().is_none());
            let tribo_cell = match t {
                Some(v) => format!("<td class=\"first\">{}</td>", fmt_value(c, v)),
                None if is_first_ratio => "<td class=\"first\">–</td>".into(),
                None => "<td class=\"first na\">—</td>".into(),
            };
            let thesis_cell = match p {
                Some(v) if *c == "ratio" && v.is_infinite() => "<td class=\"thesis\">–</td>".into(),
                Some(v) => format!("<td class=\"thesis\">{}</td>", fmt_value(c, v)),
                None => "<td class=\"thesis na\">—</td>".into(),
            };
            let _ = write!(
                h,
                "{tribo_cell}{thesis_cell}{}",
                diff_cell(c, t.zip(p).and_then(|(t, p)| rel_diff(t, p)))
            );
        }
        let ratio_to = |p: Option<f64>| index.and_then(|i| estimate_ratio(&run.rows, i, p));
        if has_estimate {
            h.push_str(&ratio_cell(ratio_to(thesis.value(cycle, "estimate"))));
        }
        if part.is_some() {
            h.push_str(&ratio_cell(ratio_to(thesis.estimate_without_part(cycle))));
        }
        tribo_only_cells(h, row, &extra, shifted);
        seconds_cells(h, row);
        h.push_str("</tr>\n");
    }
    h.push_str("</tbody></table></div>\n");
}

/// The legends above a comparison table: how to read it, the orders of convergence, the printed
/// rows left out, and what the shifted, theorem and additive-part columns mean.
fn comparison_legends(
    h: &mut String,
    s: &Section,
    shifted: bool,
    extra: &[(String, bool)],
    part: Option<&crate::experiment::AdditivePart>,
) {
    let thesis = s.thesis;
    h.push_str(
        "<p class=\"legend\">Each printed column as tribo | thesis | Δ = tribo/thesis − 1; \
         <span class=\"swatch\"></span> |Δ| beyond 3 % (cells, dofs) or 5 % (other columns). \
         — : not computed in this tier or not printed.</p>\n",
    );
    let order = super::Summary::of(s);
    if order.order.is_some() || order.thesis_order.is_some() {
        let _ = writeln!(
            h,
            "<p class=\"legend\">Experimental order of convergence, the least-squares slope of \
             log estimate against log dofs over the rows: tribo {}, thesis {} (−½ is optimal \
             for Q₁ elements in two dimensions).</p>",
            order.order.map_or("—".into(), fmt_order),
            order.thesis_order.map_or("—".into(), fmt_order),
        );
    }
    if thesis.len() > MAX_SHOWN_THESIS_ROWS {
        let _ = writeln!(
            h,
            "<p class=\"legend\">The thesis table has {} printed rows: the first {} are shown \
             here and in the figures, {} are left out.</p>",
            thesis.len(),
            MAX_SHOWN_THESIS_ROWS,
            thesis.len() - MAX_SHOWN_THESIS_ROWS
        );
    }
    if shifted {
        h.push_str(
            "<p class=\"legend\">The thesis prints each row's mesh after refinement next to the \
             estimate of the solve before it; its estimate and ratio are compared with tribo's \
             estimate of the previous solve (column estimate_previous_mesh).</p>\n",
        );
    }
    if extra.iter().any(|(n, _)| n == THEOREM_ESTIMATE) {
        h.push_str(
            "<p class=\"legend\">The estimate columns and the marking use the volume residual \
             that reproduces the thesis's printed estimates (estimator = \"thesis-code\", see \
             the notes); the column \"estimate of the theorem as stated\" is the estimator of \
             Theorem III.16/III.17 with every term, on the printed mesh.</p>\n",
        );
    }
    if let Some(p) = part {
        let _ = writeln!(
            h,
            "<p class=\"legend\">{t} prints a mesh-independent part of the thesis's estimate \
             alone; the column tribo/√(thesis² − {t}²) compares tribo with the printed estimate \
             without that part.</p>",
            t = escape(&p.table)
        );
    }
}

/// The tribo-only cells of a comparison row (`extra`: the column names, and whether each holds
/// counts); `–` for the first ratio, `—` where the row or value is missing.
fn tribo_only_cells(h: &mut String, row: Option<&Row>, extra: &[(String, bool)], shifted: bool) {
    for (i, (n, integer)) in extra.iter().enumerate() {
        let class = if i == 0 { "first" } else { "" };
        let v = row.and_then(|r| match n.as_str() {
            "ratio" => r.ratio(),
            PREVIOUS_ESTIMATE if shifted => r.estimate(),
            _ => r.value(n),
        });
        let _ = match v {
            Some(v) if *integer && v.fract() == 0.0 => {
                write!(h, "<td class=\"{class}\">{v:.0}</td>")
            }
            Some(v) => write!(h, "<td class=\"{class}\">{}</td>", fmt_sig(v)),
            None if n == "ratio" && row.is_some() => write!(h, "<td class=\"{class}\">–</td>"),
            None => write!(h, "<td class=\"{class} na\">—</td>"),
        };
    }
}

/// The seconds of a comparison row per phase and in total; `—` for a printed cycle tribo did not
/// compute.
fn seconds_cells(h: &mut String, row: Option<&Row>) {
    match row {
        Some(r) => {
            let s = r.seconds;
            for (i, v) in [
                s.setup,
                s.assemble,
                s.solve,
                s.estimate,
                s.refine,
                s.total(),
            ]
            .into_iter()
            .enumerate()
            {
                let class = if i == 0 { " class=\"first\"" } else { "" };
                let _ = write!(h, "<td{class}>{v:.3}</td>");
            }
        }
        None => {
            h.push_str("<td class=\"first na\">—</td>");
            h.push_str(&"<td class=\"na\">—</td>".repeat(5));
        }
    }
}
