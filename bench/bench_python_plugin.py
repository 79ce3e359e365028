#!/usr/bin/python3
"""bench_python_plugin.py [--build BUILD] [--flights N] [--out JSON]: plugins written in Python (issue 66).

The default mission (seed 1, to its landing) flown by `tern fly -q` three ways: as shipped (the C++
path follower and controller), with the path follower in Python at 100 Hz
(configs/missions/python_follower.yaml), and with the cruise controller in Python at 100 Hz
(configs/missions/python_controller.yaml). Per flight: the median wall time of --flights runs,
taken in turn (default, follower, controller, default, ...) so that a drift of the machine's speed
moves all three alike, and its ratio to the default's (target: at most 2); then whether two runs
of each Python flight wrote byte-identical topic files (target: yes).

Prints a table, writes JSON (default bench/results/bench_python_plugin.json). Run after building
(make build): /usr/bin/python3 bench/bench_python_plugin.py.
"""
import argparse
import filecmp
import json
import platform
import statistics
import subprocess
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FLIGHTS = {"default": "default.yaml", "python_follower": "python_follower.yaml", "python_controller": "python_controller.yaml"}


def fly(build, config, log_dir):
    t0 = time.perf_counter()
    r = subprocess.run([str(build / "bin" / "tern"), "fly", str(ROOT / "configs" / "missions" / config), "-q", "--seed", "1",
                        "--log-dir", str(log_dir)], check=True, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    run = Path(r.stdout.split("log: ")[-1].split()[0])
    return wall, run


def same_topics(a, b):
    names = sorted(p.name for p in (a / "topics").iterdir())
    match, mismatch, errors = filecmp.cmpfiles(a / "topics", b / "topics", names, shallow=False)
    return len(names) > 0 and not mismatch and not errors


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", type=Path, default=ROOT / "build")
    ap.add_argument("--flights", type=int, default=5)
    ap.add_argument("--out", type=Path, default=ROOT / "bench" / "results" / "bench_python_plugin.json")
    args = ap.parse_args()
    walls = {name: [] for name in FLIGHTS}
    runs = {name: [] for name in FLIGHTS}
    with tempfile.TemporaryDirectory(prefix="bench-python-plugin-") as tmp:
        for i in range(args.flights):
            for name, config in FLIGHTS.items():
                wall, run = fly(args.build, config, Path(tmp) / f"{name}{i}")
                walls[name].append(wall)
                runs[name].append(run)
        flown = {name: json.load(open(runs[name][0] / "summary.json"))["duration_s"] for name in FLIGHTS}
        ends = {name: json.load(open(runs[name][0] / "summary.json"))["end_reason"] for name in FLIGHTS}
        repeat = {name: same_topics(runs[name][0], runs[name][-1]) for name in FLIGHTS if args.flights > 1}
    base = statistics.median(walls["default"])
    result = {"bench": "bench_python_plugin", "issue": 66, "machine": platform.machine(), "python": platform.python_version(),
              "flights_each": args.flights, "command": "python3 bench/bench_python_plugin.py" + (f" --flights {args.flights}" if args.flights != 5 else ""),
              "flights": {name: {"config": f"configs/missions/{FLIGHTS[name]}", "flight_s": flown[name], "end_reason": ends[name],
                                 "wall_s_median": statistics.median(walls[name]), "wall_s_min": min(walls[name]), "wall_s_max": max(walls[name]),
                                 "over_default": statistics.median(walls[name]) / base, "repeats_bit_for_bit": repeat.get(name)}
                          for name in FLIGHTS}}
    print(f"{'flight':<20} {'flown s':>8} {'end':>8} {'wall s (median)':>16} {'x default':>10} {'repeats':>8}")
    for name, f in result["flights"].items():
        print(f"{name:<20} {f['flight_s']:8.1f} {f['end_reason']:>8} {f['wall_s_median']:16.2f} {f['over_default']:10.2f} {str(f['repeats_bit_for_bit']):>8}")
    args.out.write_text(json.dumps(result, indent=2) + "\n")
    print(f"written: {args.out}")


if __name__ == "__main__":
    main()
