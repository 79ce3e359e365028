#!/usr/bin/python3
"""bench_log_bound.py RUN [--out JSON]: how small can a lossless full flight log be?

Issue 44 asks for a full-log MCAP file of at most a tenth of the CSV run directory. tern's MCAP
holds the CSV's values exactly (every double bit for bit: docs/logs.md). This bench takes a
CSV-logged flight's tables (RUN/topics/*.csv), reads every column back as the float64 it was
written from (the CSV writes shortest round-trip numbers, so the doubles are exact), and
compresses the same numbers in layouts that general and float-aware compressors like best:

- rows:        each table's rows as little-endian float64 records (what a CDR message holds),
               all tables one after the other: zstd -19 --long and xz -9;
- columns:     each column contiguous (a columnar store's layout): zstd -19 --long and xz -9;
- shuffled:    each column's bytes transposed (byte 0 of every value, then byte 1, ...: Blosc's
               shuffle filter), then xz -9;
- xor-delta:   each value XORed with the column's previous value (Gorilla's transform for time
               series), then shuffled, then xz -9.

The smallest of these is an estimate from above of what any lossless encoding of these doubles
needs; tern's MCAP (CDR messages, zstd level 1 chunks, message indexes for Foxglove's reader)
can only be larger. Prints a table and writes JSON (default bench/results/log_bound.json).
"""
import argparse
import csv
import glob
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def read_table(path):
    """The table's numbers as float64 columns (a column with a non-number cell is skipped)."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if len(rows) < 2:
        return []
    columns = []
    for j in range(len(rows[0])):
        try:
            columns.append(np.array([float(r[j]) for r in rows[1:]], dtype="<f8"))
        except (ValueError, IndexError):
            continue
    return columns


def compressed_size(data, argv):
    p = subprocess.run(argv, input=data, capture_output=True, check=True)
    return len(p.stdout)


def shuffle(column):
    return column.view(np.uint8).reshape(-1, 8).T.tobytes()


def xor_delta(column):
    bits = column.view("<u8")
    out = bits.copy()
    out[1:] ^= bits[:-1]
    return out.view("<f8")


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("run", help="a run directory flown with the CSV log (its topics/*.csv)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "log_bound.json"))
    args = ap.parse_args()
    paths = sorted(glob.glob(os.path.join(args.run, "topics", "*.csv")))
    if not paths:
        sys.exit(f"bench_log_bound: {args.run}/topics/ has no CSV tables (fly with --log-format csv or both)")
    csv_bytes = sum(os.path.getsize(p) for p in paths)
    tables = [read_table(p) for p in paths]
    values = sum(len(c) for t in tables for c in t)
    rows = b"".join(np.column_stack(t).astype("<f8").tobytes() for t in tables if t)
    columns = [c for t in tables for c in t]
    col = b"".join(c.tobytes() for c in columns)
    shuf = b"".join(shuffle(c) for c in columns)
    xshuf = b"".join(shuffle(xor_delta(c)) for c in columns)
    zstd = ["zstd", "-19", "--long=27", "-T1", "-c", "-q"]
    xz = ["xz", "-9", "-T1", "-c"]
    layouts = {
        "rows, raw": len(rows),
        "rows, zstd -19 --long": compressed_size(rows, zstd),
        "rows, xz -9": compressed_size(rows, xz),
        "columns, zstd -19 --long": compressed_size(col, zstd),
        "columns, xz -9": compressed_size(col, xz),
        "columns shuffled, xz -9": compressed_size(shuf, xz),
        "columns xor-delta shuffled, xz -9": compressed_size(xshuf, xz),
    }
    best = min(v for k, v in layouts.items() if k != "rows, raw")
    mcap = os.path.join(args.run, "flight.mcap")
    result = {
        "run": os.path.basename(os.path.normpath(args.run)),
        "tables": len(paths),
        "values": values,
        "csv_bytes": csv_bytes,
        "target_bytes": csv_bytes // 10,
        "layouts_bytes": layouts,
        "best_bytes": best,
        "best_bits_per_value": 8.0 * best / values,
        "best_vs_csv": best / csv_bytes,
        "mcap_bytes": os.path.getsize(mcap) if os.path.exists(mcap) else None,
    }
    print(f"{len(paths)} tables, {values} values, CSV {csv_bytes / 1e6:.1f} MB, a tenth {csv_bytes / 1e7:.1f} MB")
    for k, v in layouts.items():
        print(f"  {k:38s} {v / 1e6:8.1f} MB  {8.0 * v / values:5.1f} bit/value  {v / csv_bytes:6.3f} of the CSV")
    if result["mcap_bytes"]:
        print(f"  {'flight.mcap (as logged)':38s} {result['mcap_bytes'] / 1e6:8.1f} MB")
    os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(result, f, indent=1)
    print(f"written {args.out}")


if __name__ == "__main__":
    main()
