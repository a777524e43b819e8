#!/usr/bin/env python3
"""Run thesis tables with each of deal.II's mesh-smoothing flags and tabulate the meshes.

Usage:

    cargo build --release
    python3 scripts/smoothing-readings.py [--report BIN] [--tables IV.50,IV.52]
        [--readings none,patch-level-1] [--work DIR] [--out docs/smoothing-readings.md]
        [--csv FILE] [--from-csv FILE]

For every table and reading the script copies `experiments/<table>.toml` into a folder of
its own, sets the reading in the copy's `[scene]` (`mesh_smoothing = [...]` after the
`effects` line; the two `8x8` readings also make the 8 x 8 grid the coarse cells:
`coarse_cells = [8, 8]`, `global_refinements = 0`), runs

    report --only <table> --experiments <copy> --out <dir> --no-progress
           --no-alternatives --jobs 1

(full tier, one table at a time) and reads `data/<table>.csv`. A copy of a thesis file
counts as edited and is not scored by the report, so the printed rows are read from the
copy's own `[thesis]` block and joined by cycle: active cells, dofs, and the estimate
`estimate_previous_mesh` (the estimate the fluid tables print in a row) against the printed
estimate. The model-and-grid tables print dofs only.

The Markdown written to --out has, per table, one line per reading (cells and dofs of every
row with their deviation from the printed row, in %) and a summary: per table and reading
the worst deviation over the rows, and whether the bars for adopting a smoothing hold:
IV.50, IV.51, IV.53, IV.54 within 6 % and the other SubStokes tables within 12 % in every
row (cells and dofs), IV.52's cells exact in every row. For the tables whose estimates are
off (IV.57-IV.62, IV.73, IV.75) it also tabulates estimate ratios tribo/thesis per row.

Default readings: none, each flag alone, the three combinations, and the 8 x 8 coarse grid
with and without patch-level-1. patch-level-1 "with the 2:1 rule alone" is the reading
patch-level-1 (tribo applies the 2:1 rule in any case). Default tables: the twenty SubStokes
tables, the model-and-grid tables IV.30-IV.35 and the Reynolds tables IV.36 and IV.40.

The output folders of the runs are deleted after their CSV is read (a full-tier Reynolds
table writes hundreds of MB of mesh); --work keeps the experiment copies and the CSVs.
--csv also writes every row in long form; --from-csv rewrites the Markdown from such a file
without running anything. docs/smoothing-readings.md was made by the default run with --csv,
then the Markdown again with --from-csv.
Exit status 0, or 1 if a run failed (the table then says which).
"""

import argparse
import csv
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import tomllib
from pathlib import Path

SUBSTOKES = [f"IV.{n}" for n in list(range(50, 64)) + list(range(70, 76))]
OTHERS = [f"IV.{n}" for n in range(30, 36)] + ["IV.36", "IV.40"]
TIGHT = {"IV.50", "IV.51", "IV.53", "IV.54"}
EXACT = {"IV.52"}
ESTIMATES = {"IV.57", "IV.58", "IV.59", "IV.60", "IV.61", "IV.62", "IV.73", "IV.75"}

FLAGS = [
    "limit-level-difference-at-vertices",
    "eliminate-unrefined-islands",
    "patch-level-1",
    "coarsest-level-1",
    "eliminate-refined-inner-islands",
    "eliminate-refined-boundary-islands",
    "do-not-produce-unrefined-islands",
    "smoothing-on-refinement",
    "smoothing-on-coarsening",
    "maximum-smoothing",
]
# A reading: name -> (smoothing flags, coarse 8 x 8 grid instead of one cell refined thrice).
READINGS = {"none": ([], False)}
READINGS.update({f: ([f], False) for f in FLAGS})
READINGS["8x8"] = ([], True)
READINGS["8x8+patch-level-1"] = (["patch-level-1"], True)


