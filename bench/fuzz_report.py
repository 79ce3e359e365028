#!/usr/bin/env python3
"""Runs the libFuzzer targets, JOBS at a time, and writes what each did (`make fuzz`, issue 78).

  fuzz_report.py --build build-fuzz --seconds N [--jobs J] [--out bench/results/fuzz.json] TARGET...

Each target runs N seconds (-max_total_time) on its corpus, BUILD/corpus/<target>, seeded from
tests/fuzz/corpus/<target> when the repository has one, with tests/fuzz/dict/<target>.dict when
there is one; at most 2 GB of memory and 10 s per input (a slower input is a hang: libFuzzer's
timeout-* artifact). The targets that read a file (loaders, archives, MCAP) write each input to
TMPDIR first: it is set to a directory of /dev/shm where the machine has one (on disk, those
targets spent most of their time waiting for the file system, not fuzzing). Its output goes to BUILD/fuzz_logs/<target>.log, what it finds to
BUILD/fuzz_artifacts/<target>/ (crash-*, leak-*, timeout-*, oom-*: the input that did it).

Per target, from libFuzzer's final lines (-print_final_stats=1): executions
(stat::number_of_executed_units, else "Done N runs in S second(s)"), execs per second, the units
the run added, peak RSS; and, measured here: the fuzzer process's CPU seconds (user + system, its
rusage), wall seconds, the corpus after the run (files, bytes), and the crashes (artifacts
written, with their kind). Exit status 1 when any target crashed or did not finish cleanly, after
the report is written.
"""
import argparse
import concurrent.futures
import datetime
import json
import os
import re
import shutil
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ARTIFACT_KINDS = ("crash", "leak", "timeout", "oom")


def parse_log(text):
    """libFuzzer's final statistics: executions, execs/s, new units, peak RSS (None if absent)."""
    out = {"executions": None, "execs_per_second": None, "new_units": None, "peak_rss_mb": None, "done_seconds": None}
    for key, name in (("executions", "number_of_executed_units"), ("execs_per_second", "average_exec_per_sec"),
                      ("new_units", "new_units_added"), ("peak_rss_mb", "peak_rss_mb")):
        m = re.findall(r"^stat::%s:\s+(\d+)" % name, text, re.M)
        if m:
            out[key] = int(m[-1])
    done = re.findall(r"^Done (\d+) runs in (\d+) second", text, re.M)
    if done:
        if out["executions"] is None:
            out["executions"] = int(done[-1][0])
        out["done_seconds"] = int(done[-1][1])
    return out


def corpus_size(directory):
    files = [os.path.join(directory, f) for f in os.listdir(directory)] if os.path.isdir(directory) else []
    files = [f for f in files if os.path.isfile(f)]
    return len(files), sum(os.path.getsize(f) for f in files)


def scratch_dir(build):
    """TMPDIR for the targets: memory-backed where the machine has /dev/shm, else BUILD/fuzz_tmp."""
    base = "/dev/shm" if os.access("/dev/shm", os.W_OK) else build
    path = os.path.join(base, f"tern-fuzz-{os.getpid()}")
    os.makedirs(path, exist_ok=True)
    return path


