#!/usr/bin/python3
"""bench_speed.py [--build BUILD] [--repeat N] [--cpu K] [--out JSON]: what the log and a reset cost (issue 80).

Everything pinned to one core (--cpu, default the last), the whole process, median of --repeat
(default 5) runs, interleaved:

1. The default mission (configs/missions/default.yaml, seed 1, to its landing) flown by
   `tern fly -q` at log levels summary, replay (MCAP: what `make fly` writes) and full (MCAP):
   wall time, real-time factor (flight time / wall time), the log writer's CPU time, the run
   directory's bytes; for replay also with `tern-plot`'s figures, as `make fly` leaves it.
2. Resets on learn.yaml: Host.reset(seed) with a new seed each time, after an episode's flight
   (the flight's start: plugins reset, the log's run directory), and FlightEnv.reset() (the same,
   then the 5 s of flight before an episode starts).
3. tern.env.FlightEnv() with its default episodes (10 s after a 5-s start, 100-Hz control),
   environment steps per second with a linear roll policy, resets included; VectorFlightEnv of
   1, 2 and 4 sub-environments the same way (sub-environment steps per second, autoresets).
   2 and 3 are bench_python.py's env_rate and vector_rate (one implementation of each figure;
   bench_python.py adds their parts: the reset split, Host.step(4) alone, runs without resets).
4. The machine's single-thread figure beside them: the same core's zlib level-1 compression and
   SHA-256 throughput on a fixed 64-MB buffer, so that figures from machines of other speeds can
   be compared (the issue's targets were set on a faster machine).

Prints a table, writes JSON (default bench/results/bench_speed.json). Run after `make build` with
Debian's python3: /usr/bin/python3 bench/bench_speed.py.
"""
import argparse
import glob
import hashlib
import json
import os
import platform
import random
import statistics
import subprocess
import sys
import tempfile
import time
import zlib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
LEVELS = (("summary", "mcap"), ("replay", "mcap"), ("full", "mcap"))


def dir_bytes(path):
    return sum(os.path.getsize(os.path.join(d, f)) for d, _, fs in os.walk(path) for f in fs)


