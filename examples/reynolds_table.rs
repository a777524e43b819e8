//! Scratch: run Reynolds tables at a tier and print rows, thesis comparison and per-phase seconds.
//! cargo run --release --example reynolds_table -- full IV.36 [IV.37 ...]
//! `alt:<suffix>` in place of a table name switches the following tables to the alternative
//! reading with that suffix (`alt:self-consistent`: R₃c from 2γ₃ − γ₃c; `alt:reynolds`: R₃ in
//! place of R₃c; `study::alternative_readings`).
use std::time::Instant;
use tribo::experiment;
use tribo::study::{self, Tier};
use tribo::thesis::ThesisTable;

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let tier = if args[0] == "full" {
        Tier::Full
    } else {
        Tier::Quick
    };
    let t_all = Instant::now();
    let mut alt: Option<String> = None;
    for t in &args[1..] {
        if let Some(suffix) = t.strip_prefix("alt:") {
            alt = Some(suffix.to_string());
            continue;
        }
        let mut spec =
            experiment::load(std::path::Path::new(&format!("experiments/{t}.toml"))).unwrap();
        if let Some(suffix) = &alt {
            match study::alternative_readings(&spec)
                .into_iter()
                .find(|a| &a.suffix == suffix)
            {
                Some(reading) => spec = reading.experiment,
                None => {
                    println!("{t}: no alternative reading '{suffix}'");
                    continue;
                }
            }
        }
        let thesis = ThesisTable::of(&spec);
        let t0 = Instant::now();
        let r = match study::run(&spec, tier, &|_, _, _| {}) {
            Ok(r) => r,
            Err(e) => {
                println!("{t}: ERROR {e}");
                continue;
            }
        };
        let wall = t0.elapsed().as_secs_f64();
        println!(
            "== {t}{} wall {wall:.2}s",
            alt.as_deref()
                .map(|a| format!(" (reading {a})"))
                .unwrap_or_default()
        );
        let mut sum = tribo::results::PhaseSeconds::default();
        for row in &r.rows {
            let td = thesis.value(row.cycle, "dofs").unwrap_or(f64::NAN);
            let te = thesis.value(row.cycle, "estimate").unwrap_or(f64::NAN);
            let s = row.seconds;
            sum.setup += s.setup;
            sum.assemble += s.assemble;
            sum.solve += s.solve;
            sum.estimate += s.estimate;
            sum.refine += s.refine;
            println!(
                "{} cells {:>8} dofs {:>8} (thesis {:>8}, {:+.2}%) est {:.4e} (ratio/thesis {:.4}) r {:.4} {:?} | setup {:.2} asm {:.2} solve {:.2} est {:.2} ref {:.2}",
                row.cycle, row.active_cells().unwrap_or(0), row.dofs().unwrap_or(0), td,
                100.0 * (row.value("dofs").unwrap_or(f64::NAN) / td - 1.0),
                row.estimate().unwrap_or(f64::NAN),
                row.estimate().unwrap_or(f64::NAN) / te, row.ratio().unwrap_or(f64::NAN), row.counts(),
                s.setup, s.assemble, s.solve, s.estimate, s.refine
            );
        }
        println!("phases (printed rows): setup {:.2} assemble {:.2} solve {:.2} estimate {:.2} refine {:.2}", sum.setup, sum.assemble, sum.solve, sum.estimate, sum.refine);
        for p in &r.probes {
            print!("{:.4} ", p.value);
        }
        println!();
        for n in &r.notes {
            println!("note: {n}");
        }
    }
    println!("total wall {:.2}s", t_all.elapsed().as_secs_f64());
}
