#!/usr/bin/python3
"""tern campaign, end to end (issue 21), on tests/campaign/short.yaml (6 flights of 20 s):

  - log levels: summary writes no topic tables, decimated caps the topics' rates
  - bad campaign input is one clear error line naming the file, the field and the value
  - flight k is the same whatever the worker count (1 vs 2): the same results.csv
  - an interrupted campaign resumes: finished flights are not re-flown, the table is the same
  - a flight re-flown alone from its recorded command gives the same summary.json
  - the Slurm script runs the same commands
  - Dask with a real local scheduler and two workers on 127.0.0.1 gives the same table
    (skipped, saying so, when Debian's python3-distributed is not installed)

Usage: test_campaign.py BIN_DIR SOURCE_DIR (ctest passes them).
"""
import glob
import json
import os
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time

BIN, SRC = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
TERN = os.path.join(BIN, "tern")
CAMPAIGN = os.path.join(SRC, "tests", "campaign", "short.yaml")
failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what, flush=True)
    if not cond:
        failures.append(what)


def campaign(out, *args, **kw):
    return subprocess.run([TERN, "campaign", CAMPAIGN, "--out", out, "--no-plots", *args], capture_output=True, text=True, **kw)


def table(out):
    """results.csv with the output directory written as OUT (the commands name it)."""
    with open(os.path.join(out, "results.csv")) as f:
        return f.read().replace(out, "OUT")


def throughput(out, what):
    """Prints the run's throughput.json (information, not a check: the machine's load varies)."""
    import json
    with open(os.path.join(out, "throughput.json")) as f:
        t = json.load(f)
    print(f"info {what}: {t['flights_flown']} flights in {t['wall_s']:.1f} s on {t['workers']} worker(s), "
          f"{t['flights_per_core_minute']:.1f} flights per core-minute, {t['mean_flight_real_time_factor']:.0f}x real time per flight, overhead {100 * t['overhead_fraction']:.0f} %")


def summaries(out):
    """The flights' finished summaries (a flight the interrupt stopped says so in end_reason and is
    flown again on resume, as tern campaign decides)."""
    found = []
    for path in sorted(glob.glob(os.path.join(out, "flights", "*", "run", "*", "summary.json"))):
        try:
            with open(path) as f:
                end = json.load(f).get("end_reason", "")
        except (OSError, ValueError):
            continue
        if end not in ("SIGINT", "SIGTERM", "SIGHUP"):
            found.append(path)
    return found


def bad_input(tmp):
    cases = {
        "dispersions.sim.wind.speed": ("sim.wind: {dist: polar, speed: [0, 80]}", "80"),
        "dispersions.sim.wnd": ("sim.wnd: {dist: uniform, low: 0, high: 1}", "sim.wnd"),
        "dispersions.slc.roll_kp.high": ("slc.roll_kp: {dist: uniform, low: 0, high: 1000}", "1000"),
        "dispersions.sim.turbulence.values[1]": ("sim.turbulence: {dist: choice, values: [light, stormy]}", "stormy"),
        "dispersions.aircraft.aero.C_Q_9": ("aircraft.aero.C_Q_9: {dist: uniform, low: -0.1, high: 0.1}", "C_Q_9"),
        "dispersions.slc.roll_kp.relative": ("slc.roll_kp: {dist: uniform, low: -0.1, high: 0.1, relative: maybe}", "maybe"),
    }
    for field, (line, value) in cases.items():
        path = os.path.join(tmp, "bad.yaml")
        with open(path, "w") as f:
            f.write(f"base: {os.path.join(SRC, 'configs', 'missions', 'default.yaml')}\nflights: 2\ndispersions:\n  {line}\n")
        r = subprocess.run([TERN, "campaign", path, "--out", os.path.join(tmp, "bad")], capture_output=True, text=True)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 1 and len(lines) == 1 and "bad.yaml" in lines[0] and field in lines[0] and value in lines[0],
              f"bad input {field} is one line naming file, field and value: {r.stderr.strip()!r}")
    # files that are no campaign file: a link to /dev/zero (read without bound before), a directory
    zero = os.path.join(tmp, "zero.yaml")
    os.symlink("/dev/zero", zero)
    for path, text in ((zero, "campaign file is not a regular file (a character device)"), (tmp, "campaign file is a directory")):
        r = subprocess.run([TERN, "campaign", path, "--out", os.path.join(tmp, "bad")], capture_output=True, text=True, timeout=60)
        lines = r.stderr.strip().splitlines()
        check(r.returncode == 1 and len(lines) == 1 and path in lines[0] and text in lines[0], f"{path}: one line: {r.stderr.strip()!r}")


