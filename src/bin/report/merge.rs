//! `report merge`: one page, its figures and its data files from the records (shards) of
//! several output folders, as a single run of all their tables would write them.

use std::path::{Path, PathBuf};
use std::time::Instant;

use tribo::report::record::{self, RecordEntry};
use tribo::report::{self, data, Entry, Section};

use crate::folder;

/// The data files' names a record writes: its table's, and those of its alternative readings.
fn tables_of(r: &record::Record) -> Vec<&str> {
    match &r.entry {
        RecordEntry::Done {
            run, alternatives, ..
        } => std::iter::once(run.table.as_str())
            .chain(alternatives.iter().map(|a| match &a.outcome {
                Ok(run) => run.table.as_str(),
                Err(f) => f.table.as_str(),
            }))
            .collect(),
        RecordEntry::Failed(f) => vec![f.table.as_str()],
    }
}

/// Refuse two records of one table: the records are named after their stems, but what they
/// write is named after the table inside (`data/<table>.csv`, its figures), so a record renamed
/// or edited to another stem would overwrite the other record's files.
fn unique_tables(records: &[record::Record]) -> Result<(), String> {
    let mut seen: std::collections::HashMap<&str, &str> = std::collections::HashMap::new();
    for r in records {
        for table in tables_of(r) {
            if let Some(first) = seen.insert(table, &r.stem) {
                return Err(format!(
                    "table {table} is in two shard records: {} and {} (a record's file name \
                     must be its table's; was one renamed or edited?)",
                    record_name(first),
                    record_name(&r.stem)
                ));
            }
        }
    }
    Ok(())
}

/// How a record's file is named in the shard folder.
fn record_name(stem: &str) -> String {
    format!("{}/{stem}.json", record::DIR)
}

/// The meshes (`data/*.vtu`) and their series (`data/*.pvd`) of the shards, copied into
/// `out/data/`: the records do not hold them (a mesh of 0.7 M cells), so merge takes the files
/// the shard runs wrote.
fn copy_meshes(shards: &[PathBuf], out: &Path) -> std::io::Result<()> {
    let target = out.join("data");
    std::fs::create_dir_all(&target)?;
    for shard in shards {
        let Ok(files) = std::fs::read_dir(shard.join("data")) else {
            continue;
        };
        for file in files {
            let path = file?.path();
            if path.extension().is_some_and(|e| e == "vtu" || e == "pvd") {
                let to = target.join(path.file_name().expect("a file in a folder"));
                let same = matches!(
                    (path.canonicalize(), to.canonicalize()),
                    (Ok(a), Ok(b)) if a == b
                );
                if !same {
                    tribo::fsio::copy(&path, &to)?;
                }
            }
        }
    }
    Ok(())
}

/// `report merge`: the page, figures, data files and records of the shards' entries in `out`.
/// Returns Ok(false) when a merged entry (or one of its alternative readings, or its figures)
/// failed; Err when the shards cannot be merged or `out` cannot be written.
pub fn merge(shards: &[PathBuf], out: &Path) -> Result<bool, String> {
    let started = Instant::now();
    let provenance = report::provenance::Provenance::collect(
        std::env::args(),
        Path::new(env!("CARGO_MANIFEST_DIR")),
    );
    let records = record::read_shards(shards)?;
    unique_tables(&records)?;
    let cannot_write =
        |e: &dyn std::fmt::Display| format!("cannot write the report into {}: {e}", out.display());
    let _lock = folder::FolderLock::take(out)?;
    folder::check(out)?;
    let stems: Vec<String> = records.iter().map(|r| r.stem.clone()).collect();
    let page = folder::PendingPage::new(
        out,
        &format!(
            "merging {} shards, started {}",
            shards.len(),
            provenance.date
        ),
        &stems,
    );
    report::prepare_output(out)
        .and_then(|()| page.write())
        .map_err(|e| cannot_write(&e))?;
    // Every record is in memory now, so `out` may be one of the shards.
    record::clear(out, true).map_err(|e| cannot_write(&e))?;
    let mut theses = Vec::with_capacity(records.len());
    let mut failed = 0;
    for r in &records {
        report::remove_outputs(out, &r.stem).map_err(|e| cannot_write(&e))?;
        record::write(out, r).map_err(|e| cannot_write(&e))?;
        match &r.entry {
            RecordEntry::Done {
                run,
                thesis,
                alternatives,
            } => {
                // Checked when the record was read.
                theses.push(Some(thesis.thesis()?));
                let printed = theses
                    .last()
                    .and_then(Option::as_ref)
                    .expect("pushed above");
                data::write_all(&out.join("data"), run, printed).map_err(|e| cannot_write(&e))?;
                for alt in alternatives {
                    match &alt.outcome {
                        Ok(run) => data::write_all(&out.join("data"), run, printed)
                            .map_err(|e| cannot_write(&e))?,
                        Err(_) => failed += 1,
                    }
                }
            }
            RecordEntry::Failed(_) => {
                theses.push(None);
                failed += 1;
            }
        }
    }
    copy_meshes(shards, out).map_err(|e| cannot_write(&e))?;
    let entries: Vec<Entry> = records
        .iter()
        .zip(&theses)
        .filter_map(|(r, thesis)| match &r.entry {
            RecordEntry::Done {
                run, alternatives, ..
            } => thesis.as_ref().map(|thesis| {
                Entry::Done(Section {
                    run,
                    thesis,
                    alternatives,
                })
            }),
            RecordEntry::Failed(failure) => Some(Entry::Failed(failure)),
        })
        .collect();
    let meta = record::merged_meta(
        &records,
        format!("tribo {}", env!("CARGO_PKG_VERSION")),
        provenance.command,
    );
    let written = report::write_report(out, &entries, &meta).map_err(|e| cannot_write(&e))?;
    for message in &written.figure_failures {
        eprintln!("error (figures): {message}");
    }
    let failures = failed + written.figure_failures.len();
    eprintln!(
        "wrote {} ({} tables from {} shards, {} tier, merged in {:.1} s){}",
        out.join("index.html").display(),
        entries.len(),
        shards.len(),
        meta.tier,
        started.elapsed().as_secs_f64(),
        if failures == 0 {
            String::new()
        } else {
            format!("; {failures} failed")
        },
    );
    Ok(failures == 0)
}