def run_target(build, target, seconds):
    binary = os.path.join(build, "bin", target)
    if not os.path.exists(binary):
        raise SystemExit(f"fuzz_report: {binary} not built (cmake --build {build} --target {target})")
    corpus = os.path.join(build, "corpus", target)
    artifacts = os.path.join(build, "fuzz_artifacts", target)
    logs = os.path.join(build, "fuzz_logs")
    for d in (corpus, artifacts, logs):
        os.makedirs(d, exist_ok=True)
    before = set(os.listdir(artifacts))
    cmd = [binary, f"-max_total_time={seconds}", "-rss_limit_mb=2048", "-timeout=10", "-print_final_stats=1",
           f"-artifact_prefix={artifacts}/"]
    dictionary = os.path.join(ROOT, "tests", "fuzz", "dict", f"{target}.dict")
    if os.path.exists(dictionary):
        cmd.append(f"-dict={dictionary}")
    cmd.append(corpus)
    seeds = os.path.join(ROOT, "tests", "fuzz", "corpus", target)
    if os.path.isdir(seeds):
        cmd.append(seeds)
    log_path = os.path.join(logs, f"{target}.log")
    print(f"fuzz: {target}, {seconds} s", flush=True)
    start = time.monotonic()
    with open(log_path, "w") as log:
        env = dict(os.environ, TMPDIR=scratch_dir(build))
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, cwd=build, env=env)
        _, status, usage = os.wait4(proc.pid, 0)
    wall = time.monotonic() - start
    exit_code = os.waitstatus_to_exitcode(status)
    with open(log_path, errors="replace") as log:
        stats = parse_log(log.read())
    new = sorted(set(os.listdir(artifacts)) - before)
    found = [f for f in new if f.split("-")[0] in ARTIFACT_KINDS]
    files, size = corpus_size(corpus)
    result = {
        "executions": stats["executions"],
        "cpu_seconds": round(usage.ru_utime + usage.ru_stime, 2),
        "wall_seconds": round(wall, 2),
        "execs_per_second": stats["execs_per_second"],
        "corpus_files": files,
        "corpus_bytes": size,
        "new_units": stats["new_units"],
        "peak_rss_mb": stats["peak_rss_mb"],
        "crashes": len(found),
        "artifacts": [os.path.relpath(os.path.join(artifacts, f), ROOT) for f in found],
        "exit_code": exit_code,
        "log": os.path.relpath(log_path, ROOT),
    }
    if stats["executions"] is None:
        result["note"] = "no final statistics in the log: the fuzzer did not finish (see the log)"
    print(f"fuzz: {target}: {result['executions']} runs, {result['cpu_seconds']} CPU s, corpus {files} files, "
          f"{len(found)} crash(es), exit {exit_code}", flush=True)
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True, help="the fuzz build directory (build-fuzz)")
    ap.add_argument("--seconds", type=int, required=True, help="seconds per target")
    ap.add_argument("--jobs", type=int, default=1, help="targets fuzzed at once (each one process, one core)")
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results", "fuzz.json"))
    ap.add_argument("--merge", action="store_true",
                    help="keep the other targets' entries of an existing report (each entry names its own commit and date)")
    ap.add_argument("targets", nargs="+")
    a = ap.parse_args()
    build = os.path.abspath(a.build)
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True, text=True).stdout.strip()
    now = datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds")
    results = {}
    if a.merge and os.path.exists(a.out):
        with open(a.out) as f:
            old = json.load(f)
        for t, r in old.get("targets", {}).items():
            r.setdefault("commit", old.get("commit"))
            r.setdefault("date", old.get("date"))
            r.setdefault("seconds", old.get("seconds_per_target"))
            results[t] = r
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as pool:  # each waits on its own process
        runs = {t: pool.submit(run_target, build, t, a.seconds) for t in a.targets}
        for t in a.targets:
            results[t] = dict(runs[t].result(), commit=commit, date=now, seconds=a.seconds)
    shutil.rmtree(scratch_dir(build), ignore_errors=True)
    clang = subprocess.run(["clang++", "--version"], capture_output=True, text=True).stdout.splitlines()
    report = {
        "date": now,
        "commit": commit,
        "compiler": clang[0] if clang else None,
        "cpus": os.cpu_count(),
        "jobs": a.jobs,
        "seconds_per_target": a.seconds,
        "flags": "-fsanitize=fuzzer,address,undefined; -rss_limit_mb=2048 -timeout=10",
        "targets": results,
        "total": {"executions": sum(r["executions"] or 0 for r in results.values()),
                  "cpu_seconds": round(sum(r["cpu_seconds"] for r in results.values()), 2),
                  "crashes": sum(r["crashes"] for r in results.values())},
    }
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(report, f, indent=2)
        f.write("\n")
    print(f"fuzz: wrote {a.out}")
    bad = [t for t in a.targets if results[t]["crashes"] or results[t]["exit_code"] != 0]
    if bad:
        print(f"fuzz: found something in {', '.join(bad)} ({a.out}, the artifacts above)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
