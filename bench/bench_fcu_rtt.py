#!/usr/bin/python3
"""bench_fcu_rtt.py [TERN_BIN_DIR] [--duration S] [--links pty,uart] [--loads none,stress] [--status-samples N] [--out JSON]:
the serial round trip of issue 41, item 4: companion -> FCU -> companion, measured with MAVLink
TIMESYNC against the REAL ROSflight firmware (tern-fcu-sil) over a pseudo-terminal.

1. Flights: configs/missions/default_sil.yaml as written (the firmware on tern's SIL board, the
   same world, estimator and controllers), but free-running in real time instead of lockstep:
   `--set sim.lockstep=false --set sim.emulator_link=pty` and tern-fcu-sil `--speed 1`, the
   pilot's script cut to the arming steps (< 100 s), no --companion-silence. fcu_serial sends a
   TIMESYNC request at 10 Hz (timesync_rate) stamped with its steady clock; the firmware answers
   in its main loop (rosflight_firmware src/comm_manager.cpp CommManager::timesync_callback,
   reached from ROSflight::run -> CommManager::receive -> MavlinkAdapter::receive ->
   handle_msg_timesync), and the round trip is the answer's arrival (stamped by fcu_serial's
   reader thread) minus the request's stamp. Per flight: timing.json's fcu_timesync_rtt_p50_ms,
   _p99_ms, _max_ms and fcu_timesync_answers (instance `sim`).
   Links:
     pty   the pseudo-terminal alone: bytes move at memory speed (the 921600 in its terminal
           settings is only recorded): the software's share of the round trip;
     uart  the same pty paced as a UART at 921600 baud, 8N1 (tern-fcu-sil --baud 921600,
           tools/emulator/uart.hpp): every byte 10.85 us, queued behind what the firmware
           streams (IMU and attitude at 400 Hz ...): what a real UART at that rate adds.
   Loads: none, or stress (bench_realtime_load.py's: one busy loop per core and a repeated 4-GB
   file write with fsync). On an aircraft the FCU is other hardware; here its stand-in shares the
   loaded cores, and under the stress it falls behind real time itself. --fcu-priority N runs
   tern-fcu-sil at SCHED_FIFO N (through `chrt`, as fcu_serial's emulator_path), so that the load
   reaches the companion's side only (tern stays SCHED_OTHER).
2. `tern fcu status` against a tern-fcu-sil of its own (uart link, no flight): --status-samples
   TIMESYNC requests at 10 Hz; its printed round trip line.
Prints a table and writes JSON (default bench/results/fcu_rtt.json).
"""
import argparse
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, HERE)
from bench_realtime_load import Stress, comma_list, git_commit, machine  # noqa: E402

MISSION = os.path.join(REPO, "configs", "missions", "default_sil.yaml")
BAUD = 921600
LINKS = {"pty": [], "uart": ["--baud", str(BAUD)]}
LOADS = ("none", "stress")
PILOT_EVENTS_FROM_S = 100.0  # default_sil.yaml's emulator_rc: the steps after arming


def fail(msg):
    sys.exit(f"bench_fcu_rtt: {msg}")


def mission_param(key):
    with open(MISSION) as f:
        m = re.search(rf"^\s+{key}:\s*\"([^\"]*)\"", f.read(), re.M)
    if not m:
        fail(f"{MISSION}: no sim.{key}")
    return m.group(1)


def settings(link, wrapper):
    args = re.sub(r"\s*--companion-silence \S+", "", mission_param("emulator_args")) + " --speed 1 " + " ".join(LINKS[link])
    rc = "; ".join(s.strip() for s in mission_param("emulator_rc").split(";") if float(s.split()[0]) < PILOT_EVENTS_FROM_S)
    out = ["--set", "sim.lockstep=false", "--set", "sim.emulator_link=pty", "--set", "sim.emulator_args=" + json.dumps(args.strip()),
           "--set", "sim.emulator_rc=" + json.dumps(rc)]
    return out + (["--set", "sim.emulator_path=" + json.dumps(wrapper)] if wrapper else [])


def fifo_wrapper(bin_dir, priority, work):
    """A script that execs tern-fcu-sil under SCHED_FIFO `priority` (same process: --exit-with-parent holds)."""
    path = os.path.join(work, "tern-fcu-sil-fifo")
    with open(path, "w") as f:
        f.write(f"#!/bin/sh\nexec chrt -f {priority} {os.path.join(bin_dir, 'tern-fcu-sil')} \"$@\"\n")
    os.chmod(path, 0o755)
    return path


