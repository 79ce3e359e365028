#!/usr/bin/python3
"""bench_realtime_load.py [TERN_BIN_DIR] [--duration S] [--settings other,fifo] [--loads none,stress] [--out JSON]:
the real-time load test of issue 41, item 3.

Flies the default mission paced to wall time (`tern fly configs/missions/default.yaml --realtime
--duration S`, 600 s by default: 240000 ticks at 400 Hz) once per (load, settings) pair and reads
each flight's summary.json "realtime" (core/host/graph/realtime.hpp): deadline misses, wake-up
latency and work per tick (p50, p99, max), the flight thread's page faults.

Settings:
  other  SCHED_OTHER, any CPU, memory not locked (no option);
  fifo   --rt-priority 80 --cpu 1 --mlockall (SCHED_FIFO 80, the flight thread on CPU 1, every page
         locked). Refused by the system (not root, no rtprio/memlock): reported as refused with
         tern's one line, not flown another way.
Loads:
  none   nothing started by the bench (what else runs on the machine is recorded: the load average
         and the whole machine's CPU busy share during the flight, from /proc/stat);
  stress one CPU hog per core (--hogs; a `python3` busy loop each, nice 0: as hungry as the flight's
         own process) and a big file write (--write-gb; 0: none): `dd if=/dev/zero of=TMP bs=1M count=GB*1024 conv=fsync`
         (default 4 GB, in the directory of --write-dir, default the system's temporary
         directory), deleted and written again until the flight ends; dirty pages pile up and
         the kernel writes them back under the flight. The hogs and dd start 2 s before the
         flight and are stopped (SIGTERM, then SIGKILL) when it ends; the file is removed.

Prints a table and writes JSON (default bench/results/realtime_load.json) with every flight's
"realtime" object, the load achieved (hogs, GB written, dd passes) and the machine.
Targets (issue 41): unloaded, 0 deadline misses and a wake-up p99 <= 200 us; loaded with
SCHED_FIFO, misses <= 0.1 %.
"""
import argparse
import glob
import json
import os
import platform
import shutil
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
SETTINGS = {
    "other": [],
    "fifo": ["--rt-priority", "80", "--cpu", "1", "--mlockall"],
}
LOADS = ("none", "stress")
TARGET_MISS_SHARE_LOADED = 0.001  # 0.1 %
TARGET_WAKE_P99_US = 200.0


def fail(msg):
    sys.exit(f"bench_realtime_load: {msg}")


def cpu_times():
    """(busy, steal, total) jiffies of the whole machine (/proc/stat's cpu line: user nice system
    idle iowait irq softirq steal; guest time is inside user). Steal: time the hypervisor ran
    something else while this virtual machine's CPU wanted to run."""
    with open("/proc/stat") as f:
        v = ([int(x) for x in f.readline().split()[1:]] + [0] * 8)[:8]
    return sum(v) - v[3] - v[4], v[7], sum(v)


