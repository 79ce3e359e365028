#!/usr/bin/python3
"""bench_log_levels.py BIN_DIR [MISSION] [--seconds S] [--repeat N] [--cpu K] [--out JSON]: what a flight's log level costs.

Flies MISSION (default: configs/missions/default.yaml, its full duration unless --seconds) N
times (default 3, interleaved) at each log level (summary, decimated, replay, sysid, full; core/host/config/config.hpp)
in CSV and in MCAP (docs/logs.md), each flight pinned to one core (--cpu, default the last), and reads each
flight's timing.json (core/host/record/flight_report.hpp): wall time, real-time factor (flight time /
wall time), the flight thread's and the log writer's CPU time, and the run directory's size.
Reports each level's best run (least wall time: the least disturbed by other processes) and
the median real-time factors. Prints a table and writes JSON (default
bench/results/log_levels.json). The machine and its load vary: compare the levels with each
other (ratios), not with another machine; the flight thread's CPU-time factor is the least
sensitive to other load.
"""
import argparse
import glob
import json
import os
import statistics
import subprocess
import sys
import tempfile


def dir_bytes(path):
    return sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(path) for f in fs)


# (log level, log format): the levels in CSV, the default (replay) and the full log in MCAP too
# (docs/logs.md); `make fly` writes replay in MCAP
VARIANTS = (("summary", "csv"), ("decimated", "csv"), ("replay", "csv"), ("replay", "mcap"), ("sysid", "mcap"), ("full", "csv"),
            ("full", "mcap"))


def fly(tern, mission, variant, seconds, tmp, k, cpu):
    level, fmt = variant
    out = os.path.join(tmp, f"{level}-{fmt}-{k}")
    argv = [tern, "fly", mission, "--log-dir", out, "--log-level", level, "--log-format", fmt, "-q"]
    if seconds:
        argv += ["--duration", str(seconds)]
    # pinned: the flight thread, the log writer and everything else of the process share one core
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, preexec_fn=lambda: os.sched_setaffinity(0, {cpu}))
    run = glob.glob(os.path.join(out, "*"))[0]
    with open(os.path.join(run, "timing.json")) as f:
        t = json.load(f)
    with open(os.path.join(run, "summary.json")) as f:
        s = json.load(f)
    return {"level": level, "format": fmt, "flight_s": s["duration_s"], "wall_s": t["wall_s"], "real_time_factor": t["real_time_factor"],
            "flight_thread_cpu_s": t["flight_thread_cpu_s"], "flight_thread_real_time_factor": t["flight_thread_real_time_factor"],
            "log_writer_cpu_s": t["log_writer_cpu_s"], "start_to_first_tick_ms": t["start_to_first_tick_ms"],
            "run_dir_bytes": dir_bytes(run)}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bin_dir")
    ap.add_argument("mission", nargs="?", default=os.path.join(here, "..", "configs", "missions", "default.yaml"))
    ap.add_argument("--seconds", type=float, default=0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)), help="the core every flight is pinned to")
    ap.add_argument("--out", default=os.path.join(here, "results", "log_levels.json"))
    a = ap.parse_args()
    tern = os.path.join(a.bin_dir, "tern")
    runs = {v: [] for v in VARIANTS}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(a.repeat):
            for v in VARIANTS:
                runs[v].append(fly(tern, a.mission, v, a.seconds, tmp, k, a.cpu))
    rows = []
    for v in VARIANTS:
        best = dict(min(runs[v], key=lambda r: r["wall_s"]))
        best["runs"] = len(runs[v])
        best["median_real_time_factor"] = statistics.median(r["real_time_factor"] for r in runs[v])
        best["median_flight_thread_real_time_factor"] = statistics.median(r["flight_thread_real_time_factor"] for r in runs[v])
        rows.append(best)
    print(f"{'level':<10} {'format':<6} {'flight s':>8} {'wall s':>7} {'x real time':>11} {'flight thread x':>15} {'log CPU s':>9} "
          f"{'log MB':>7}")
    for r in rows:
        print(f"{r['level']:<10} {r['format']:<6} {r['flight_s']:>8.0f} {r['wall_s']:>7.2f} {r['real_time_factor']:>11.0f} "
              f"{r['flight_thread_real_time_factor']:>15.0f} {r['log_writer_cpu_s']:>9.2f} {r['run_dir_bytes'] / 1e6:>7.2f}")
    full_csv, full_mcap = rows[2], rows[3]
    result = {"mission": os.path.relpath(a.mission, os.path.join(here, "..")), "cores": 1, "cpu": a.cpu, "nproc": os.cpu_count(),
              "levels": rows, "summary_speedup_vs_full": full_csv["wall_s"] / rows[0]["wall_s"],
              "mcap_vs_csv_full": {"size": full_mcap["run_dir_bytes"] / full_csv["run_dir_bytes"],
                                   "writer_cpu": full_mcap["log_writer_cpu_s"] / full_csv["log_writer_cpu_s"]},
              "load_average_1min": os.getloadavg()[0],
              "note": "best of `runs` flights per variant (least wall time), each pinned to core `cpu`, on a shared 2-core machine; "
                      "real_time_factor = flight time / wall time of fly() (the whole process: flight thread and log writer on the "
                      "one core); flight_thread_real_time_factor = flight time / CPU time of the flight thread"}
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