def fly(tern, link, duration, log_dir, wrapper):
    os.makedirs(log_dir, exist_ok=True)
    argv = [tern, "fly", MISSION, "--duration", str(duration), "-q", "--log-dir", log_dir] + settings(link, wrapper)
    p = subprocess.run(argv, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    with open(os.path.join(log_dir, "fly.log"), "w") as f:
        f.write(p.stdout)
    if p.returncode != 0:
        fail(f"{' '.join(argv)} failed (exit {p.returncode}); see {log_dir}/fly.log")
    runs = glob.glob(os.path.join(log_dir, "*", "timing.json"))
    if len(runs) != 1:
        fail(f"expected one run directory in {log_dir}, found {len(runs)}")
    return os.path.dirname(runs[0]), p.stdout


def one_flight(tern, link, load, duration, work, wrapper, fcu_priority):
    print(f"  flight, link {link:4} load {load:6} ({duration:g} s) ...", end="", flush=True)
    stress = Stress(os.cpu_count(), 4.0, tempfile.gettempdir()) if load == "stress" else None
    if stress:
        stress.start()
    try:
        run, out = fly(tern, link, duration, os.path.join(work, f"{link}-{load}"), wrapper)
    finally:
        achieved = stress.stop() if stress else None
    with open(os.path.join(run, "timing.json")) as f:
        sim = json.load(f)["instances"]["sim"]
    with open(os.path.join(run, "summary.json")) as f:
        summary = json.load(f)
    keys = ("fcu_timesync_answers", "fcu_timesync_too_slow", "fcu_timesync_rtt_p50_ms", "fcu_timesync_rtt_p99_ms",
            "fcu_timesync_rtt_max_ms", "fcu_frames")
    missing = [k for k in keys if k not in sim]
    if missing:
        fail(f"{run}/timing.json: instance sim has no {', '.join(missing)}")
    if sim["fcu_timesync_answers"] < 1:
        fail(f"{run}: no TIMESYNC answer in the whole flight")
    uart = [line for line in out.splitlines() if "tern-fcu-sil: UART" in line]
    row = {"link": link, "load": load, "fcu_priority": fcu_priority, "duration_s": duration, "end_reason": summary["end_reason"],
           "flight_s": summary["duration_s"], "stress": achieved, "uart": uart[-1] if uart else None,
           **{k: sim[k] for k in keys}, "fcu_seq_gaps": summary["instances"]["sim"].get("fcu_seq_gaps"),
           "fcu_link_losses": summary["instances"]["sim"].get("fcu_link_losses")}
    print(f" p50 {row['fcu_timesync_rtt_p50_ms']:.3f} ms, p99 {row['fcu_timesync_rtt_p99_ms']:.3f} ms, "
          f"max {row['fcu_timesync_rtt_max_ms']:.3f} ms ({row['fcu_timesync_answers']:.0f} answers)")
    return row


def status_check(bin_dir, samples, work):
    """tern fcu status against a tern-fcu-sil of its own (uart link): its printed lines."""
    sil = [os.path.join(bin_dir, "tern-fcu-sil"), "--aircraft", os.path.join(REPO, "configs", "aircraft", "anaconda.yaml"),
           "--params", os.path.join(REPO, "configs", "fcu", "anaconda_rosflight_sil.yaml"), "--speed", "1", "--baud", str(BAUD),
           "--bench-calibration", "--flash", os.path.join(work, "status.flash")]
    print(f"  tern fcu status, {samples} TIMESYNC requests at 10 Hz over the UART-paced pty ...", end="", flush=True)
    with open(os.path.join(work, "status-sil.log"), "w") as err:
        proc = subprocess.Popen(sil, stdout=subprocess.PIPE, stderr=err, text=True)
        try:
            line = proc.stdout.readline().strip()
            if not line.startswith("pty: "):
                fail(f"tern-fcu-sil said '{line}', not its port; see {work}/status-sil.log")
            device = line.split(" ", 1)[1]
            p = subprocess.run([os.path.join(bin_dir, "tern-fcu"), "--device", device, "--baud", str(BAUD), "status", "--samples",
                                str(samples)], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=samples / 10 + 60)
        finally:
            proc.terminate()
            proc.wait(timeout=10)
    m = re.search(r"round trip: p50 ([\d.]+) ms, p99 ([\d.]+) ms, max ([\d.]+) ms \(TIMESYNC, (\d+) of (\d+)", p.stdout)
    if p.returncode != 0 or not m:
        fail(f"tern fcu status failed (exit {p.returncode}):\n{p.stdout}")
    print(f" p50 {m.group(1)} ms, p99 {m.group(2)} ms, max {m.group(3)} ms")
    return {"output": p.stdout.splitlines(), "rtt_p50_ms": float(m.group(1)), "rtt_p99_ms": float(m.group(2)),
            "rtt_max_ms": float(m.group(3)), "answers": int(m.group(4)), "requests": int(m.group(5))}


def print_table(rows, status):
    print(f"\nTIMESYNC round trip, companion -> ROSflight firmware (tern-fcu-sil, real time) -> companion")
    print(f"{'link':34}{'fcu':9}{'load':8}{'flight s':>9}{'answers':>9}{'p50 ms':>9}{'p99 ms':>9}{'max ms':>9}{'>50 ms':>8}")
    names = {"pty": "pty (memory speed)", "uart": f"pty paced as a UART, {BAUD} baud"}
    for r in rows:
        print(f"{names[r['link']]:34}{('FIFO ' + str(r['fcu_priority'])) if r.get('fcu_priority') else 'OTHER':9}{r['load']:8}{r['flight_s']:9.0f}{r['fcu_timesync_answers']:9.0f}{r['fcu_timesync_rtt_p50_ms']:9.3f}"
              f"{r['fcu_timesync_rtt_p99_ms']:9.3f}{r['fcu_timesync_rtt_max_ms']:9.3f}{r['fcu_timesync_too_slow']:8.0f}")
    if status:
        print(f"{'tern fcu status (' + names['uart'] + ')':51}{'':9}{status['answers']:9d}{status['rtt_p50_ms']:9.3f}"
              f"{status['rtt_p99_ms']:9.3f}{status['rtt_max_ms']:9.3f}")
    for r in rows:
        if r["uart"]:
            print(f"{r['link']}/{r['load']}: {r['uart'].split(': ', 1)[1]}")


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bin_dir", nargs="?", default=os.path.join(REPO, "build", "bin"), help="directory of tern (default build/bin)")
    ap.add_argument("--duration", type=float, default=120.0, help="s of each flight (real time)")
    ap.add_argument("--links", default="pty,uart", help="comma-separated: pty, uart")
    ap.add_argument("--loads", default="none,stress", help="comma-separated: none, stress")
    ap.add_argument("--fcu-priority", type=int, default=0, help="run tern-fcu-sil at SCHED_FIFO N (1..99; 0: SCHED_OTHER)")
    ap.add_argument("--status-samples", type=int, default=300, help="TIMESYNC requests of `tern fcu status` (0: not run)")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "fcu_rtt.json"))
    ap.add_argument("--keep", help="fly into this directory and keep it (default: a temporary one, removed)")
    a = ap.parse_args()
    a.links = comma_list(a.links, "--links", LINKS, fail)
    a.loads = comma_list(a.loads, "--loads", LOADS, fail)
    if not a.duration >= 20:
        fail(f"--duration: {a.duration:g}: at least 20 s (the firmware boots, calibrates and arms in the first 10)")
    if not 0 <= a.fcu_priority <= 99:
        fail(f"--fcu-priority: {a.fcu_priority}: must be 0..99")
    if a.fcu_priority and not shutil.which("chrt"):
        fail("--fcu-priority: no chrt (util-linux) on PATH")
    if a.status_samples < 0:
        fail(f"--status-samples: {a.status_samples}: must be >= 0")
    for exe in ("tern", "tern-fcu", "tern-fcu-sil"):
        if not os.access(os.path.join(a.bin_dir, exe), os.X_OK):
            fail(f"{os.path.join(a.bin_dir, exe)}: not built (tern-fcu-sil needs a rosflight_firmware tree: "
                 "docs/fly-with-the-real-firmware.md)")
    return a


def main():
    a = parse_args()
    commit = git_commit()
    work = a.keep or tempfile.mkdtemp(prefix="bench_fcu_rtt-")
    os.makedirs(work, exist_ok=True)
    print(f"serial round trip: {os.path.relpath(MISSION, REPO)} free-running, {a.duration:g}-s flights; in {work}")
    rows, status = [], None
    try:
        wrapper = fifo_wrapper(a.bin_dir, a.fcu_priority, work) if a.fcu_priority else None
        for load in a.loads:
            for link in a.links:
                rows.append(one_flight(os.path.join(a.bin_dir, "tern"), link, load, a.duration, work, wrapper, a.fcu_priority))
        if a.status_samples:
            status = status_check(a.bin_dir, a.status_samples, work)
    finally:
        if not a.keep:
            shutil.rmtree(work, ignore_errors=True)
    print_table(rows, status)
    result = {"bench": "fcu_rtt", "mission": os.path.relpath(MISSION, REPO), "baud": BAUD, "flights": rows, "tern_fcu_status": status,
              "machine": machine(), "git": commit, "time": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime())}
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(result, f, indent=1)
        f.write("\n")
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()
