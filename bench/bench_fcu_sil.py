#!/usr/bin/python3
"""bench_fcu_sil.py [TERN_BIN_DIR] [--seeds 1,2,3,4,5] [--duration S] [--speed-duration S] [--out JSON]:
the default mission flown three ways (issue 40): direct (configs/missions/default.yaml, sim_aero),
through tern's emulated FCU (default_fcu.yaml, tern-fcu-emulator) and through the REAL ROSflight
firmware (default_sil.yaml, tern-fcu-sil).

1. Tracking. The same world and seed for the three: init heading 2.3562 rad (default.yaml's;
   default_fcu.yaml's 0.0 is overridden), 5 m/s of wind from the south-east, light turbulence,
   the pitot covered until 8.5 s. Sensors: `realistic` for direct and firmware; the emulator has
   only its own (sim::SensorParams defaults), so its column differs in sensors too. The FCU
   flights fly WITHOUT the pilot's events: emulator_rc is only the arming steps (< 100 s) and
   --companion-silence is dropped. Each flight's TRUE position (sim_aero's truth topic; the FCU
   programs' --truth file) is taken into the estimator's frame (its origin, the first GNSS fix:
   the frame the path is flown in) and compared, at 50 Hz, in FlightMetrics' window (cruise phase,
   from the end of the first loop: not the path capture after the climb), with the commanded path
   as FlightMetrics (core/host/record/metrics.cpp) does with the estimate: the horizontal distance
   to the closest point of the line or orbit, and h_c - h (h: the true height above the takeoff
   point, where the estimator's barometric altitude is zeroed).
2. Link figures of the firmware flights (summary.json / timing.json) and determinism: the seed's
   firmware flight flown twice, topics/*.csv compared byte for byte.
3. Speed: wall time per simulated second pinned to one core (taskset -c 1), median of 3; the FCU
   flights run two processes (tern and the FCU program) on that core.
Writes bench/results/fcu_sil.json and prints the tables.
"""
import argparse
import bisect
import csv
import hashlib
import json
import math
import os
import platform
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
MISSIONS = os.path.join(REPO, "configs", "missions")
WAYS = {  # way -> mission config
    "direct": "default.yaml",
    "emulator": "default_fcu.yaml",
    "firmware": "default_sil.yaml",
}
INIT_HEADING = "2.3562"      # rad, default.yaml's sim.init_heading
PILOT_EVENTS_FROM_S = 100.0  # the scripted pilot's first step after arming (default_sil.yaml)
GRID_HZ = 50                 # the FCU programs' --truth rate
TARGET_RATIO = 1.2           # firmware within 20 % of direct
TARGET_SPEED = 100.0         # x real time on one core
METRICS = ["xt_line_rms_m", "xt_line_max_m", "xt_orbit_rms_m", "xt_orbit_max_m", "xt_rms_m", "xt_max_m",
           "alt_rms_m", "alt_max_m"]


