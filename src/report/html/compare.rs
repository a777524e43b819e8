//! The section of a comparison of runs ([`crate::report::compare`]): what was compared, a table
//! with one row per run — which run it is, the compared quantities, the estimate and the dofs of
//! its last printed cycle and its seconds — the runs without a result, and the figures. It is
//! folded like a table's section and stands before the first run it compares.

use std::fmt::Write as _;

use super::{anchor, escape, fmt_seconds, fmt_sig, fmt_value, SectionFigures};
use crate::report::compare::{last_value, ComparedRuns};
use crate::report::run_seconds;
use crate::study::quantities::label;

/// The folded section of comparison `c` with its figures `figs`.
pub(super) fn comparison_section(h: &mut String, c: &ComparedRuns, figs: &SectionFigures) {
    let _ = writeln!(
        h,
        "<details class=\"entry\"><summary>{} — {} runs compared</summary>\n\
         <section id=\"{}\">\n<h2>{}</h2>\n<p>{}</p>",
        escape(&c.title),
        c.runs.len() + c.missing.len(),
        escape(&c.anchor),
        escape(&c.title),
        escape(&c.what),
    );
    h.push_str("<div class=\"scroll\"><table>\n<thead><tr>");
    for column in &c.columns {
        let _ = write!(h, "<th class=\"text\">{}</th>", escape(column));
    }
    for q in &c.quantities {
        let (text, unit) = label(q).unwrap_or_else(|| (q.clone(), ""));
        let _ = write!(h, "<th>{} [{}]</th>", escape(&text), escape(unit));
    }
    h.push_str(
        "<th>last estimate</th><th>dofs</th><th>cycle</th><th>seconds</th>\
         <th class=\"text\">run</th></tr></thead>\n<tbody>\n",
    );
    for r in &c.runs {
        h.push_str("<tr>");
        for value in &r.values {
            let _ = write!(h, "<td class=\"text\"><code>{}</code></td>", escape(value));
        }
        for q in &c.quantities {
            let _ = write!(
                h,
                "<td>{}</td>",
                fmt_sig(last_value(r.run, q).unwrap_or(f64::NAN))
            );
        }
        let last = r.run.rows.last();
        let _ = writeln!(
            h,
            "<td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td class=\"text\"><a href=\"#{}\">{}</a></td></tr>",
            fmt_sig(last.and_then(|row| row.estimate()).unwrap_or(f64::NAN)),
            last.and_then(|row| row.dofs())
                .map_or("—".into(), |n| fmt_value("dofs", n as f64)),
            last.map_or("—".into(), |row| row.cycle.to_string()),
            fmt_seconds(run_seconds(r.run)),
            anchor(&r.run.table),
            escape(&r.run.table),
        );
    }
    h.push_str("</tbody></table></div>\n");
    if !c.missing.is_empty() {
        h.push_str("<p class=\"legend\">Without a result on this page: ");
        let links = c.missing.iter().map(|id| (format!("#{}", anchor(id)), id));
        super::link_list(h, links, ", ");
        h.push_str(
            " (a run that failed says why in its section; a related table not run is not on \
             the page).</p>\n",
        );
    }
    if c.quantities.is_empty() {
        h.push_str(
            "<p class=\"legend\">No engineering quantity compared: the scene computes none \
             (an elastic body, the model-adaptive film), or <code>[sweep] quantities</code> \
             names none.</p>\n",
        );
    } else if c.axis.is_none() && !c.own_norms {
        h.push_str(
            "<p class=\"legend\">The swept values are not numbers, so the quantities are not \
             plotted against them.</p>\n",
        );
    }
    super::figures_block(h, figs);
    h.push_str("</section>\n</details>\n");
}