class Stress:
    """One busy-loop process per core and a repeated big file write, until stop()."""

    def __init__(self, hogs, write_gb, write_dir):
        self.hogs, self.write_gb, self.write_dir = hogs, write_gb, write_dir
        self.procs, self.writer = [], None

    def start(self):
        for _ in range(self.hogs):
            self.procs.append(subprocess.Popen([sys.executable, "-c", "while True: pass"]))
        if self.write_gb > 0:
            self.file = os.path.join(self.write_dir, f"bench_realtime_load-{os.getpid()}.dat")
            count = int(self.write_gb * 1024)
            # the shell loop: write, fsync, delete, again; each pass's end is one line on stdout
            loop = (f'trap "rm -f \'{self.file}\'; exit 0" TERM; '
                    f'while :; do dd if=/dev/zero of=\'{self.file}\' bs=1M count={count} conv=fsync status=none & '
                    f'wait $! || exit 1; rm -f \'{self.file}\'; echo pass; done')
            self.writer = subprocess.Popen(["sh", "-c", loop], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                           start_new_session=True)
        time.sleep(2.0)
        for p in self.procs + ([self.writer] if self.writer else []):
            if p.poll() is not None:
                self.stop()
                fail(f"the stress process {p.args} ended at once (exit {p.returncode})")

    def stop(self):
        """Stops everything; returns what was achieved."""
        for p in self.procs:
            p.terminate()
        passes, partial_gb = 0, 0.0
        if self.writer:
            try:
                partial_gb = os.path.getsize(self.file) / 2**30
            except OSError:
                pass
            os.killpg(self.writer.pid, signal.SIGTERM)
            try:
                out, err = self.writer.communicate(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(self.writer.pid, signal.SIGKILL)
                out, err = self.writer.communicate()
            passes = out.split().count("pass")
            errors = [line for line in err.splitlines() if line.strip() and "Terminated" not in line]
            if errors:
                print(f"\nbench_realtime_load: the file write said: {errors[-1]}", file=sys.stderr)
            if os.path.exists(self.file):
                os.remove(self.file)
        for p in self.procs:
            try:
                p.wait(timeout=5)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        return {"cpu_hogs": self.hogs, "write_gb_per_pass": self.write_gb, "write_passes_completed": passes,
                "written_gb": passes * self.write_gb + partial_gb}


def fly(tern, mission, duration, settings, log_dir):
    """One paced flight: (run dir or None, the error line of a refused flight or None, wall s)."""
    os.makedirs(log_dir, exist_ok=True)
    argv = [tern, "fly", mission, "--realtime", "--duration", str(duration), "-q", "--log-dir", log_dir] + SETTINGS[settings]
    t0 = time.monotonic()
    p = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.monotonic() - t0
    with open(os.path.join(log_dir, "fly.log"), "w") as f:
        f.write(p.stdout)
    if p.returncode != 0:
        errors = [line for line in p.stdout.splitlines() if "error" in line]
        return None, (errors[-1] if errors else f"exit {p.returncode}"), wall
    runs = glob.glob(os.path.join(log_dir, "*", "summary.json"))
    if len(runs) != 1:
        fail(f"expected one run directory in {log_dir}, found {len(runs)}")
    return os.path.dirname(runs[0]), None, wall


def one(tern, mission, duration, settings, load, args, work):
    print(f"  {settings:5} load {load:6} ({duration:g} s) ...", end="", flush=True)
    stress = Stress(args.hogs, args.write_gb, args.write_dir) if load == "stress" else None
    if stress:
        stress.start()
    load0, (busy0, steal0, total0) = os.getloadavg(), cpu_times()
    try:
        run, refused, wall = fly(tern, mission, duration, settings, os.path.join(work, f"{settings}-{load}"))
    finally:
        achieved = stress.stop() if stress else None
    busy1, steal1, total1 = cpu_times()
    out = {"settings": settings, "options": SETTINGS[settings], "load": load, "duration_s": duration, "wall_s": wall,
           "load_average_before": load0, "load_average_after": os.getloadavg(),
           "machine_cpu_busy_share": (busy1 - busy0) / max(1, total1 - total0),
           "machine_cpu_steal_share": (steal1 - steal0) / max(1, total1 - total0), "stress": achieved}
    if refused:
        out["refused"] = refused
        print(f" refused: {refused}")
        return out
    with open(os.path.join(run, "summary.json")) as f:
        s = json.load(f)
    if "realtime" not in s:
        fail(f"{run}/summary.json has no \"realtime\" (a paced flight always has it)")
    if s["end_reason"] != "duration":
        fail(f"{run}: the flight ended early ({s['end_reason']} at {s['duration_s']} s)")
    out["realtime"] = s["realtime"]
    rt = s["realtime"]
    print(f" {rt['deadline_misses']} misses, wake-up p99 {rt['wake_up_latency']['p99_us']:.0f} us"
          + (f", {achieved['written_gb']:.1f} GB written" if achieved else ""))
    return out


def print_table(rows):
    print(f"\n{'settings':42}{'load':8}{'ticks':>8}{'misses':>8}{'%':>8}  {'wake-up p50/p99/max us':>24}  "
          f"{'work p50/p99/max us':>22}  {'faults min/maj':>14}  {'busy':>5} {'steal':>5}")
    for r in rows:
        if "refused" in r:
            print(f"{' '.join(r['options']) or 'SCHED_OTHER':42}{r['load']:8}  refused: {r['refused']}")
            continue
        rt = r["realtime"]
        w, k = rt["wake_up_latency"], rt["work_per_tick"]
        print(f"{rt['scheduling']:42}{r['load']:8}{rt['ticks']:8d}{rt['deadline_misses']:8d}{100 * rt['deadline_miss_share']:8.3f}  "
              f"{w['p50_us']:>6.0f} /{w['p99_us']:>6.0f} /{w['max_us']:>7.0f}    {k['p50_us']:>5.0f} /{k['p99_us']:>5.0f} /{k['max_us']:>7.0f}  "
              f"{rt['page_faults_minor']:>7d} /{rt['page_faults_major']:>3d}  {100 * r['machine_cpu_busy_share']:4.0f}% "
              f"{100 * r['machine_cpu_steal_share']:4.1f}%")
    print(f"busy, steal: the whole machine's CPU busy share during the flight and the share the hypervisor took (/proc/stat). Targets: unloaded 0 misses and wake-up "
          f"p99 <= {TARGET_WAKE_P99_US:.0f} us; loaded with SCHED_FIFO <= {100 * TARGET_MISS_SHARE_LOADED:.1f} % misses")


def machine():
    model = ""
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    return {"cpu": model, "cores": os.cpu_count(), "kernel": platform.release(), "kernel_version": platform.version(),
            "preempt_rt": os.path.exists("/sys/kernel/realtime"), "euid": os.geteuid()}


def git_commit():
    head = subprocess.run(["git", "-C", REPO, "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", REPO, "status", "--porcelain", "--untracked-files=no"], capture_output=True,
                           text=True).stdout.strip()
    return {"commit": head, "tracked_files_modified": bool(dirty)}


def comma_list(value, option, allowed, error=None):
    """'a,b' -> ['a', 'b'], each one of `allowed`; else one error line naming the option, through
    `error` (the calling bench's own fail; default this one's)."""
    error = error or fail
    items = [s.strip() for s in value.split(",") if s.strip()]
    for s in items:
        if s not in allowed:
            error(f"{option}: '{s}' is not one of {', '.join(allowed)}")
    return items


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bin_dir", nargs="?", default=os.path.join(REPO, "build", "bin"), help="directory of tern (default build/bin)")
    ap.add_argument("--mission", default=os.path.join(REPO, "configs", "missions", "default.yaml"))
    ap.add_argument("--duration", type=float, default=600.0, help="s of each flight (default 600: the issue's target)")
    ap.add_argument("--settings", default="other,fifo", help="comma-separated: other, fifo")
    ap.add_argument("--loads", default="none,stress", help="comma-separated: none, stress")
    ap.add_argument("--hogs", type=int, default=os.cpu_count(), help="CPU hogs of the stress (default: one per core)")
    ap.add_argument("--write-gb", type=float, default=4.0, help="GB per pass of the file write (0: no file write)")
    ap.add_argument("--write-dir", default=tempfile.gettempdir(), help="where the big file is written")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "realtime_load.json"))
    ap.add_argument("--keep", help="fly into this directory and keep it (default: a temporary one, removed)")
    a = ap.parse_args()
    a.settings = comma_list(a.settings, "--settings", SETTINGS)
    a.loads = comma_list(a.loads, "--loads", LOADS)
    if not a.settings or not a.loads:
        fail("--settings and --loads each need at least one entry")
    if not a.duration > 0:
        fail(f"--duration: {a.duration:g}: must be > 0 s")
    if not 0 <= a.hogs <= 256:
        fail(f"--hogs: {a.hogs}: must be 0..256")
    if a.write_gb < 0:
        fail(f"--write-gb: {a.write_gb:g}: must be >= 0")
    if not os.path.isdir(a.write_dir):
        fail(f"--write-dir: {a.write_dir}: not a directory")
    if not os.path.isfile(a.mission):
        fail(f"--mission: {a.mission}: no such file")
    a.tern = os.path.join(a.bin_dir, "tern")
    if not os.access(a.tern, os.X_OK):
        fail(f"{a.tern}: no tern executable there (build it: cmake --build build --target tern_fly)")
    if "stress" in a.loads and a.write_gb > 0 and shutil.disk_usage(a.write_dir).free < (a.write_gb + 1) * 2**30:
        fail(f"--write-dir {a.write_dir}: less than {a.write_gb + 1:g} GB free for the {a.write_gb:g}-GB file write")
    return a


def main():
    a = parse_args()
    commit = git_commit()
    work = a.keep or tempfile.mkdtemp(prefix="bench_realtime_load-")
    os.makedirs(work, exist_ok=True)
    print(f"real-time load test: {os.path.relpath(a.mission, REPO)}, {a.duration:g}-s paced flights; flights in {work}")
    rows = []
    try:
        for load in a.loads:
            for settings in a.settings:
                rows.append(one(a.tern, a.mission, a.duration, settings, load, a, work))
    finally:
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    print_table(rows)
    result = {"bench": "realtime_load", "mission": os.path.relpath(a.mission, REPO), "duration_s": a.duration,
              "stress": {"cpu_hogs": f"{a.hogs} x python3 busy loop (nice 0; {os.cpu_count()} cores)",
                         "file_write": f"dd if=/dev/zero bs=1M count={int(a.write_gb * 1024)} conv=fsync to {a.write_dir}, "
                                       "removed and repeated until the flight ends" if a.write_gb > 0 else "none"},
              "machine": machine(), "git": commit, "time": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()), "flights": rows}
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
