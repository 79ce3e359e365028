#!/usr/bin/env python3
"""End-to-end: configs/missions/default_sil.yaml, the hourglass flown through the REAL ROSflight
firmware (tern-fcu-sil, lockstep), checked against what the mission's script does (issue 40,
"done when"):

1. arming by RC: the firmware boots disarmed (its IMU calibrated on the bench beforehand, baro
   and pitot by itself at boot), the pilot's arm switch at 9.1 s arms it, the flight holds in
   preflight until then and takes off after it; it reaches cruise and passes waypoints;
2. pilot override and hand-back: the roll stick past RC_OVRD_DEV from 100 to 102 s hands roll to
   the pilot, and the firmware hands it back within RC_OVRD_LAG_T of the stick being centred;
3. RC loss (the receiver's failsafe flag, 160-163 s): the firmware's failsafe is on for exactly
   that window (state_manager.cpp), tern reports it and flies on afterwards (waypoints passed
   after it, no crash, the estimate valid at the end);
4. companion silence (tern's bytes do not reach the firmware, 220-222 s): the firmware stops
   reporting offboard control after OFFBOARD_TIMEOUT (100 ms) and resumes it when tern's
   commands arrive again; the flight goes on to its end;
5. determinism: two 30-s flights with the same seed write byte-identical topics;
6. the link's round trip is reported (issue 41): the flight's timing.json has TIMESYNC answers
   and finite, ordered round trips (p50 <= p99 <= max), and `tern fcu status` against a
   tern-fcu-sil paced as a 921600-baud UART prints its state and a round-trip line. The
   plumbing only: no figure is compared with a time (bench/bench_fcu_rtt.py measures them).

usage: e2e_sil_mission.py TERN MISSIONS_DIR WORK_DIR [DURATION_S]
"""
import filecmp
import json
import math
import os
import re
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from e2e_default_mission import Checks, check_arming, check_override, fly, manager, topic  # noqa: E402

RC_LOST_S = (160.0, 163.0)         # default_sil.yaml emulator_rc: lost=1 / lost=0
COMPANION_SILENT_S = (220.0, 222.0)  # default_sil.yaml emulator_args: --companion-silence
OFFBOARD_TIMEOUT_S = 0.1           # the firmware's OFFBOARD_TIMEOUT default (param.cpp): 100 ms
STATUS_PERIOD_S = 0.1              # ROSFLIGHT_STATUS at 10 Hz (comm_manager.cpp send_1hz_heartbeat)


def window(rows, key, value, after):
    """First time at or after `after` where rows[key] == value, else nan."""
    for r in rows:
        if r["t"] >= after and r[key] == value:
            return r["t"]
    return float("nan")


def check_rc_loss(c, run, summary):
    st = topic(run, "fcu_status")
    on = window(st, "failsafe", 1, RC_LOST_S[0] - 1)
    off = window(st, "failsafe", 0, on) if on == on else float("nan")
    c.row("failsafe on at, s", RC_LOST_S[0], on)
    c.row("failsafe off at, s", RC_LOST_S[1], off)
    c.expect(RC_LOST_S[0] <= on <= RC_LOST_S[0] + STATUS_PERIOD_S + 0.05, f"failsafe on at {on} s, RC lost at {RC_LOST_S[0]} s")
    c.expect(RC_LOST_S[1] <= off <= RC_LOST_S[1] + STATUS_PERIOD_S + 0.05, f"failsafe off at {off} s, RC back at {RC_LOST_S[1]} s")
    c.expect(not any(r["failsafe"] == 1 for r in st if r["t"] < RC_LOST_S[0] or r["t"] > RC_LOST_S[1] + 0.2),
             "failsafe outside the RC-loss window")
    log = open(os.path.join(run, "tern.log")).read()
    c.expect("FCU failsafe ON" in log and "FCU failsafe off" in log, "tern.log does not say the FCU's failsafe came and went")


def check_companion_silence(c, run):
    st = topic(run, "fcu_status")
    lost = window(st, "offboard", 0, COMPANION_SILENT_S[0])
    back = window(st, "offboard", 1, lost) if lost == lost else float("nan")
    c.row("offboard control lost at, s", COMPANION_SILENT_S[0] + OFFBOARD_TIMEOUT_S, lost)
    c.row("offboard control back at, s", COMPANION_SILENT_S[1], back)
    c.expect(COMPANION_SILENT_S[0] + OFFBOARD_TIMEOUT_S <= lost <= COMPANION_SILENT_S[0] + OFFBOARD_TIMEOUT_S + STATUS_PERIOD_S + 0.05,
             f"offboard control lost at {lost} s; tern's bytes stopped at {COMPANION_SILENT_S[0]} s")
    c.expect(COMPANION_SILENT_S[1] <= back <= COMPANION_SILENT_S[1] + STATUS_PERIOD_S + 0.05,
             f"offboard control back at {back} s; tern's bytes arrive again at {COMPANION_SILENT_S[1]} s")


