#!/usr/bin/env python3
"""Compare the CSV data of two tribo report folders ("nothing moves" check).

Usage:

    python3 scripts/compare-report.py [--rtol 1e-12] [--quiet] FOLDER_A FOLDER_B

Each folder is the output of the `report` binary and must contain a `data/`
subfolder with `<table>.csv`, `<table>.probes.csv` and the alternative-reading
files (e.g. `IV.64.self-consistent.csv`). The script checks:

  * the same set of CSV files exists under `data/` in both folders;
  * per file, the same header (same column names in the same order) and the
    same number of rows;
  * columns named `seconds` or starting with `seconds_` are timings and are not compared
    (a timing column present on one side only is still a header difference);
  * integer columns (every non-empty value on both sides is written without a
    decimal point or exponent) and string columns must be exactly equal;
  * float values are equal if both are empty, both NaN, the same infinity, or
    |a - b| <= rtol * max(|a|, |b|).

Only files that differ are listed (row indices count data rows from 0, the
header excluded), at most 10 lines per file. The last line is the verdict:
"... : SAME" or "... : DIFFERENT (...)". It also says how many values were
identical as text, how many only within rtol, and the largest relative
difference seen.

Exit code: 0 when SAME, 1 when DIFFERENT, 2 on usage errors (missing folder,
no `data/` subfolder).

To compare two commits A and B:

    git checkout A && cargo run --release --bin report -- --out /tmp/report-A --no-progress
    git checkout B && cargo run --release --bin report -- --out /tmp/report-B --no-progress
    python3 scripts/compare-report.py /tmp/report-A /tmp/report-B
"""

import argparse
import csv
import math
import sys
from pathlib import Path

MAX_LINES_PER_FILE = 10
TIMING_PREFIX = "seconds_"
# The cumulative seconds of a solver study (data/fig-III.6.csv).
TIMING_COLUMN = "seconds"


class Totals:
    """Counters accumulated over all files."""

    def __init__(self):
        self.files_compared = 0
        self.values = 0
        self.identical_text = 0
        self.within_rtol = 0
        self.differing_values = 0
        self.files_with_value_differences = 0
        self.header_differences = 0
        self.row_count_differences = 0
        self.one_sided_files = 0
        self.largest_rel_diff = 0.0
        self.largest_where = None  # (file, row, column)


# ---------------------------------------------------------------- parsing


def is_int_text(text):
    """True if text is an integer written without decimal point or exponent."""
    digits = text[1:] if text[:1] in ("+", "-") else text
    return digits.isascii() and digits.isdigit()


def parse_float(text):
    """The float value of text (accepts NaN, inf, -inf in any case), or None."""
    try:
        return float(text)
    except ValueError:
        return None


def read_csv(path):
    """Header (list of names) and rows (lists of stripped strings) of a CSV file."""
    with open(path, newline="", encoding="utf-8") as handle:
        lines = [[cell.strip() for cell in line] for line in csv.reader(handle)]
    if not lines:
        return [], []
    return lines[0], lines[1:]


def cell(row, index):
    """The cell at index, or "" when the row is short."""
    return row[index] if index < len(row) else ""


def column_kind(values):
    """'int', 'float' or 'string' for the non-empty values of a column (both sides)."""
    present = [value for value in values if value != ""]
    if all(is_int_text(value) for value in present) and present:
        return "int"
    if all(parse_float(value) is not None for value in present):
        return "float"
    return "string"


# ---------------------------------------------------------------- comparing


def relative_difference(a, b):
    """|a - b| / max(|a|, |b|) for finite a, b; inf when only one is special."""
    if math.isnan(a) and math.isnan(b):
        return 0.0
    if math.isinf(a) or math.isinf(b) or math.isnan(a) or math.isnan(b):
        return 0.0 if a == b else math.inf
    scale = max(abs(a), abs(b))
    return 0.0 if scale == 0.0 else abs(a - b) / scale


def compare_floats(text_a, text_b, rtol):
    """(equal, relative difference or None) of two float cells."""
    if text_a == "" or text_b == "":
        return text_a == text_b, None
    rel = relative_difference(parse_float(text_a), parse_float(text_b))
    return rel <= rtol, rel


def compare_exact(kind, text_a, text_b):
    """Equality of two int or string cells."""
    if kind == "int" and text_a != "" and text_b != "":
        return int(text_a) == int(text_b)
    return text_a == text_b


def header_problems(header_a, header_b):
    """Lines describing how two headers differ (empty if they are the same)."""
    if header_a == header_b:
        return []
    only_a = [name for name in header_a if name not in header_b]
    only_b = [name for name in header_b if name not in header_a]
    problems = []
    if only_a:
        problems.append("columns only in A: " + ", ".join(only_a))
    if only_b:
        problems.append("columns only in B: " + ", ".join(only_b))
    if not only_a and not only_b:
        problems.append("column order differs: A = %s; B = %s"
                        % (",".join(header_a), ",".join(header_b)))
    return problems