def fly(build, level, fmt, out, cpu, plot):
    """One `tern fly` of the default mission pinned to `cpu`: its figures."""
    argv = [str(build / "bin" / "tern"), "fly", str(ROOT / "configs" / "missions" / "default.yaml"), "--log-dir", out, "--log-level",
            level, "--log-format", fmt, "-q"]
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, preexec_fn=lambda: os.sched_setaffinity(0, {cpu}))
    run = glob.glob(os.path.join(out, "*"))[0]
    t = json.load(open(os.path.join(run, "timing.json")))
    s = json.load(open(os.path.join(run, "summary.json")))
    row = {"flight_s": s["duration_s"], "wall_s": t["wall_s"], "real_time_factor": t["real_time_factor"],
           "log_writer_cpu_s": t["log_writer_cpu_s"], "run_dir_bytes": dir_bytes(run)}
    if plot:
        subprocess.run([str(build / "bin" / "tern-plot"), run], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        row["run_dir_with_plots_bytes"] = dir_bytes(run)
    return row


def log_levels(build, repeat, cpu):
    runs = {v: [] for v in LEVELS}
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(repeat):
            for level, fmt in LEVELS:
                runs[(level, fmt)].append(fly(build, level, fmt, os.path.join(tmp, f"{level}-{k}"), cpu, level == "replay" and k == 0))
    rows = []
    for (level, fmt), rs in runs.items():
        row = {"level": level, "format": fmt, "runs": len(rs)}
        for key in ("flight_s", "wall_s", "real_time_factor", "log_writer_cpu_s", "run_dir_bytes"):
            row[key] = statistics.median(r[key] for r in rs)
        row["real_time_factor_all"] = [r["real_time_factor"] for r in rs]
        if "run_dir_with_plots_bytes" in rs[0]:
            row["run_dir_with_plots_bytes"] = rs[0]["run_dir_with_plots_bytes"]
        rows.append(row)
    return rows


def python_figures(repeat):
    """Resets and environment steps, in this process (already pinned), measured by bench_python's
    own functions (one implementation of each figure), `repeat` times: the medians."""
    import bench_python
    envs = [bench_python.env_rate(20000, 10.0) for _ in range(repeat)]
    out = {"host_reset_ms": statistics.median(e["host_reset_s"] for e in envs) * 1e3,
           "flight_env_reset_ms": statistics.median(e["reset_s"] for e in envs) * 1e3,
           "flight_env_steps_per_s": statistics.median(e["steps_per_s_with_resets"] for e in envs),
           "flight_env": "bench_python.env_rate(20000, 10.0): FlightEnv's default episodes (10 s after a 5-s start), resets included",
           "vector_env": []}
    for n in (1, 2, 4):
        vecs = [bench_python.vector_rate(20000, 10.0, n) for _ in range(repeat)]
        out["vector_env"].append({"num_envs": n, "steps_per_s": statistics.median(v["steps_per_s_with_autoresets"] for v in vecs)})
    return out


def machine():
    """Single-thread yardsticks on this core: zlib level 1 and SHA-256 over a fixed 64-MB buffer."""
    rng = random.Random(1)
    block = bytes(rng.getrandbits(8) for _ in range(1 << 16)) + bytes(1 << 16)  # half noise, half zeros
    data = block * (64 * (1 << 20) // len(block))

    def rate(f):
        best = 1e9
        for _ in range(3):
            t0 = time.process_time()
            f(data)
            best = min(best, time.process_time() - t0)
        return len(data) / best / 1e6

    cpu = next((ln.split(":", 1)[1].strip() for ln in open("/proc/cpuinfo") if ln.startswith("model name")), platform.processor())
    return {"cpu_model": cpu, "zlib_level1_MB_per_s": rate(lambda d: zlib.compress(d, 1)),
            "sha256_MB_per_s": rate(lambda d: hashlib.sha256(d).digest())}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)))
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "bench_speed.json"))
    a = ap.parse_args()
    build = Path(a.build).resolve()
    sys.path.insert(0, str(build / "python"))
    sys.path.insert(0, str(ROOT / "bench"))
    os.environ.setdefault("TERN_BUILD_DIR", str(build))
    os.sched_setaffinity(0, {a.cpu})
    m = machine()
    rows = log_levels(build, a.repeat, a.cpu)
    py = python_figures(a.repeat)
    by = {r["level"]: r for r in rows}
    result = {
        "bench": "bench_speed", "issue": 80, "cores": 1, "cpu": a.cpu, "nproc": os.cpu_count(), "repeat": a.repeat, "statistic": "median",
        "machine": m, "log_levels": rows,
        "replay_over_summary_wall": by["replay"]["wall_s"] / by["summary"]["wall_s"],
        "make_fly_run_dir_bytes": by["replay"].get("run_dir_with_plots_bytes"),
        "python": py,
        "targets": {"default_log_real_time_factor": 1000, "default_log_within_summary": 0.10, "full_log_real_time_factor": 700,
                    "make_fly_run_dir_bytes": 40e6, "flight_env_steps_per_s": 50000, "host_reset_ms": 2.0},
        "load_average_1min": os.getloadavg()[0],
        "note": "each figure the median of `repeat` runs pinned to core `cpu` (the whole process on one core: the flight thread and "
                "the log writer share it); real_time_factor = flight time / wall time; machine: the same core's single-thread "
                "throughput, for comparing machines"}
    print(f"machine: {m['cpu_model']}; zlib -1 {m['zlib_level1_MB_per_s']:.0f} MB/s, sha256 {m['sha256_MB_per_s']:.0f} MB/s (one core)")
    print(f"{'level':<8} {'wall s':>7} {'x real time':>11} {'log CPU s':>9} {'run dir MB':>10}")
    for r in rows:
        print(f"{r['level']:<8} {r['wall_s']:>7.3f} {r['real_time_factor']:>11.0f} {r['log_writer_cpu_s']:>9.3f} {r['run_dir_bytes'] / 1e6:>10.2f}")
    print(f"replay / summary wall: {result['replay_over_summary_wall']:.3f}; make fly's run directory: "
          f"{result['make_fly_run_dir_bytes'] / 1e6:.2f} MB")
    print(f"Host.reset {py['host_reset_ms']:.2f} ms, FlightEnv.reset {py['flight_env_reset_ms']:.2f} ms, FlightEnv default episodes "
          f"{py['flight_env_steps_per_s']:.0f} steps/s; VectorFlightEnv " +
          ", ".join(f"{v['num_envs']}: {v['steps_per_s']:.0f}" for v in py["vector_env"]) + " steps/s")
    os.makedirs(os.path.dirname(a.out), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(result, f, indent=2)
        f.write("\n")
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