def check_flight(c, run, summary):
    c.row("end", "duration", summary["end_reason"])
    c.expect(summary["end_reason"] == "duration", f"the flight ended early: {summary['end_reason']}")
    passed = manager(summary)["waypoints_passed"]
    c.row("waypoints passed", ">= 8", passed)
    c.expect(passed >= 8, f"only {passed} waypoints passed")
    log = open(os.path.join(run, "tern.log")).read()
    after = [float(l.split("t=")[1].split(" s")[0]) for l in log.splitlines() if "passed waypoint" in l and "t=" in l]
    state = topic(run, "state")
    c.expect(state[-1]["valid"] == 1, "the estimate is not valid at the end")
    alt = [-r["p_d"] for r in state if r["t"] > COMPANION_SILENT_S[1] + 10]
    c.row("altitude after the events, m (min)", "> 40", min(alt) if alt else float("nan"))
    c.expect(alt and min(alt) > 40, "the aircraft did not get back to its mission altitude after the events")
    sim = summary["instances"]["sim"]
    for k in ("fcu_bad_crc", "fcu_seq_gaps"):
        c.row(k, 0, sim.get(k, "missing"))
        c.expect(sim.get(k) == 0, f"{k} = {sim.get(k)} on a clean link")
    return after


def rtt_ordered(p50, p99, mx):
    """Finite and ordered, each above 0 and below TimeSync's 50-ms acceptance bound (timesync.hpp)."""
    vals = (p50, p99, mx)
    return all(isinstance(v, (int, float)) and math.isfinite(v) for v in vals) and 0 < p50 <= p99 <= mx < 50


def check_round_trip(c, run):
    with open(os.path.join(run, "timing.json")) as f:
        sim = json.load(f)["instances"]["sim"]
    answers = sim.get("fcu_timesync_answers", 0)
    c.row("TIMESYNC answers in the flight", ">= 1", answers)
    c.expect(answers >= 1, "timing.json: no TIMESYNC answer (fcu_timesync_answers) in the whole flight")
    vals = [sim.get(k) for k in ("fcu_timesync_rtt_p50_ms", "fcu_timesync_rtt_p99_ms", "fcu_timesync_rtt_max_ms")]
    c.row("flight round trip p50/p99/max ordered", True, answers >= 1 and rtt_ordered(*vals))
    c.expect(answers >= 1 and rtt_ordered(*vals), f"timing.json: round trips p50/p99/max {vals} are not finite and ordered")


def check_status(c, tern, missions, work):
    """`tern fcu status` against a tern-fcu-sil of its own, its port paced as a 921600-baud UART."""
    bindir = os.path.dirname(tern)
    configs = os.path.dirname(os.path.abspath(missions))
    sil = [os.path.join(bindir, "tern-fcu-sil"), "--aircraft", os.path.join(configs, "aircraft", "anaconda.yaml"), "--params",
           os.path.join(configs, "fcu", "anaconda_rosflight_sil.yaml"), "--baud", "921600", "--flash", os.path.join(work, "status.flash")]
    proc = subprocess.Popen(sil, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    try:
        line = proc.stdout.readline().strip()
        out = subprocess.run([os.path.join(bindir, "tern-fcu"), "--device", line.split(" ", 1)[-1], "status", "--samples", "5"],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60) if line.startswith("pty: ") else None
    finally:
        proc.terminate()
        proc.wait(timeout=10)
    c.row("tern-fcu-sil --baud 921600 port", "pty: ...", line)
    c.expect(out is not None, f"tern-fcu-sil said '{line}', not its port")
    if out is None:
        return
    m = re.search(r"^round trip: p50 (\S+) ms, p99 (\S+) ms, max (\S+) ms \(TIMESYNC, (\d+) of 5 ", out.stdout, re.M)
    c.row("tern fcu status: exit, round-trip line", "0, yes", f"{out.returncode}, {'yes' if m else 'no'}")
    c.expect(out.returncode == 0 and m is not None and "\nstate:" in out.stdout, f"tern fcu status said:\n{out.stdout}")
    if m:
        c.row("tern fcu status round trip ordered", True, rtt_ordered(*(float(m.group(i)) for i in (1, 2, 3))))
        c.expect(int(m.group(4)) >= 1 and rtt_ordered(*(float(m.group(i)) for i in (1, 2, 3))), f"tern fcu status: {m.group(0)}")


def check_determinism(c, tern, config, work):
    runs = []
    for i in (1, 2):
        _, run = fly(tern, config, os.path.join(work, f"det{i}"), 30)
        runs.append(os.path.join(run, "topics"))
    names = sorted(os.listdir(runs[0]))
    _, mismatch, errors = filecmp.cmpfiles(runs[0], runs[1], names, shallow=False)
    c.row("determinism: differing topics", 0, len(mismatch) + len(errors))
    c.expect(not mismatch and not errors, f"same seed, different topics: {mismatch + errors}")


def main():
    tern, missions, work = sys.argv[1], sys.argv[2], sys.argv[3]
    duration = float(sys.argv[4]) if len(sys.argv) > 4 else 260.0
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    config = os.path.join(missions, "default_sil.yaml")
    summary, run = fly(tern, config, os.path.join(work, "mission"), duration)
    c = Checks()
    check_arming(c, summary, run)
    check_override(c, run)
    check_rc_loss(c, run, summary)
    check_companion_silence(c, run)
    check_flight(c, run, summary)
    check_round_trip(c, run)
    check_status(c, tern, missions, work)
    check_determinism(c, tern, config, work)
    for name, a, b in c.rows:
        print(f"{name:40s} expected {a!s:>10}  got {b!s:>10}")
    if c.failures:
        print("FAILED:\n  " + "\n  ".join(c.failures))
        return 1
    print("the real firmware in the loop: all checks passed")
    return 0


if __name__ == "__main__":
    sys.exit(main())
