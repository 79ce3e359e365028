#!/usr/bin/env python3
"""Compare two flights of the same config and seed flown by different builds (an x86-64 and an
arm64 one under qemu-user: `make arm64-test`, docs/companion-computer.md "Building for arm64").

    compare_arch.py REFERENCE_RUN OTHER_RUN [--max-position-rms M]

Prints
  - the flight's events: end reason, preflight time, every phase change (name and time);
  - the RMS and largest difference, OTHER minus REFERENCE at the same stamp, of the true state
    (truth.csv), the estimate (state.csv) and the actuator commands (actuators.csv);
  - summary.json's numbers: how many are bit-identical, and the largest relative differences.

Exit status 1 when the flights are not the same flight: a different end, a different phase
sequence, a phase change more than one base tick apart, different stamps in a table, a
non-finite difference, or (with --max-position-rms) a true-position RMS difference above M metres.
Only the Python 3 standard library (Debian's python3).
"""

import argparse
import csv
import json
import math
import os
import sys

# (table, column, unit shown, scale from the file's unit, is an angle in radians)
STATE_COLUMNS = [
    ("p_n", "m", 1.0, False),
    ("p_e", "m", 1.0, False),
    ("p_d", "m", 1.0, False),
    ("u", "m/s", 1.0, False),
    ("v", "m/s", 1.0, False),
    ("w", "m/s", 1.0, False),
    ("phi", "deg", math.degrees(1.0), True),
    ("theta", "deg", math.degrees(1.0), True),
    ("psi", "deg", math.degrees(1.0), True),
    ("p", "deg/s", math.degrees(1.0), False),
    ("q", "deg/s", math.degrees(1.0), False),
    ("r", "deg/s", math.degrees(1.0), False),
    ("Va", "m/s", 1.0, False),
    ("chi", "deg", math.degrees(1.0), True),
    ("w_n", "m/s", 1.0, False),
    ("w_e", "m/s", 1.0, False),
]
ACTUATOR_COLUMNS = [
    ("delta_a", "deg", math.degrees(1.0), False),
    ("delta_e", "deg", math.degrees(1.0), False),
    ("delta_r", "deg", math.degrees(1.0), False),
    ("delta_t", "", 1.0, False),
]
# summary.json leaves that name the build, not the flight
BUILD_KEYS = {"library", "library_fnv1a"}


def read_table(path):
    """A topic table: {column name without unit: [float]}, and the stamps in ns."""
    with open(path, newline="") as f:
        rows = csv.reader(f)
        header = [h.split(" [")[0] for h in next(rows)]
        cols = {h: [] for h in header}
        for row in rows:
            for h, v in zip(header, row):
                cols[h].append(v)
    stamps = [int(s) for s in cols["stamp"]]
    return stamps, cols


def wrap_pi(a):
    return (a + math.pi) % (2.0 * math.pi) - math.pi


def compare_table(name, ref_dir, oth_dir, columns, problems):
    ref_stamps, ref = read_table(os.path.join(ref_dir, "topics", name + ".csv"))
    oth_stamps, oth = read_table(os.path.join(oth_dir, "topics", name + ".csv"))
    if ref_stamps != oth_stamps:
        problems.append(f"{name}.csv: different stamps ({len(ref_stamps)} rows vs {len(oth_stamps)})")
        n = min(len(ref_stamps), len(oth_stamps))
    else:
        n = len(ref_stamps)
    out = []
    for col, unit, scale, angle in columns:
        sq = 0.0
        worst = 0.0
        worst_t = 0.0
        identical = 0
        for i in range(n):
            a, b = float(ref[col][i]), float(oth[col][i])
            if ref[col][i] == oth[col][i]:
                identical += 1
            d = b - a
            if angle:
                d = wrap_pi(d)
            d *= scale
            if not math.isfinite(d):
                problems.append(f"{name}.csv {col}: non-finite difference at t={ref_stamps[i] * 1e-9:.3f} s")
                break
            sq += d * d
            if abs(d) > worst:
                worst, worst_t = abs(d), ref_stamps[i] * 1e-9
        rms = math.sqrt(sq / n) if n else float("nan")
        out.append((col, unit, rms, worst, worst_t, identical, n))
    return out


