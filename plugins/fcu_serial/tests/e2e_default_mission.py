#!/usr/bin/env python3
"""End-to-end: the default mission flown through fcu_serial and tern-fcu-emulator completes like
the direct sim_aero flight (same waypoints reached, phase times and line tracking error within
20 % of the direct run).

usage: e2e_default_mission.py TERN MISSIONS_DIR WORK_DIR [DURATION_S]
"""
import glob
import json
import os
import shutil
import subprocess
import sys


def fly(tern, config, log_dir, duration):
    r = subprocess.run([tern, "fly", config, "-q", "--duration", str(duration), "--log-dir", log_dir],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
    if r.returncode != 0:
        print(r.stdout)
        raise SystemExit(f"tern fly {config} failed with exit code {r.returncode}")
    runs = sorted(glob.glob(os.path.join(log_dir, "*", "summary.json")), key=os.path.getmtime)
    if not runs:
        raise SystemExit(f"no summary.json under {log_dir}")
    return json.load(open(runs[-1]))


def manager(summary):
    for name, inst in summary["instances"].items():
        if "waypoints_passed" in inst:
            return inst
    raise SystemExit("summary has no path manager figures")


def main():
    if len(sys.argv) < 4:
        raise SystemExit(__doc__)
    tern, missions, work = sys.argv[1:4]
    duration = float(sys.argv[4]) if len(sys.argv) > 4 else 300.0
    for sub in ("direct", "fcu"):  # only this test's own run directories
        shutil.rmtree(os.path.join(work, sub), ignore_errors=True)
    os.makedirs(work, exist_ok=True)
    direct = fly(tern, os.path.join(missions, "default.yaml"), os.path.join(work, "direct"), duration)
    fcu = fly(tern, os.path.join(missions, "default_fcu.yaml"), os.path.join(work, "fcu"), duration)
    failures = []
    for s, name in ((direct, "direct"), (fcu, "fcu")):
        if s["end_reason"] != "duration":
            failures.append(f"{name} flight ended early: {s['end_reason']}")
    md, mf = manager(direct), manager(fcu)
    rows = [("waypoints passed", md["waypoints_passed"], mf["waypoints_passed"])]
    if mf["waypoints_passed"] != md["waypoints_passed"] or md["waypoints_passed"] < 1:
        failures.append("waypoints passed differ")
    for key in ("line_cross_track_rms_m", "line_cross_track_max_m"):
        rows.append((key, md[key], mf[key]))
        if abs(mf[key] - md[key]) > 0.2 * md[key]:
            failures.append(f"{key}: {mf[key]:.3f} through the FCU vs {md[key]:.3f} direct (more than 20 % apart)")
    pd = {p["phase"]: p["start_s"] for p in direct["phases"]}
    pf = {p["phase"]: p["start_s"] for p in fcu["phases"]}
    for ph in pd:
        rows.append((f"{ph} starts, s", pd[ph], pf.get(ph, float("nan"))))
        if ph not in pf or abs(pf[ph] - pd[ph]) > max(1.0, 0.2 * pd[ph]):
            failures.append(f"phase {ph} starts at {pf.get(ph)} s through the FCU vs {pd[ph]} s direct")
    frames = fcu["instances"].get("sim", {}).get("fcu_frames", 0)
    rows.append(("MAVLink frames received", float("nan"), frames))
    print(f"{'':30} {'direct':>12} {'through FCU':>12}")
    for name, a, b in rows:
        print(f"{name:30} {a:12.3f} {b:12.3f}")
    if failures:
        print("\n".join("FAIL: " + f for f in failures))
        return 1
    print("OK: the mission through fcu_serial and the emulator completes like the direct flight")
    return 0


if __name__ == "__main__":
    sys.exit(main())