def compare_file(name, path_a, path_b, rtol, totals):
    """Compare one CSV file present on both sides; returns lines describing differences."""
    header_a, rows_a = read_csv(path_a)
    header_b, rows_b = read_csv(path_b)
    problems = header_problems(header_a, header_b)
    if problems:
        totals.header_differences += 1
    if len(rows_a) != len(rows_b):
        totals.row_count_differences += 1
        problems.append("row count differs: A has %d, B has %d" % (len(rows_a), len(rows_b)))

    # Compare the common, non-timing columns over the common rows.
    columns = [
        c
        for c in header_a
        if c in header_b and not (c.startswith(TIMING_PREFIX) or c == TIMING_COLUMN)
    ]
    row_count = min(len(rows_a), len(rows_b))
    value_differences = 0
    for column in columns:
        index_a = header_a.index(column)
        index_b = header_b.index(column)
        values_a = [cell(row, index_a) for row in rows_a[:row_count]]
        values_b = [cell(row, index_b) for row in rows_b[:row_count]]
        kind = column_kind(values_a + values_b)
        for row, (text_a, text_b) in enumerate(zip(values_a, values_b)):
            totals.values += 1
            if kind == "float":
                equal, rel = compare_floats(text_a, text_b, rtol)
            else:
                equal, rel = compare_exact(kind, text_a, text_b), None
            if rel is not None and rel > totals.largest_rel_diff:
                totals.largest_rel_diff = rel
                totals.largest_where = (name, row, column)
            if equal and text_a == text_b:
                totals.identical_text += 1
            elif equal:
                totals.within_rtol += 1
            else:
                value_differences += 1
                problems.append(describe_value(row, column, text_a, text_b, rel))

    totals.differing_values += value_differences
    if value_differences:
        totals.files_with_value_differences += 1
    return problems


def describe_value(row, column, text_a, text_b, rel):
    """One line describing a differing value."""
    line = "row %d column %s: A = %r, B = %r" % (row, column, text_a, text_b)
    if rel is not None:
        line += " (rel. diff %.1e)" % rel
    return line


# ---------------------------------------------------------------- folders


def csv_files(data_dir):
    """Paths of the CSV files under data_dir, relative to data_dir, as strings."""
    return {path.relative_to(data_dir).as_posix() for path in data_dir.rglob("*.csv")}


def data_dir_of(folder):
    """The data/ subfolder of a report folder; exits with 2 if it is missing."""
    path = Path(folder)
    if not path.is_dir():
        usage_error("not a folder: %s" % folder)
    data = path / "data"
    if not data.is_dir():
        usage_error("no data/ subfolder in %s" % folder)
    return data


def usage_error(message):
    print("error: " + message, file=sys.stderr)
    sys.exit(2)


def print_file_report(name, problems):
    print("data/%s:" % name)
    for line in problems[:MAX_LINES_PER_FILE]:
        print("  " + line)
    if len(problems) > MAX_LINES_PER_FILE:
        print("  … and %d more" % (len(problems) - MAX_LINES_PER_FILE))


def final_line(totals, rtol, differing_files):
    """The one-line verdict."""
    if totals.largest_where is None:
        largest = "largest rel. diff 0"
    else:
        name, row, column = totals.largest_where
        largest = "largest rel. diff %.1e in data/%s row %d column %s" % (
            totals.largest_rel_diff, name, row, column)
    summary = "compared %d files, %d values (%d identical text, %d within rtol %g, %s)" % (
        totals.files_compared, totals.values, totals.identical_text,
        totals.within_rtol, rtol, largest)
    if not differing_files:
        return summary + ": SAME"
    parts = []
    if totals.differing_values:
        parts.append("%d values in %d files" % (totals.differing_values,
                                                totals.files_with_value_differences))
    if totals.header_differences:
        parts.append("%d header differences" % totals.header_differences)
    if totals.row_count_differences:
        parts.append("%d row count differences" % totals.row_count_differences)
    if totals.one_sided_files:
        parts.append("%d files on one side only" % totals.one_sided_files)
    return summary + ": DIFFERENT (" + "; ".join(parts) + ")"


def main():
    parser = argparse.ArgumentParser(
        description="Compare the data/*.csv files of two tribo report folders.")
    parser.add_argument("folder_a", help="first report folder (A), e.g. /tmp/report-before")
    parser.add_argument("folder_b", help="second report folder (B), e.g. /tmp/report-after")
    parser.add_argument("--rtol", type=float, default=1e-12,
                        help="relative tolerance for float values (default 1e-12)")
    parser.add_argument("--quiet", action="store_true", help="print only the final line")
    args = parser.parse_args()
    if not args.rtol >= 0.0:
        usage_error("--rtol must be a non-negative number")

    data_a = data_dir_of(args.folder_a)
    data_b = data_dir_of(args.folder_b)
    files_a = csv_files(data_a)
    files_b = csv_files(data_b)
    totals = Totals()
    differing_files = 0
    printed_legend = False

    for name in sorted(files_a | files_b):
        if name in files_a and name in files_b:
            totals.files_compared += 1
            problems = compare_file(name, data_a / name, data_b / name, args.rtol, totals)
        else:
            totals.one_sided_files += 1
            problems = ["file only in %s" % ("A" if name in files_a else "B")]
        if not problems:
            continue
        differing_files += 1
        if not args.quiet:
            if not printed_legend:
                print("A = %s\nB = %s" % (args.folder_a, args.folder_b))
                printed_legend = True
            print_file_report(name, problems)

    print(final_line(totals, args.rtol, differing_files))
    return 1 if differing_files else 0


if __name__ == "__main__":
    sys.exit(main())