def edited_copy(text, flags, coarse_8x8, rows):
    """The experiment text with the reading set and `rows` printed rows to run, or None if
    the reading does not apply."""
    lines = text.splitlines()
    study = lines.index("[study]")
    at = [i for i, l in enumerate(lines) if i > study and l.startswith("rows = ")]
    lines[at[0]] = f"rows = {rows}"
    study_file = tomllib.loads(text)["study"]
    if rows < study_file["rows"]:
        # Fewer rows: the convergence window and the quick tier must stay inside them.
        for i, l in enumerate(lines):
            if l.startswith("quick_rows = "):
                lines[i] = f"quick_rows = {min(study_file['quick_rows'], rows)}"
            if l.startswith("convergence_window = "):
                lo, hi = study_file["convergence_window"]
                hi = min(hi, rows - 1)
                lines[i] = f"convergence_window = [{max(0, min(lo, hi - 2))}, {hi}]"
    effects = next(i for i, l in enumerate(lines) if l.startswith("effects = "))
    if coarse_8x8:
        cc = [i for i, l in enumerate(lines) if l.strip() == "coarse_cells = [1, 1]"]
        gr = [i for i, l in enumerate(lines) if l.strip() == "global_refinements = 3"]
        if len(cc) != 1 or len(gr) != 1:
            return None
        lines[cc[0]] = "coarse_cells = [8, 8]"
        lines[gr[0]] = "global_refinements = 0"
    if flags:
        names = ", ".join(f'"{f}"' for f in flags)
        lines.insert(effects + 1, f"mesh_smoothing = [{names}]")
    return "\n".join(lines) + "\n"


def number(value):
    if value is None or value == "":
        return None
    return float(value)


def run(report, table, reading, text, work, budget):
    """Rows {cycle: (cells, dofs, estimate)} of one reading, or an error text. A reading
    whose mesh outgrows the memory budget is run again with one printed row fewer, until it
    fits; the rows it could not reach are missing."""
    flags, coarse = READINGS[reading]
    n_rows = tomllib.loads(text)["study"]["rows"]
    if edited_copy(text, flags, coarse, n_rows) is None:
        return "n/a"
    base = work / table / reading
    exp = base / "experiments"
    out = base / "report"
    for rows in range(n_rows, 0, -1):
        shutil.rmtree(base, ignore_errors=True)
        exp.mkdir(parents=True)
        (exp / f"{table}.toml").write_text(edited_copy(text, flags, coarse, rows))
        cmd = [report, "--only", table, "--experiments", str(exp), "--out", str(out)]
        cmd += ["--no-progress", "--no-alternatives", "--jobs", "1"]
        cmd += ["--memory-budget", budget]
        done = subprocess.run(cmd, capture_output=True, text=True)
        data = out / "data" / f"{table}.csv"
        if done.returncode == 0 and data.exists():
            break
        shutil.rmtree(out, ignore_errors=True)
        if "memory budget" not in done.stderr:
            print(done.stderr, file=sys.stderr)
            return f"failed (exit {done.returncode})"
    else:
        return f"over the {budget} budget from the first row"
    shutil.copy(data, base / f"{table}.csv")
    shutil.rmtree(out)
    rows = {}
    with open(base / f"{table}.csv", newline="") as f:
        for r in csv.DictReader(f):
            estimate = r.get("estimate_previous_mesh", r.get("estimate"))
            rows[int(r["cycle"])] = (
                number(r.get("active_cells")),
                number(r["dofs"]),
                number(estimate),
            )
    return rows


def printed(text):
    """Printed rows {cycle: (cells, dofs, estimate)} of the [thesis] block."""
    thesis = tomllib.loads(text)["thesis"]
    cols = thesis["columns"]
    out = {}
    for row in thesis["rows"]:
        r = dict(zip(cols, row))
        est = r.get("estimate")
        if est is not None and not math.isfinite(est):
            est = None
        out[int(r["cycle"])] = (r.get("active_cells"), r.get("dofs"), est)
    return out


def dev(ours, theirs):
    """Relative deviation ours/theirs - 1, or None."""
    if ours is None or theirs is None or theirs == 0:
        return None
    return ours / theirs - 1.0


def pct(d):
    return "–" if d is None else f"{100 * d:+.1f}"


def bar(table):
    """The adoption bar of a SubStokes table: ('exact', 0) or ('within', fraction)."""
    if table in EXACT:
        return ("exact", 0.0)
    if table in TIGHT:
        return ("within", 0.06)
    if table in SUBSTOKES:
        return ("within", 0.12)
    return None


def verdict(table, rows, thesis):
    """Whether the bar of `table` holds for the reading's rows (None: no bar)."""
    b = bar(table)
    if b is None:
        return None
    for k, (pc, pd, _) in thesis.items():
        if k not in rows:
            return False
        c, d, _ = rows[k]
        if b[0] == "exact":
            if pc is not None and c != pc:
                return False
            continue
        for ours, theirs in ((c, pc), (d, pd)):
            x = dev(ours, theirs)
            if x is not None and abs(x) > b[1]:
                return False
    return True


def worst(rows, thesis, column):
    """The deviation of largest magnitude over the printed rows, with its row."""
    best = None
    for k, p in thesis.items():
        if k in rows:
            x = dev(rows[k][column], p[column])
            if x is not None and (best is None or abs(x) > abs(best[0])):
                best = (x, k)
    return best


