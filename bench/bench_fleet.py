#!/usr/bin/python3
"""bench_fleet.py BIN_DIR [--vehicles 1,3,10] [--seconds S] [--repeat N] [--cpu K] [--seeds N] [--out JSON]: multi-vehicle cost and rendezvous.

Cost (issue 42: "N vehicles cost about N times one vehicle"): writes a multi-vehicle mission of N
copies of configs/missions/crossing.yaml's stack (realistic sensors, light turbulence, the
summary log), the vehicles released at trim 300 m apart flying parallel legs north, and flies it
--repeat times per N (default 3) pinned to one core (--cpu, default the last). Reports the best
run's process CPU time and wall time, the flight speed (simulated s of all vehicles per CPU s)
and the efficiency per core, N * cpu(1) / cpu(N) (1: N vehicles cost exactly N times one).

Rendezvous (configs/missions/rendezvous.yaml, when it exists): flies it for --seeds seeds
(default 10) and reads the coordination's figures from the fleet's summary.json (arrival spread,
s; planned time) and the closest approach. Reports the worst seed.

Prints tables and writes JSON (default bench/results/bench_fleet.json). The machine's load varies:
compare the Ns with each other.
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import tempfile
import time

import yaml


def fleet_mission(repo, n, seconds):
    with open(os.path.join(repo, "configs", "missions", "crossing.yaml")) as f:
        m = yaml.safe_load(f)
    m["name"] = f"bench_fleet_{n}"
    m["duration"] = seconds
    m["aircraft"] = os.path.join(repo, "configs", "aircraft", "anaconda.yaml")
    for p in m["plugins"]:
        if "param_file" in p:
            p["param_file"] = os.path.join(repo, "configs", "gains", os.path.basename(p["param_file"]))
    m["log"] = {"level": "summary"}
    m["vehicles"] = [{"name": f"uav{i + 1}",
                      "initial": {"mode": "trim", "position": [0, 300 * i], "altitude": 80, "airspeed": 17, "heading": 0.0},
                      "mission": {"waypoints": [{"ned": [2000, 0, 0], "Va_d": 17}, {"ned": [4000, 0, 0], "Va_d": 17}]}}
                     for i in range(n)]
    return m


def fly(tern, mission, out, cpu, extra=()):
    argv = [tern, "fly", mission, "--log-dir", out, "-q", *extra]
    t0 = time.monotonic()
    p = subprocess.Popen(argv, stdout=subprocess.DEVNULL, preexec_fn=lambda: os.sched_setaffinity(0, {cpu}))
    _, status, usage = os.wait4(p.pid, 0)
    wall = time.monotonic() - t0
    run = glob.glob(os.path.join(out, "*"))[0]
    with open(os.path.join(run, "summary.json")) as f:
        s = json.load(f)
    return {"exit": os.waitstatus_to_exitcode(status), "wall_s": wall, "cpu_s": usage.ru_utime + usage.ru_stime, "summary": s}


def cost(args, tern, repo, tmp):
    rows = []
    for n in args.vehicles:
        path = os.path.join(tmp, f"fleet{n}.yaml")
        with open(path, "w") as f:
            yaml.safe_dump(fleet_mission(repo, n, args.seconds), f)
        runs = [fly(tern, path, os.path.join(tmp, f"n{n}-{k}"), args.cpu) for k in range(args.repeat)]
        best = min(runs, key=lambda r: r["cpu_s"])
        flown = sum(v["flown_s"] for v in best["summary"]["vehicles"].values())
        rows.append({"vehicles": n, "cpu_s": best["cpu_s"], "wall_s": best["wall_s"], "vehicle_seconds": flown,
                     "speed_vehicle_s_per_cpu_s": flown / best["cpu_s"],
                     "end_reasons": sorted({v["end_reason"] for v in best["summary"]["vehicles"].values()})})
    one = next((r for r in rows if r["vehicles"] == 1), None)
    for r in rows:
        r["efficiency"] = r["vehicles"] * one["cpu_s"] / r["cpu_s"] if one else None
    print(f"{'vehicles':>8} {'cpu s':>8} {'wall s':>8} {'vehicle-s per cpu-s':>20} {'efficiency':>10}  ends")
    for r in rows:
        eff = f"{r['efficiency']:.3f}" if r["efficiency"] is not None else "-"
        print(f"{r['vehicles']:>8} {r['cpu_s']:>8.2f} {r['wall_s']:>8.2f} {r['speed_vehicle_s_per_cpu_s']:>20.1f} {eff:>10}  "
              f"{','.join(r['end_reasons'])}")
    return rows


def rendezvous(args, tern, repo, tmp):
    mission = os.path.join(repo, "configs", "missions", "rendezvous.yaml")
    if not os.path.exists(mission):
        print("rendezvous: configs/missions/rendezvous.yaml not found: skipped")
        return None
    rows = []
    for seed in range(1, args.seeds + 1):
        r = fly(tern, mission, os.path.join(tmp, f"rdv{seed}"), args.cpu, ("--seed", str(seed), "--log-level", "summary"))
        s = r["summary"]
        figures = {}
        for inst in (s.get("coordination", {}).get("instances") or {}).values():
            figures.update({k: v for k, v in inst.items() if k not in ("plugin", "library", "library_fnv1a", "steps")})
        rows.append({"seed": seed, "exit": r["exit"], "closest_approach_m": s["separation"]["closest_approach_m"], **figures})
    print(f"{'seed':>4} {'spread s':>9} {'arrived':>8} {'closest m':>10}")
    for r in rows:
        spread = r.get("arrival_spread")
        print(f"{r['seed']:>4} {spread if spread is None else round(spread, 3):>9} {r.get('vehicles_arrived', '-'):>8} "
              f"{r['closest_approach_m'] or float('nan'):>10.1f}")
    spreads = [r.get("arrival_spread") for r in rows]
    worst = max((x for x in spreads if x is not None), default=None)
    print(f"worst arrival spread over {len(rows)} seeds: {worst} s (target <= 1 s)")
    return {"seeds": rows, "worst_arrival_spread_s": worst}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("bin_dir")
    ap.add_argument("--vehicles", default="1,3,10", help="comma-separated vehicle counts")
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--seeds", type=int, default=10)
    ap.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)), help="the core every flight is pinned to")
    ap.add_argument("--skip-rendezvous", action="store_true")
    ap.add_argument("--out", default=os.path.join(here, "results", "bench_fleet.json"))
    args = ap.parse_args()
    try:
        args.vehicles = [int(x) for x in args.vehicles.split(",")]
    except ValueError:
        sys.exit(f"bench_fleet.py: --vehicles: expected a comma-separated list of counts, got '{args.vehicles}'")
    tern = os.path.join(args.bin_dir, "tern")
    repo = os.path.dirname(here)
    with tempfile.TemporaryDirectory() as tmp:
        result = {"cost": cost(args, tern, repo, tmp), "seconds": args.seconds, "cpu": args.cpu}
        if not args.skip_rendezvous:
            result["rendezvous"] = rendezvous(args, tern, repo, tmp)
    os.makedirs(os.path.dirname(args.out), exist_ok=True)
    with open(args.out, "w") as f:
        json.dump(result, f, indent=2)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