def run(argv, log):
    with open(log, "w") as out:
        p = subprocess.run(argv, stdout=out, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        sys.exit(f"bench_fcu_sil: {' '.join(argv)} failed (exit {p.returncode}); see {log}")


def config_param(way, key):
    """A plugin param of the `sim` instance as the mission file writes it (a one-line string)."""
    with open(os.path.join(MISSIONS, WAYS[way])) as f:
        m = re.search(rf"^\s+{key}:\s*\"([^\"]*)\"", f.read(), re.M)
    if not m:
        sys.exit(f"bench_fcu_sil: {WAYS[way]}: no sim.{key}")
    return m.group(1)


def fcu_settings(way, truth_file):
    """--set options of an FCU flight: the file's emulator_args with default.yaml's init heading,
    without --companion-silence, with --truth; emulator_rc cut to the arming steps."""
    if way == "direct":
        return []
    args = config_param(way, "emulator_args")
    args = re.sub(r"--init-heading \S+", "--init-heading " + INIT_HEADING, args)
    args = re.sub(r"\s*--companion-silence \S+", "", args)
    if truth_file:
        args += " --truth " + truth_file
    steps = [s.strip() for s in config_param(way, "emulator_rc").split(";")]
    rc = "; ".join(s for s in steps if float(s.split()[0]) < PILOT_EVENTS_FROM_S)
    return ["--set", "sim.emulator_args=" + json.dumps(args), "--set", "sim.emulator_rc=" + json.dumps(rc)]


def fly(tern, way, seed, duration, log_dir, truth_file=None, pin=None, as_configured=False):
    """One flight (as_configured: the mission file unchanged); returns (run dir, wall seconds
    measured around the process)."""
    argv = [tern, "fly", os.path.join(MISSIONS, WAYS[way]), "--duration", str(duration), "--seed", str(seed), "-q",
            "--log-dir", log_dir] + ([] if as_configured else fcu_settings(way, truth_file))
    if pin is not None:
        argv = ["taskset", "-c", str(pin)] + argv
    os.makedirs(log_dir, exist_ok=True)
    t0 = time.monotonic()
    run(argv, os.path.join(log_dir, "fly.log"))
    wall = time.monotonic() - t0
    runs = [d for d in os.listdir(log_dir) if os.path.isfile(os.path.join(log_dir, d, "summary.json"))]
    if len(runs) != 1:
        sys.exit(f"bench_fcu_sil: expected one run directory in {log_dir}, found {runs}")
    return os.path.join(log_dir, runs[0]), wall


def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    keys = [h.split(" [")[0] for h in rows[0]]
    return [{k: float(v) for k, v in zip(keys, r)} for r in rows[1:]]


# --- WGS-84: a truth position about the simulator's origin, seen about the estimator's origin ---
WGS84_A, WGS84_F = 6378137.0, 1.0 / 298.257223563
WGS84_E2 = WGS84_F * (2.0 - WGS84_F)


class TangentPlane:
    """NED about a geodetic origin (lat, lon deg; alt m), exact through ECEF."""

    def __init__(self, lat, lon, alt):
        la, lo = math.radians(lat), math.radians(lon)
        n = WGS84_A / math.sqrt(1.0 - WGS84_E2 * math.sin(la) ** 2)
        self.o = ((n + alt) * math.cos(la) * math.cos(lo), (n + alt) * math.cos(la) * math.sin(lo),
                  (n * (1.0 - WGS84_E2) + alt) * math.sin(la))
        self.axes = ((-math.sin(la) * math.cos(lo), -math.sin(la) * math.sin(lo), math.cos(la)),
                     (-math.sin(lo), math.cos(lo), 0.0),
                     (-math.cos(la) * math.cos(lo), -math.cos(la) * math.sin(lo), -math.sin(la)))

    def to_ecef(self, ned):
        return tuple(self.o[i] + sum(ned[k] * self.axes[k][i] for k in range(3)) for i in range(3))

    def to_ned(self, ecef):
        d = [ecef[i] - self.o[i] for i in range(3)]
        return tuple(sum(self.axes[k][i] * d[i] for i in range(3)) for k in range(3))


def latest(times, rows, t):
    i = bisect.bisect_right(times, t + 1e-6) - 1
    return rows[i] if i >= 0 else None


def estimator_origin(run_dir):
    """The estimator's origin (its first GNSS fix); the bench expects one per flight."""
    origins = {(r["origin_lat"], r["origin_lon"], r["origin_alt"]) for r in read_csv(os.path.join(run_dir, "topics", "state.csv"))
               if r["origin_valid"] == 1}
    if len(origins) != 1:
        sys.exit(f"bench_fcu_sil: {run_dir}: the estimator has {len(origins)} origins, expected one")
    return origins.pop()


def cross_track(cp, n, e):
    """Horizontal distance to the closest point of the commanded line or orbit (FlightMetrics::step)."""
    if cp["path_type"] == 1:
        qn, qe = cp["q_n"], cp["q_e"]
        norm = math.hypot(qn, qe)
        if norm < 1e-9:
            return 0.0
        qn, qe = qn / norm, qe / norm
        dn, de = n - cp["r_n"], e - cp["r_e"]
        along = dn * qn + de * qe
        return math.hypot(dn - along * qn, de - along * qe)
    return abs(math.hypot(n - cp["c_n"], e - cp["c_e"]) - cp["rho"])


def on_grid(t):
    return abs(t * GRID_HZ - round(t * GRID_HZ)) < 1e-6


def series(run_dir, name):
    rows = read_csv(os.path.join(run_dir, "topics", name + ".csv"))
    return [r["t"] for r in rows], rows


def rms(xs):
    return math.sqrt(sum(x * x for x in xs) / len(xs)) if xs else float("nan")


def phase_code(run_dir, name):
    """The code of phase `name` in the run's definitions.json (core/host/record/log_definitions.hpp)."""
    with open(os.path.join(run_dir, "definitions.json")) as f:
        codes = [int(c) for c, n in json.load(f)["phase"].items() if n == name]
    if not codes:
        raise SystemExit(f"{run_dir}/definitions.json: no phase named {name}")
    return codes[0]


def tracking(run_dir, truth_rows, truth_origin, t_from):
    """Tracking of the true aircraft, 50 Hz, in the cruise phase from t_from on: horizontally in the
    estimator's frame (the path's), vertically the true height above the takeoff point (where the
    estimator's barometric altitude is zeroed; its origin_alt, the first fix's altitude, is off by
    metres) against h_c."""
    path, command, phase = (series(run_dir, n) for n in ("current_path", "controller_command", "flight_phase"))
    sim, est = TangentPlane(*truth_origin), TangentPlane(*estimator_origin(run_dir))
    cruise = phase_code(run_dir, "cruise")
    xt, alt, times = {1: [], 0: []}, [], []
    for r in truth_rows:
        t = r["t"]
        ph = latest(*phase, t)
        if t < t_from or not on_grid(t) or ph is None or ph["phase"] != cruise:
            continue
        cp, cmd = latest(*path, t), latest(*command, t)
        n, e, _ = est.to_ned(sim.to_ecef((r["p_n"], r["p_e"], r["p_d"])))
        xt[int(cp["path_type"])].append(cross_track(cp, n, e))
        alt.append(cmd["h_c"] + r["p_d"])
        times.append(t)
    both = xt[1] + xt[0]
    return {"xt_line_rms_m": rms(xt[1]), "xt_line_max_m": max(xt[1]), "xt_orbit_rms_m": rms(xt[0]),
            "xt_orbit_max_m": max(xt[0]), "xt_rms_m": rms(both), "xt_max_m": max(both), "alt_rms_m": rms(alt),
            "alt_max_m": max(abs(a) for a in alt), "samples": len(times), "cruise_from_s": times[0], "cruise_to_s": times[-1]}


def gnss_vs_truth(run_dir, truth_rows, truth_origin):
    """Frame check: horizontal RMS of the fixes tern received against the truth at their time of
    validity, in the simulator's frame (metres if the origins are right, far more if not)."""
    sim = TangentPlane(*truth_origin)
    times = [r["t"] for r in truth_rows]
    errs = []
    for g in read_csv(os.path.join(run_dir, "topics", "gnss.csv")):
        tr = latest(times, truth_rows, g["time_of_validity"] * 1e-9)
        if g["fix_type"] == 3 and tr is not None:
            n, e, _ = sim.to_ned(TangentPlane(g["lat"], g["lon"], g["alt"]).o)
            errs.append(math.hypot(n - tr["p_n"], e - tr["p_e"]))
    return rms(errs)


def link_figures(run_dir):
    with open(os.path.join(run_dir, "summary.json")) as f:
        sim = json.load(f)["instances"]["sim"]
    with open(os.path.join(run_dir, "timing.json")) as f:
        timing = json.load(f)["instances"]["sim"]
    keys = ("fcu_seq_gaps", "fcu_bad_crc", "fcu_bad_length", "fcu_unknown_id", "fcu_skipped_bytes", "fcu_link_losses",
            "fcu_lockstep_resends", "fcu_commands_sent")
    out = {k: sim.get(k) for k in keys}
    out["fcu_frames"] = timing.get("fcu_frames")
    return out


def checked(run_dir, duration):
    with open(os.path.join(run_dir, "summary.json")) as f:
        s = json.load(f)
    if s["end_reason"] != "duration" or abs(s["duration_s"] - duration) > 0.01:
        sys.exit(f"bench_fcu_sil: {run_dir} ended early: {s['end_reason']} at {s['duration_s']} s")
    return s


def truth_of(way, run_dir, truth_file, direct_origin):
    """(truth rows, simulator origin): sim_aero's truth topic; the FCU program's --truth file, whose
    world uses sim_aero's default origin, the direct flight's (checked by gnss_vs_truth)."""
    if way == "direct":
        rows = read_csv(os.path.join(run_dir, "topics", "truth.csv"))
        return rows, (rows[0]["origin_lat"], rows[0]["origin_lon"], rows[0]["origin_alt"])
    return read_csv(truth_file), direct_origin


def track_seed(tern, seed, duration, work):
    figures, link, origin, runs = {}, None, None, {}
    for way in WAYS:  # direct first: its truth topic names the simulator's origin
        truth_file = None if way == "direct" else os.path.join(work, f"truth-{way}-{seed}.csv")
        run_dir, _ = fly(tern, way, seed, duration, os.path.join(work, f"track-{way}-{seed}"), truth_file)
        window = checked(run_dir, duration)["metrics"]["window_start_s"]  # FlightMetrics': the first loop flown
        runs[way] = run_dir
        rows, origin = truth_of(way, run_dir, truth_file, origin)
        figures[way] = tracking(run_dir, rows, origin, window)
        figures[way]["gnss_vs_truth_rms_m"] = gnss_vs_truth(run_dir, rows, origin)
        if figures[way]["gnss_vs_truth_rms_m"] > 10.0:
            sys.exit(f"bench_fcu_sil: {way} seed {seed}: fixes {figures[way]['gnss_vs_truth_rms_m']:.1f} m RMS from the truth: "
                     "the truth's origin is not the simulator's")
        if way == "firmware":
            link = link_figures(run_dir)
        print(f"  seed {seed} {way:9} xt RMS {figures[way]['xt_rms_m']:.3f} m, alt RMS {figures[way]['alt_rms_m']:.3f} m",
              flush=True)
    return figures, link, runs


def topic_digests(run_dir):
    d = os.path.join(run_dir, "topics")
    out = {}
    for name in sorted(os.listdir(d)):
        with open(os.path.join(d, name), "rb") as f:
            out[name] = hashlib.sha256(f.read()).hexdigest()
    return out


def same_topics(run_dirs):
    """Byte-identical topics/*.csv across flights: (yes/no, the files that differ)."""
    digests = [topic_digests(r) for r in run_dirs]
    names = sorted(set().union(*digests))
    differ = [n for n in names if len({d.get(n) for d in digests}) != 1]
    return {"identical": not differ, "files": len(names), "differing": differ}


def flown_param(run_dir, key):
    """A parameter's value as flown (the run's config.yaml), or None."""
    with open(os.path.join(run_dir, "config.yaml")) as f:
        m = re.search(rf"^\s+{key}:\s*(\S+)", f.read(), re.M)
    return m.group(1) if m else None


def speed(tern, way, seed, duration, repeats, cpu, work):
    """Pinned flights: wall s per flight (measured around `tern fly`; timing.json's wall_s beside
    it) and the CPU s of tern and its FCU program together (user + sys)."""
    out = []
    for i in range(repeats):
        before = os.times()
        run_dir, wall = fly(tern, way, seed, duration, os.path.join(work, f"speed-{way}-{i}"), pin=cpu)
        after = os.times()
        checked(run_dir, duration)
        with open(os.path.join(run_dir, "timing.json")) as f:
            timing = json.load(f)
        out.append({"run_dir": run_dir, "wall_s": wall, "tern_wall_s": timing["wall_s"],
                    "cpu_user_s": after.children_user - before.children_user,
                    "cpu_sys_s": after.children_system - before.children_system,
                    "flight_thread_cpu_s": timing.get("flight_thread_cpu_s")})
    walls = [r["wall_s"] for r in out]
    med = statistics.median(walls)
    return {"runs": out, "emulator_link": flown_param(out[0]["run_dir"], "emulator_link"), "median_wall_s": med,
            "x_real_time": duration / med,
            "x_real_time_tern_wall": duration / statistics.median(r["tern_wall_s"] for r in out)}


def aggregate(per_seed):
    """per way and figure: mean over seeds and the worst seed (largest value)."""
    out = {}
    for way in WAYS:
        out[way] = {}
        for m in METRICS:
            vals = {s: per_seed[s][way][m] for s in per_seed}
            worst = max(vals, key=vals.get)
            out[way][m] = {"mean": statistics.mean(vals.values()), "worst": vals[worst], "worst_seed": worst}
    ratio = {m: {k: out["firmware"][m][k] / out["direct"][m][k] for k in ("mean", "worst")} for m in METRICS}
    for m in METRICS:
        ratio[m]["within_20pct"] = ratio[m]["mean"] <= TARGET_RATIO
    return out, ratio


def print_tracking(agg, ratio, seeds):
    print(f"\nTracking: the truth vs the commanded path in cruise, after the first loop, seeds {seeds} "
          "(m; mean over seeds / worst seed)")
    print(f"{'':16}" + "".join(f"{w:>22}" for w in WAYS) + f"{'firmware/direct':>22}")
    for m in METRICS:
        cells = "".join(f"{agg[w][m]['mean']:9.3f} / {agg[w][m]['worst']:6.3f} s{agg[w][m]['worst_seed']:<2}" for w in WAYS)
        r = ratio[m]
        flag = "ok" if r["within_20pct"] else "MISS"
        print(f"{m:16}{cells}{r['mean']:10.2f} / {r['worst']:5.2f} {flag:>4}")
    print(f"target: firmware/direct (mean over seeds) <= {TARGET_RATIO}")


def print_link(link, determinism):
    print("\nLink of the firmware flights (summary.json, timing.json)")
    keys = ["fcu_frames", "fcu_seq_gaps", "fcu_bad_crc", "fcu_bad_length", "fcu_unknown_id", "fcu_skipped_bytes",
            "fcu_link_losses", "fcu_lockstep_resends", "fcu_commands_sent"]
    print(f"{'flight':28}" + "".join(f"{k[4:]:>17}" for k in keys))
    for name, fig in link.items():
        print(f"{name:28}" + "".join(f"{fig[k]:17.0f}" for k in keys))
    for name, d in determinism.items():
        print(f"determinism, {name}: {'yes' if d['identical'] else 'NO'} ({d['files']} topics/*.csv files"
              + (f"; differing: {', '.join(d['differing'])})" if d["differing"] else ")"))


def print_speed(spd, duration, cpu):
    print(f"\nSpeed: {duration:g} s flights pinned to CPU {cpu} (taskset), median of {len(spd['direct']['runs'])}")
    print(f"{'way':10}{'wall s':>10}{'x real time':>14}{'cpu user s':>12}{'cpu sys s':>11}{'tern thread cpu s':>19}  link")
    for way, s in spd.items():
        runs = s["runs"]
        med = lambda k: statistics.median(r[k] for r in runs)
        print(f"{way:10}{s['median_wall_s']:10.2f}{s['x_real_time']:14.1f}{med('cpu_user_s'):12.2f}{med('cpu_sys_s'):11.2f}"
              f"{med('flight_thread_cpu_s'):19.2f}  {s['emulator_link'] or '-'}")
    print(f"target: firmware >= {TARGET_SPEED:g}x real time on one core (the FCU flights: tern and the FCU program on it)")


def machine():
    model = ""
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    return {"cpu": model, "cores": os.cpu_count(), "kernel": platform.release(), "python": platform.python_version(),
            "load_average": os.getloadavg()}


def git_commit():
    head = subprocess.run(["git", "-C", REPO, "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
    dirty = subprocess.run(["git", "-C", REPO, "status", "--porcelain", "--untracked-files=no"], capture_output=True,
                           text=True).stdout.strip()
    return {"commit": head, "tracked_files_modified": bool(dirty)}


def determinism_check(tern, seed, duration, first_run, work):
    """The firmware flight of `seed` flown again: topics/*.csv and the truth byte for byte."""
    truth = os.path.join(work, f"truth-firmware-{seed}-again.csv")
    again, _ = fly(tern, "firmware", seed, duration, os.path.join(work, f"again-firmware-{seed}"), truth)
    out = same_topics([first_run, again])
    with open(truth, "rb") as a, open(os.path.join(work, f"truth-firmware-{seed}.csv"), "rb") as b:
        out["truth_identical"] = a.read() == b.read()
    return out


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("bin_dir", nargs="?", default=os.path.join(REPO, "build", "bin"), help="directory of tern (default build/bin)")
    ap.add_argument("--seeds", default="1,2,3,4,5", help="tracking seeds, comma-separated (at least 3)")
    ap.add_argument("--duration", type=float, default=700.0, help="s of each tracking flight (default.yaml's 700)")
    ap.add_argument("--speed-duration", type=float, default=120.0, help="s of each speed flight")
    ap.add_argument("--speed-repeats", type=int, default=3)
    ap.add_argument("--cpu", type=int, default=1, help="the core the speed flights are pinned to")
    ap.add_argument("--out", default=os.path.join(HERE, "results", "fcu_sil.json"))
    ap.add_argument("--keep", help="fly into this directory and keep it (default: a temporary one, removed)")
    a = ap.parse_args()
    a.seeds = [int(s) for s in a.seeds.split(",")]
    if len(a.seeds) < 3:
        ap.error("--seeds: at least 3")
    a.tern = os.path.join(os.path.abspath(a.bin_dir), "tern")
    if not os.access(a.tern, os.X_OK):
        ap.error(f"{a.tern}: no tern binary (build it: cmake --build BUILD_DIR)")
    return a


def main():
    a = parse_args()
    a.git = git_commit()  # the tree the flights start from
    work = os.path.abspath(a.keep) if a.keep else tempfile.mkdtemp(prefix="bench_fcu_sil-")
    os.makedirs(work, exist_ok=True)
    per_seed, link, track_runs = {}, {}, {}
    print(f"tracking flights, {a.duration:g} s, seeds {a.seeds}", flush=True)
    for seed in a.seeds:
        per_seed[seed], link[f"tracking, seed {seed}"], track_runs[seed] = track_seed(a.tern, seed, a.duration, work)
    agg, ratio = aggregate(per_seed)
    s0 = a.seeds[0]
    determinism = {f"seed {s0}, {a.duration:g} s, flown twice": determinism_check(a.tern, s0, a.duration, track_runs[s0]["firmware"],
                                                                               work)}
    run_dir, _ = fly(a.tern, "firmware", s0, a.duration, os.path.join(work, "as-configured"), as_configured=True)
    link[f"default_sil.yaml, seed {s0}"] = link_figures(run_dir)
    print("speed flights", flush=True)
    spd = {way: speed(a.tern, way, s0, a.speed_duration, a.speed_repeats, a.cpu, work) for way in WAYS}
    determinism[f"speed flights, {a.speed_repeats} x {a.speed_duration:g} s"] = same_topics(
        [r["run_dir"] for r in spd["firmware"]["runs"]])
    print_tracking(agg, ratio, a.seeds)
    print_link(link, determinism)
    print_speed(spd, a.speed_duration, a.cpu)
    write_results(a, per_seed, agg, ratio, link, determinism, spd)
    if not a.keep:
        shutil.rmtree(work)


def write_results(a, per_seed, agg, ratio, link, determinism, spd):
    for s in spd.values():
        for r in s["runs"]:
            r.pop("run_dir")
    out = {
        "bench": "bench/bench_fcu_sil.py", "issue": 40, "date_utc": time.strftime("%Y-%m-%dT%H:%M:%SZ", time.gmtime()),
        "git": a.git, "machine": machine(), "tern": a.tern,
        "seeds": a.seeds, "tracking_duration_s": a.duration, "speed_duration_s": a.speed_duration,
        "speed_repeats": a.speed_repeats, "speed_cpu": a.cpu,
        "flights": {w: {"config": "configs/missions/" + WAYS[w], "set": fcu_settings(w, "TRUTH.csv")[1::2]} for w in WAYS},
        "notes": ["same world for the three: init heading 2.3562 rad, wind 3.5355,-3.5355,0 m/s, light turbulence, pitot "
                  "covered until 8.5 s, the same seed",
                  "sensors: realistic for direct and firmware; the emulator has only its own (sim::SensorParams defaults)",
                  "FCU flights without the pilot's events: emulator_rc = the arming steps, no --companion-silence",
                  "tracking: the truth, cruise phase from the end of the first loop (FlightMetrics' window_start_s), 50 Hz; "
                  "horizontal in the estimator's frame (by the origins' latitude/longitude), height above the takeoff "
                  "point against h_c",
                  "speed: the FCU flights run tern and the FCU program on the one pinned core"],
        "tracking": {"per_seed": {str(s): v for s, v in per_seed.items()}, "summary": agg, "firmware_over_direct": ratio,
                     "target_ratio": TARGET_RATIO},
        "link": link, "determinism": determinism,
        "speed": spd, "target_x_real_time": TARGET_SPEED,
    }
    os.makedirs(os.path.dirname(os.path.abspath(a.out)), exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(out, f, indent=1, sort_keys=False)
        f.write("\n")
    print(f"\nwrote {a.out}")


if __name__ == "__main__":
    main()