def ratio_range(rows, thesis):
    rs = [
        rows[k][2] / p[2]
        for k, p in thesis.items()
        if k in rows and rows[k][2] is not None and p[2]
    ]
    return (min(rs), max(rs)) if rs else None


def read_csv(path):
    """{(table, reading): {cycle: (cells, dofs, estimate)}} of a --csv file."""
    out = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            rows = out.setdefault((r["table"], r["reading"]), {})
            if r["dofs"] != "":
                rows[int(r["row"])] = (number(r["cells"]), number(r["dofs"]),
                                       number(r["estimate"]))
    return out


def write_markdown(path, tables, readings, results, prints, argv):
    out = []
    w = out.append
    w("# Mesh-smoothing readings of the SubStokes, model-and-grid and Reynolds tables")
    w("")
    w(f"Generated by `python3 scripts/smoothing-readings.py {' '.join(argv)}`; full tier, the "
      "estimator unchanged. A run whose mesh outgrows the memory budget is repeated with "
      "fewer rows; the rows it could not reach are shown as –. Each reading copies the table's experiment file with `[scene] mesh_smoothing` "
      "set (the `8x8` readings also make the 8 × 8 grid the coarse cells, without parents). "
      "Deviations are tribo/printed − 1 in %; `bars` is whether the adoption bars hold in "
      "every row (IV.50, IV.51, IV.53, IV.54 within 6 %, the other SubStokes tables within "
      "12 %, cells and dofs; IV.52's cells exact); the model-and-grid tables print dofs only.")
    sub = [t for t in tables if t in SUBSTOKES]
    adoptable = []
    if sub:
        w("")
        w("## Per reading over the SubStokes tables")
        w("")
        w("A smoothing is adopted for the SubStokes files only if its bars hold in every "
          "SubStokes table. Worst dofs deviation over the rows (table, row):")
        w("")
        w("| reading | bars hold | IV.52 cells exact | worst of IV.50/51/53/54 | "
          "worst of the others |")
        w("|---|---|---|---|---|")
        for rd in readings:
            ok, exact, tight, other = 0, "", None, None
            for t in sub:
                rows, th = results[t][rd], prints[t]
                if isinstance(rows, str):
                    continue
                ok += bool(verdict(t, rows, th))
                if t in EXACT:
                    exact = "yes" if verdict(t, rows, th) else "no"
                    continue
                x = worst(rows, th, 1)
                if x is None:
                    continue
                x = (x[0], f"{t} row {x[1]}")
                if t in TIGHT:
                    tight = x if tight is None or abs(x[0]) > abs(tight[0]) else tight
                else:
                    other = x if other is None or abs(x[0]) > abs(other[0]) else other
            fmt = lambda x: "–" if x is None else f"{pct(x[0])} ({x[1]})"
            w(f"| {rd} | {ok} of {len(sub)} | {exact} | {fmt(tight)} | {fmt(other)} |")
            if ok == len(sub):
                adoptable.append(rd)
        w("")
        if adoptable:
            w(f"The bars hold in every SubStokes table for: {', '.join(adoptable)}.")
        else:
            w(f"No reading meets the bars in all {len(sub)} SubStokes tables: no smoothing is "
              "adopted.")
    w("")
    w("## Summary: worst row per table and reading")
    w("")
    w("| table | reading | worst cells % (row) | worst dofs % (row) | bars | estimate ratio |")
    w("|---|---|---|---|---|---|")
    for t in tables:
        for rd in readings:
            rows = results[t][rd]
            if isinstance(rows, str):
                w(f"| {t} | {rd} | {rows} | | | |")
                continue
            th = prints[t]
            cells = worst(rows, th, 0)
            dofs = worst(rows, th, 1)
            v = verdict(t, rows, th)
            rr = ratio_range(rows, th)
            fmt = lambda x: "–" if x is None else f"{pct(x[0])} ({x[1]})"
            vs = "" if v is None else ("yes" if v else "no")
            missing = [k for k in th if k not in rows]
            if missing:
                vs += f" (rows {min(missing)}–{max(missing)} over the memory budget)"
            rs = "" if rr is None else f"{rr[0]:.2f}–{rr[1]:.2f}"
            w(f"| {t} | {rd} | {fmt(cells)} | {fmt(dofs)} | {vs} | {rs} |")
    w("")
    w("## Per row: cells (deviation %) / dofs (deviation %)")
    for t in tables:
        th = prints[t]
        ks = sorted(th)
        w("")
        w(f"### {t}")
        w("")
        w("| reading | " + " | ".join(f"row {k}" for k in ks) + " |")
        w("|---|" + "---|" * len(ks))
        cell = lambda c, d: f"{'–' if c is None else int(c)} / {'–' if d is None else int(d)}"
        w("| printed | " + " | ".join(cell(th[k][0], th[k][1]) for k in ks) + " |")
        for rd in readings:
            rows = results[t][rd]
            if isinstance(rows, str):
                w(f"| {rd} | {rows} |" + " |" * (len(ks) - 1))
                continue
            entries = []
            for k in ks:
                if k not in rows:
                    entries.append("–")
                    continue
                c, d, _ = rows[k]
                cs = "–" if c is None else f"{int(c)} ({pct(dev(c, th[k][0]))})"
                if th[k][0] is None:
                    cs = "–" if c is None else f"{int(c)}"
                entries.append(f"{cs} / {int(d)} ({pct(dev(d, th[k][1]))})")
            w(f"| {rd} | " + " | ".join(entries) + " |")
        if t in ESTIMATES:
            w("")
            w(f"Estimate ratio tribo/printed per row ({t}):")
            w("")
            w("| reading | " + " | ".join(f"row {k}" for k in ks) + " |")
            w("|---|" + "---|" * len(ks))
            for rd in readings:
                rows = results[t][rd]
                if isinstance(rows, str):
                    continue
                rs = []
                for k in ks:
                    e = rows.get(k, (None, None, None))[2]
                    p = th[k][2]
                    rs.append("–" if e is None or not p else f"{e / p:.2f}")
                w(f"| {rd} | " + " | ".join(rs) + " |")
    path.write_text("\n".join(out) + "\n")