def numeric_leaves(node, path=""):
    if isinstance(node, dict):
        for k, v in node.items():
            if k in BUILD_KEYS:
                continue
            yield from numeric_leaves(v, f"{path}.{k}" if path else k)
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield from numeric_leaves(v, f"{path}[{i}]")
    elif isinstance(node, bool) or node is None or isinstance(node, str):
        yield path, node
    elif isinstance(node, (int, float)):
        yield path, float(node)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("reference", help="run directory of the reference flight (x86-64)")
    ap.add_argument("other", help="run directory of the same flight on the other build (arm64)")
    ap.add_argument("--labels", default="x86-64,arm64", help="names of the two builds (default: x86-64,arm64)")
    ap.add_argument("--max-position-rms", type=float, default=None,
                    help="fail when the true position's RMS difference (any axis) exceeds this (m)")
    ap.add_argument("--json", help="also write the figures to this JSON file")
    args = ap.parse_args()
    ref_label, oth_label = args.labels.split(",")
    problems = []

    ref_sum = json.load(open(os.path.join(args.reference, "summary.json")))
    oth_sum = json.load(open(os.path.join(args.other, "summary.json")))
    base_tick = 1.0 / ref_sum.get("base_rate_hz", 400.0)

    print(f"{ref_label}: {args.reference}")
    print(f"{oth_label}: {args.other}")
    for key in ("mission", "seed", "duration_s"):
        if ref_sum.get(key) != oth_sum.get(key):
            problems.append(f"summary.json {key}: {ref_sum.get(key)} vs {oth_sum.get(key)} (not the same flight)")
    print(f"mission {ref_sum.get('mission')}, seed {ref_sum.get('seed')}, {ref_sum.get('duration_s')} s")

    # events
    print("\nevents                         %-14s %-14s" % (ref_label, oth_label))
    print("  end reason                   %-14s %-14s" % (ref_sum.get("end_reason"), oth_sum.get("end_reason")))
    if ref_sum.get("end_reason") != oth_sum.get("end_reason"):
        problems.append("different end reason")
    print("  preflight (s)                %-14s %-14s" % (ref_sum.get("preflight_s"), oth_sum.get("preflight_s")))
    ref_ph, oth_ph = ref_sum.get("phases", []), oth_sum.get("phases", [])
    if [p["phase"] for p in ref_ph] != [p["phase"] for p in oth_ph]:
        problems.append("different phase sequence: %s vs %s" % ([p["phase"] for p in ref_ph], [p["phase"] for p in oth_ph]))
    for a, b in zip(ref_ph, oth_ph):
        print("  %-28s %-14.4f %-14.4f" % (a["phase"] + " at (s)", a["start_s"], b["start_s"]))
        if abs(a["start_s"] - b["start_s"]) > base_tick * 1.0001:
            problems.append(f"phase {a['phase']} starts {b['start_s'] - a['start_s']:+.4f} s apart")

    # tables
    figures = {}
    for table, columns, title in (("truth", STATE_COLUMNS, "true state (truth.csv)"),
                                  ("state", STATE_COLUMNS, "estimate (state.csv)"),
                                  ("actuators", ACTUATOR_COLUMNS, "actuator commands (actuators.csv)")):
        rows = compare_table(table, args.reference, args.other, columns, problems)
        n = rows[0][6] if rows else 0
        print(f"\n{title}, {oth_label} - {ref_label} over {n} samples")
        print("  %-8s %-6s %12s %12s %10s %s" % ("", "unit", "RMS diff", "max |diff|", "at t (s)", "bit-identical"))
        for col, unit, rms, worst, worst_t, identical, n in rows:
            print("  %-8s %-6s %12.3e %12.3e %10.3f %d/%d" % (col, unit, rms, worst, worst_t, identical, n))
        figures[table] = {col: {"unit": unit, "rms": rms, "max": worst, "max_at_s": worst_t,
                                "identical": identical, "samples": n}
                          for col, unit, rms, worst, worst_t, identical, n in rows}

    # summary.json
    ref_leaves = dict(numeric_leaves(ref_sum))
    oth_leaves = dict(numeric_leaves(oth_sum))
    same = 0
    numeric = 0
    diffs = []
    only = sorted(set(ref_leaves) ^ set(oth_leaves))
    for k in sorted(set(ref_leaves) & set(oth_leaves)):
        a, b = ref_leaves[k], oth_leaves[k]
        if isinstance(a, float) and isinstance(b, float):
            numeric += 1
            if a == b or (math.isnan(a) and math.isnan(b)):
                same += 1
            else:
                rel = abs(b - a) / max(abs(a), abs(b), 1e-300)
                diffs.append((rel, k, a, b))
        elif a != b:
            diffs.append((float("inf"), k, a, b))
    diffs.sort(reverse=True)
    print(f"\nsummary.json: {same} of {numeric} numbers bit-identical, {len(diffs)} fields differ"
          + (f", {len(only)} fields in one file only: {', '.join(only[:5])}" if only else ""))
    for rel, k, a, b in diffs[:15]:
        if math.isinf(rel):
            print(f"  {k}: {a!r} vs {b!r}")
        else:
            print(f"  {k}: {a:.9g} vs {b:.9g} (relative {rel:.1e})")
    if len(diffs) > 15:
        print(f"  ... and {len(diffs) - 15} more")

    if args.max_position_rms is not None:
        for col in ("p_n", "p_e", "p_d"):
            if figures["truth"][col]["rms"] > args.max_position_rms:
                problems.append(f"true {col} RMS difference {figures['truth'][col]['rms']:.3e} m > {args.max_position_rms} m")
    if args.json:
        with open(args.json, "w") as f:
            json.dump({"reference": args.reference, "other": args.other, "labels": [ref_label, oth_label],
                       "tables": figures, "summary_numbers": numeric, "summary_identical": same,
                       "summary_differences": [{"field": k, "reference": a, "other": b} for _, k, a, b in diffs],
                       "problems": problems}, f, indent=1)
    if problems:
        print("\nNOT THE SAME FLIGHT:")
        for p in problems:
            print("  " + p)
        return 1
    print(f"\nsame flight: same events and stamps; differences above are {oth_label} - {ref_label}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