def resume(tmp, reference):
    out = os.path.join(tmp, "resumed")
    p = subprocess.Popen([TERN, "campaign", CAMPAIGN, "--out", out, "--no-plots", "--workers", "1"], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    # a 20-s flight takes some 30 ms here: poll often enough that the interrupt lands before the last one ends
    while len(summaries(out)) < 2 and time.time() < deadline and p.poll() is None:
        time.sleep(0.002)
    p.send_signal(signal.SIGINT)
    p.communicate(timeout=60)
    done = {s: os.stat(s).st_mtime_ns for s in summaries(out)}
    check(p.returncode == 130 and 2 <= len(done) < 6, f"interrupted campaign exits 130 with {len(done)} of 6 flights flown")
    r = campaign(out, "--workers", "2")
    check(r.returncode == 0 and f"{6 - len(done)} to fly" in r.stderr, f"resumed campaign flies only the {6 - len(done)} left")
    check(all(os.path.exists(s) and os.stat(s).st_mtime_ns == t for s, t in done.items()), "flights finished before the interrupt are not re-flown")
    check(table(out) == reference, "resumed table equals the uninterrupted one")


def refly(tmp, out):
    with open(os.path.join(out, "results.csv")) as f:
        header, *rows = [line for line in f.read().splitlines()]
    row3 = rows[3].split(",")
    command = row3[header.split(",").index("command")]
    argv = shlex.split(command)
    argv[argv.index("--log-dir") + 1] = os.path.join(tmp, "refly")
    subprocess.run(argv, check=True, capture_output=True)
    again = glob.glob(os.path.join(tmp, "refly", "*", "summary.json"))
    original = glob.glob(os.path.join(out, "flights", "00003", "run", "*", "summary.json"))
    check(len(again) == 1 and len(original) == 1 and open(again[0]).read() == open(original[0]).read(),
          "flight 3 re-flown alone from its recorded command gives the same summary.json")


def slurm(tmp, out):
    s = os.path.join(tmp, "slurm")
    r = campaign(s, "--slurm")
    with open(os.path.join(s, "commands.txt")) as f:
        commands = f.read().replace(s, "OUT").splitlines()
    ref = [row.split(",")[4] for row in table(out).splitlines()[1:]]
    check(r.returncode == 0 and commands == ref and subprocess.run(["bash", "-n", os.path.join(s, "slurm.sh")]).returncode == 0,
          "--slurm writes a valid job-array script over the table's commands")


def log_levels(tmp):
    """tern fly --log-level: summary writes no topic tables; decimated logs the 400-Hz IMU at 10 Hz."""
    mission = os.path.join(SRC, "configs", "missions", "default.yaml")
    runs = {}
    for level in ("summary", "decimated"):
        d = os.path.join(tmp, "level-" + level)
        subprocess.run([TERN, "fly", mission, "--duration", "12", "--log-level", level, "--log-dir", d, "-q"], check=True, capture_output=True)
        runs[level] = glob.glob(os.path.join(d, "*"))[0]
    s = runs["summary"]
    check(os.path.exists(os.path.join(s, "summary.json")) and not glob.glob(os.path.join(s, "topics", "*.csv")),
          "log level summary: summary.json and no topic tables")
    with open(os.path.join(runs["decimated"], "topics", "imu.csv")) as f:
        rows = sum(1 for _ in f) - 1
    check(115 <= rows <= 125, f"log level decimated: 12 s of the 400-Hz IMU at 10 Hz is ~120 rows, got {rows}")


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def dask(tmp, reference):
    try:
        import distributed  # noqa: F401
    except ImportError:
        print("skip Dask: python3-distributed is not installed (apt-get install python3-distributed)")
        return
    port = free_port()
    env = dict(os.environ, DASK_DISTRIBUTED__WORKER__DAEMON="False")
    procs = [subprocess.Popen(["dask-scheduler", "--host", "127.0.0.1", "--port", str(port), "--no-dashboard"], stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL, env=env, cwd=tmp)]
    try:
        time.sleep(2)
        for _ in range(2):
            procs.append(subprocess.Popen(["dask-worker", f"tcp://127.0.0.1:{port}", "--nthreads", "1", "--host", "127.0.0.1", "--no-dashboard",
                                           "--local-directory", tmp], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, env=env, cwd=tmp))
        time.sleep(3)
        out = os.path.join(tmp, "dask")
        r = campaign(out, "--dask", f"tcp://127.0.0.1:{port}", timeout=300)
        check(r.returncode == 0, f"campaign on Dask completes: {r.stderr.strip()[-300:]!r}")
        check(os.path.exists(os.path.join(out, "results.csv")) and table(out) == reference, "Dask table equals the local one")
        throughput(out, "Dask")
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in procs:
            p.wait(timeout=30)


def main():
    tmp = tempfile.mkdtemp(prefix="tern-campaign-test-")
    try:
        bad_input(tmp)
        log_levels(tmp)
        one, two = os.path.join(tmp, "one"), os.path.join(tmp, "two")
        r1 = campaign(one, "--workers", "1")
        check(r1.returncode == 0 and len(summaries(one)) == 6, f"6 flights with 1 worker: {r1.stderr.strip()[-300:]!r}")
        reference = table(one)
        check(reference.count("\n") == 7 and ",error," not in reference, "results.csv: a header and 6 rows, every flight with a summary")
        r2 = campaign(two, "--workers", "2")
        check(r2.returncode == 0 and table(two) == reference, "2 workers give the same table as 1")
        throughput(two, "local")
        resume(tmp, reference)
        refly(tmp, one)
        slurm(tmp, one)
        dask(tmp, reference)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
    print(f"{len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