def main():
    here = Path(__file__).resolve().parent.parent
    target = Path(os.environ.get("CARGO_TARGET_DIR", here / "target"))
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--report", default=str(target / "release" / "report"))
    ap.add_argument("--experiments", default=str(here / "experiments"))
    ap.add_argument("--tables", default=",".join(SUBSTOKES + OTHERS))
    ap.add_argument("--readings", default=",".join(READINGS))
    ap.add_argument("--work", default=None, help="keep the copies and CSVs here")
    ap.add_argument("--memory-budget", default="4G", help="of each run (report's flag)")
    ap.add_argument("--out", default=str(here / "docs" / "smoothing-readings.md"))
    ap.add_argument("--csv", default=None, help="also write the readings in long form")
    ap.add_argument("--from-csv", default=None,
                    help="write the Markdown from a --csv file of an earlier run, running nothing")
    args = ap.parse_args()
    tables = [t for t in args.tables.split(",") if t]
    readings = [r for r in args.readings.split(",") if r]
    unknown = [r for r in readings if r not in READINGS]
    if unknown:
        ap.error(f"unknown readings {unknown}; known: {', '.join(READINGS)}")
    work = Path(args.work) if args.work else Path(tempfile.mkdtemp(prefix="smoothing-"))
    earlier = read_csv(args.from_csv) if args.from_csv else {}
    results, prints, failed = {}, {}, False
    for t in tables:
        text = (Path(args.experiments) / f"{t}.toml").read_text()
        prints[t] = printed(text)
        results[t] = {}
        for rd in readings:
            if args.from_csv:
                results[t][rd] = earlier.get((t, rd), "n/a")
                continue
            rows = run(args.report, t, rd, text, work, args.memory_budget)
            results[t][rd] = rows
            failed |= isinstance(rows, str) and rows.startswith("failed")
            print(f"{t} {rd}: {rows if isinstance(rows, str) else 'ok'}", file=sys.stderr)
    argv = []
    if args.tables != ap.get_default("tables"):
        argv.append(f"--tables {args.tables}")
    if args.readings != ap.get_default("readings"):
        argv.append(f"--readings {args.readings}")
    argv.append(f"--memory-budget {args.memory_budget}")
    write_markdown(Path(args.out), tables, readings, results, prints, argv)
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            wr = csv.writer(f)
            wr.writerow(["table", "reading", "row", "cells", "printed_cells", "dofs",
                         "printed_dofs", "estimate", "printed_estimate"])
            for t in tables:
                for rd in readings:
                    rows = results[t][rd]
                    if isinstance(rows, str):
                        continue
                    for k, (pc, pd, pe) in sorted(prints[t].items()):
                        c, d, e = rows.get(k, (None, None, None))
                        wr.writerow([t, rd, k, c, pc, d, pd, e, pe])
    if not args.work:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
