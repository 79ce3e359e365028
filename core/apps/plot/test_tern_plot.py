#!/usr/bin/env python3
"""Tests of tern-plot: run as `python3 core/apps/plot/test_tern_plot.py` (plain unittest).

Writes small synthetic run directories (the layout of core/host/record/flight_log.hpp) into a temp
dir, runs tern-plot on them as a user would, and checks the figures, the printed list and
the errors; also checks the pieces a wrong figure would come from (the YAML reader,
ROSplane mission files, lat/lon -> NED, angle errors across +-pi, commanded path segments).
With test_plot_pages.py's: index.html's order, course.png wrapped, the A/B differences.
"""

import importlib.machinery
import importlib.util
import json
import math
import os
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest

try:
    import numpy as np  # noqa: F401  (the plotting module's functions are tested in-process)
except ImportError:  # a pyenv/venv python3 first on PATH: Debian's has python3-numpy
    if os.path.exists("/usr/bin/python3") and not os.environ.get("TERN_PLOT_TEST_REEXEC"):
        os.environ["TERN_PLOT_TEST_REEXEC"] = "1"
        # the script run (test_plot_flight.py imports this module), not necessarily this file
        os.execv("/usr/bin/python3", ["/usr/bin/python3", os.path.abspath(sys.argv[0])] + sys.argv[1:])
    raise

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPT = os.path.join(HERE, "tern-plot")
FIGURES = ["ground_track.png", "altitude.png", "airspeed.png", "course.png", "roll_pitch.png",
           "actuators.png", "estimation_errors.png"]
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def load_module():
    loader = importlib.machinery.SourceFileLoader("tern_plot", SCRIPT)
    spec = importlib.util.spec_from_loader("tern_plot", loader)
    mod = importlib.util.module_from_spec(spec)
    loader.exec_module(mod)
    return mod


TP = load_module()  # it puts its modules (tern_plot_*.py, beside it) on sys.path
import tern_plot_log as TL  # noqa: E402
import tern_plot_mission as TM  # noqa: E402
import tern_plot_yaml as TY  # noqa: E402
import tern_plot_angles as TA  # noqa: E402
import tern_plot_draw as TDraw  # noqa: E402
import tern_plot_errors as TErrors  # noqa: E402
import tern_plot_track as TTrack  # noqa: E402

STATE_HEADER = ["t [s]", "stamp [ns]", "p_n [m]", "p_e [m]", "p_d [m]", "u [m/s]", "v [m/s]", "w [m/s]",
                "phi [rad]", "theta [rad]", "psi [rad]", "Va [m/s]", "alpha [rad]", "chi [rad]",
                "origin_lat [deg]", "origin_lon [deg]", "origin_alt [m]", "origin_valid [bool]", "valid [bool]",
                "w_n [m/s]", "w_e [m/s]"]

ORIGIN = (40.2463724, -111.6474138, 1387.0)
R_ORBIT = 100.0
VA = 17.0


# definitions.json as the host writes it (core/host/record/log_definitions.hpp; test_plot_flight
# reads a real flight's): the synthetic runs' codes mean what a flight's mean
DEFINITIONS = {"phase": {"0": "takeoff", "1": "climb", "2": "cruise", "3": "landing", "4": "loiter", "5": "preflight",
                         "6": "approach", "7": "flare", "8": "rollout", "9": "stopped"},
               "item_type": {"0": "waypoint", "1": "loiter", "2": "return_home", "3": "land"},
               "land_item": {"glide_slope": 0.0873, "flare_height": 4.0, "decision_height": 12.0, "min_entry_heights": 2.0}}


def write_definitions(run, definitions=None):
    with open(os.path.join(run, "definitions.json"), "w") as f:
        json.dump(DEFINITIONS if definitions is None else definitions, f)


def write_csv(path, header, rows):
    with open(path, "w") as f:
        f.write(",".join(header) + "\n")
        for r in rows:
            f.write(",".join(repr(float(x)) for x in r) + "\n")


def write_run(run, topics=("state", "truth", "controller_command", "controller_internals", "current_path",
                           "flight_phase", "waypoints", "actuators"), config=True, duration=60.0, rate=50.0):
    """A clockwise orbit of R_ORBIT about the origin, climbing to 50 m, course past +-180 deg."""
    os.makedirs(os.path.join(run, "topics"))
    n = int(duration * rate) + 1
    omega = VA / R_ORBIT
    state_rows, truth_rows = [], []
    for k in range(n):
        t = k / rate
        ang = omega * t                        # clockwise seen from above: north -> east
        p_n, p_e = R_ORBIT * math.cos(ang), R_ORBIT * math.sin(ang)
        h = 50.0 * min(1.0, t / 20.0)
        chi = math.atan2(math.sin(ang + math.pi / 2), math.cos(ang + math.pi / 2))
        phi, theta = 0.4, 0.05 * math.sin(0.3 * t)
        truth_rows.append([t, t * 1e9, p_n, p_e, -h, VA, 0, 0, phi, theta, chi, VA, 0.05, chi,
                           ORIGIN[0], ORIGIN[1], ORIGIN[2], 1, 1, 3.5, -3.5])
        valid = 1 if t >= 1.0 else 0          # the estimator initialises after 1 s
        e = 0.5 * math.sin(0.5 * t)
        state_rows.append([t, t * 1e9, p_n + e, p_e - e, -h + e, VA, 0, 0, phi + 0.01, theta - 0.01,
                           chi + 0.02, VA + e, 0.05, chi + 0.02, ORIGIN[0], ORIGIN[1], ORIGIN[2], 1, valid,
                           3.4, -3.4])
    tp = os.path.join(run, "topics")
    if "state" in topics:
        write_csv(os.path.join(tp, "state.csv"), STATE_HEADER, state_rows)
    if "truth" in topics:
        write_csv(os.path.join(tp, "truth.csv"), STATE_HEADER, truth_rows)
    if "controller_command" in topics:
        write_csv(os.path.join(tp, "controller_command.csv"),
                  ["t [s]", "stamp [ns]", "Va_c [m/s]", "h_c [m]", "chi_c [rad]", "phi_ff [rad]"],
                  [[r[0], r[1], VA, 50.0, r[13] + 0.1, 0.4] for r in truth_rows])
    if "controller_internals" in topics:
        write_csv(os.path.join(tp, "controller_internals.csv"),
                  ["t [s]", "stamp [ns]", "phi_c [rad]", "theta_c [rad]", "delta_t_c []", "alt_zone [enum]"],
                  [[r[0], r[1], 0.42, 0.0, 0.6, 2] for r in truth_rows])
    if "current_path" in topics:
        hdr = ["t [s]", "stamp [ns]", "path_type [enum]", "Va_d [m/s]", "r_n [m]", "r_e [m]", "r_d [m]",
               "q_n []", "q_e []", "q_d []", "c_n [m]", "c_e [m]", "c_d [m]", "rho [m]", "lambda []",
               "waypoint_index []"]
        rows = []
        for r in truth_rows:
            if r[0] < 10.0:   # a line north from the origin, then the orbit
                rows.append([r[0], r[1], 1, VA, 0, 0, -50, 1, 0, 0, 0, 0, 0, 0, 1, 0])
            else:
                rows.append([r[0], r[1], 0, VA, 0, 0, 0, 1, 0, 0, 0, 0, -50, R_ORBIT, 1, 1])
        write_csv(os.path.join(tp, "current_path.csv"), hdr, rows)
    if "flight_phase" in topics:
        write_csv(os.path.join(tp, "flight_phase.csv"),
                  ["t [s]", "stamp [ns]", "phase [enum]", "previous [enum]", "since [ns]"],
                  [[0, 0, 0, 0, 0], [3, 3e9, 1, 0, 3e9], [20, 20e9, 2, 1, 20e9]])
    if "actuators" in topics:   # the aileron at slc's max_a from 30 s to 40 s
        write_csv(os.path.join(tp, "actuators.csv"),
                  ["t [s]", "stamp [ns]", "delta_a [rad]", "delta_e [rad]", "delta_r [rad]", "delta_t []"],
                  [[r[0], r[1], 0.5 if 30.0 <= r[0] < 40.0 else 0.1, -0.1, 0.0, 0.6] for r in truth_rows])
        write_csv(os.path.join(run, "params.csv"), ["t [s]", "parameter", "value", "source"], [])
        with open(os.path.join(run, "params.csv"), "a") as f:
            f.write("0,slc.max_a,0.5,config\n0,slc.max_e,0.61,default\n0,slc.max_r,0.523,default\n"
                    "0,slc.min_t,0,default\n0,slc.max_t,1,default\n0,phase_machine.max_deflection,0.7,default\n")
        write_definitions(run)
        with open(os.path.join(run, "summary.json"), "w") as f:
            f.write('{"phases": [{"phase": "takeoff", "start_s": 0.0, "reason": "r"}], "controller_handovers": '
                    '[{"t_s": 0.0, "from": "(none)", "to": "slc", "reason": "phase takeoff"}], "failsafes": [], '
                    '"metrics": {"window_start_s": null}}')
    if "waypoints" in topics:
        write_csv(os.path.join(tp, "waypoints.csv"),
                  ["t [s]", "stamp [ns]", "revision []", "count []", "loop [bool]"], [[0, 0, 1, 4, 1]])
    if config:
        with open(os.path.join(run, "config.yaml"), "w") as f:
            f.write("# resolved from /nonexistent/configs/missions/synthetic.yaml\n"
                    "name: synthetic\nseed: 1\nduration: 60\n"
                    "plugins:\n  - name: sim\n    plugin: sim_aero\n    rate: 400\n"
                    "    params:\n      wind: [3.5, -3.5, 0]\n      gusts: []\n      aircraft: \"\"\n"
                    "  - name: planner\n    plugin: path_planner\n    rate: 10\n    params:\n"
                    "      mission_file: \"\"\n"
                    "phases: {takeoff: slc, climb: slc, cruise: slc}\n"
                    "mission:\n  loop: true\n  waypoints:\n"
                    "    - [100, 0, -50]\n"
                    "    - {ned: [0, 100, -50], Va_d: 17}\n"
                    "    - ned: [-100, 0, -50]   # block map entry\n"
                    "      Va_d: 17\n"
                    f"    - {{lla: [{ORIGIN[0]}, {ORIGIN[1] - 0.0011}, {ORIGIN[2] + 50}]}}\n")


# A landing (heading east, touchdown point at the origin; along = east, across = -north): at rest,
# a first approach that goes around at the decision height, the second flown to a stop.
LAND_GS, LAND_HEADING, LAND_ENTRY = 0.0873, math.pi / 2, 40.0
LAND_PHASES = [(0.0, 5, "preflight"), (10.0, 0, "takeoff"), (12.0, 1, "climb"), (20.0, 2, "cruise"),
               (30.0, 6, "approach"), (51.3, 1, "climb"), (60.0, 2, "cruise"), (80.0, 6, "approach"),
               (107.4, 7, "flare"), (111.0, 8, "rollout"), (120.0, 9, "stopped")]
ITEM_HEADER = ["t [s]", "stamp [ns]", "revision []", "index []", "w_0 [m|deg]", "w_1 [m|deg]", "w_2 [m|deg]",
               "lla [bool]", "chi_d [rad]", "use_chi [bool]", "Va_d [m/s]", "type [enum]", "loiter_radius [m]",
               "loiter_direction []", "loiter_time [s]", "loiter_turns []"]
LAND_FIELDS = ["land_glide_slope [rad]", "land_flare_height [m]", "land_decision_height [m]"]


def landing_position(t):
    """(along, height above the touchdown point) of the synthetic landing at time t."""
    length = LAND_ENTRY / math.tan(LAND_GS)
    if t < 30.0:
        return (0.0, 0.0) if t < 10.0 else (-length - 300.0, LAND_ENTRY)
    if t < 60.0:  # the first approach, 2 m high; the go-around at 51.3 s climbs out
        along = -length + 15.0 * (t - 30.0)
        climb = 3.0 * max(0.0, t - 51.3)
        return along, -along * math.tan(LAND_GS) + 2.0 + climb
    if t < 80.0:
        return -length - 300.0, LAND_ENTRY
    along = -length + 15.0 * (t - 80.0)  # the second approach; the flare at 107.4 s, on the wheels at 111 s
    if t < 107.4:
        return along, -along * math.tan(LAND_GS)
    if t < 111.0:
        return along, 4.0 * (111.0 - t) / 3.6
    return 7.8 + 48.0 * (1.0 - math.exp(-(t - 111.0) / 3.0)), 0.0  # rolled out, stopped 56 m beyond


def write_landing_run(run, land_item=True, approached=True):
    """A run directory with the synthetic landing (truth 1 m north of the estimate, which is 0.3 m low)."""
    os.makedirs(os.path.join(run, "topics"))
    tp = os.path.join(run, "topics")
    phases = [p for p in LAND_PHASES if approached or p[0] < 30.0]
    truth, state, path = [], [], []
    for k in range(int(125.0 * 20) + 1):
        t = k / 20.0
        along, h = landing_position(t)
        row = [t, t * 1e9, -0.5 * math.sin(0.1 * t), along, -h, 15, 0, 0, 0, 0.05, LAND_HEADING, 15, 0.05,
               LAND_HEADING, ORIGIN[0], ORIGIN[1], ORIGIN[2], 1, 1, 0, 0]
        truth.append(row)
        state.append([t, t * 1e9, row[2] + 1.0, along, -h + 0.3] + row[5:])
        land = approached and (30.0 <= t < 51.3 or t >= 80.0)
        q = (0.0, math.cos(LAND_GS), math.sin(LAND_GS))
        path.append([t, t * 1e9, 1, 15, 0, 0, 0, *q, 0, 0, 0, 0, 1, 1, int(land), 4, 12, 1 + (t >= 80.0)])
    write_csv(os.path.join(tp, "truth.csv"), STATE_HEADER, truth)
    write_csv(os.path.join(tp, "state.csv"), STATE_HEADER, state)
    write_csv(os.path.join(tp, "current_path.csv"),
              ["t [s]", "stamp [ns]", "path_type [enum]", "Va_d [m/s]", "r_n [m]", "r_e [m]", "r_d [m]", "q_n []",
               "q_e []", "q_d []", "c_n [m]", "c_e [m]", "c_d [m]", "rho [m]", "lambda []", "waypoint_index []",
               "landing [bool]", "flare_height [m]", "decision_height [m]", "attempt []"], path)
    write_csv(os.path.join(tp, "flight_phase.csv"), ["t [s]", "stamp [ns]", "phase [enum]", "previous [enum]", "since [ns]"],
              [[t, t * 1e9, code, 0, t * 1e9] for t, code, _ in phases])
    items = [[0, 0, 1, 0, 0, -800, -LAND_ENTRY, 0, 0, 0, 17, 0, 0, 1, 0, 0, 0.0873, 4, 12]]
    if land_item:
        items.append([0, 0, 1, 1, 0, 0, 0, 0, LAND_HEADING, 0, 15, 3, 0, 1, 0, 0, LAND_GS, 4, 12])
    write_csv(os.path.join(tp, "waypoints_items.csv"), ITEM_HEADER + LAND_FIELDS, items)
    aim_n = truth[200][2]  # metrics.landing: about the truth at rest (10 s) plus the item's offset
    landing = {"touchdown_t_s": 111.0, "touchdown_along_m": 7.8, "touchdown_across_m": -(truth[2220][2] - aim_n),
               "sink_rate_mps": 1.11, "rollout_m": 48.0, "stopped": True} if approached else None
    write_definitions(run)
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"phases": [{"phase": name, "start_s": t, "reason": "r"} for t, _, name in phases],
                   "controller_handovers": [], "failsafes": [],
                   "instances": {"manager": {"plugin": "path_manager", "home_altitude_m": 0.0}},
                   "metrics": {"window_start_s": None, **({"landing": landing} if landing else {})}}, f)


def run_plot(*args):
    return subprocess.run([SCRIPT, *args], capture_output=True, text=True, timeout=300)


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    if head[:8] != PNG_SIGNATURE or head[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", head[16:24])


class TernPlotRuns(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="tern_plot_test_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_full_run_writes_every_figure_and_lists_them(self):
        run = os.path.join(self.tmp, "20260101T000000Z-synthetic")
        write_run(run)
        r = run_plot("--strict", run)   # strict: any missing topic/field/waypoint would be exit 1
        self.assertEqual(r.returncode, 0, r.stderr)
        plots = os.path.join(run, "plots")
        out = r.stdout.strip().splitlines()
        for name in FIGURES:
            path = os.path.join(plots, name)
            self.assertTrue(os.path.isfile(path), name)
            size = png_size(path)
            self.assertIsNotNone(size, f"{name} is not a PNG")
            self.assertGreater(size[0], 500, name)
            self.assertGreater(size[1], 300, name)
            self.assertGreater(os.path.getsize(path), 10000, name)
            self.assertIn(path, out)
        self.assertEqual(out[-1], f"plots: {plots}/")
        self.assertNotIn("note:", r.stdout)   # every topic present, waypoints readable
        self.assertEqual(r.stderr, "")
        # a run without tune tables or a land item: no tune.png, no landing.png, and no note about either
        self.assertFalse(os.path.exists(os.path.join(plots, "tune.png")))
        self.assertFalse(os.path.exists(os.path.join(plots, "landing.png")))

    def test_a_tune_run_gets_tune_png(self):   # a plain run gets none: test_full_run_writes_every_figure_and_lists_them
        run = os.path.join(self.tmp, "tune")
        write_run(run)
        t = [40.0 + 0.01 * k for k in range(600)]
        cmd = [0.1 if x >= 43.0 else -0.1 for x in t]
        write_csv(os.path.join(run, "tune.csv"), ["t [s]", "phi_c [rad]", "phi [rad]"],
                  [(x, c, c * (1.0 - math.exp(-(x - 43.0) / 0.2)) if x >= 43.0 else c) for x, c in zip(t, cmd)])
        write_csv(os.path.join(run, "tune_steps.csv"),
                  ["t [s]", "from", "to", "rise_time [s]", "overshoot [%]", "settling_time [s]", "steady_state_error",
                   "y0", "y_final"], [(43.0, -0.1, 0.1, 0.44, 0.0, 0.78, 0.0, -0.1, 0.1)])
        r = run_plot("--strict", run)
        self.assertEqual(r.returncode, 0, r.stderr)
        path = os.path.join(run, "plots", "tune.png")
        self.assertIn(path, r.stdout.splitlines())
        self.assertIsNotNone(png_size(path))

    def test_a_landing_gets_landing_png_with_its_markers(self):
        run = os.path.join(self.tmp, "landing")
        write_landing_run(run)
        r = run_plot(run)
        self.assertEqual(r.returncode, 0, r.stderr)
        path = os.path.join(run, "plots", "landing.png")
        self.assertIn(path, r.stdout.splitlines())
        size = png_size(path)
        self.assertIsNotNone(size)
        self.assertGreater(size[0], 1000)
        self.assertFalse([ln for ln in r.stdout.splitlines() if "note:" in ln and "landing" in ln], r.stdout)
        with open(os.path.join(run, "plots", "figures.json")) as f:
            fig = {x["file"]: x for x in json.load(f)}["landing.png"]
        self.assertEqual(fig["markers"], ["approach 1", "go-around 1", "approach 2", "flare", "rollout", "stopped",
                                          "touchdown", "stop"])
        legend = " ".join(fig["legend"])
        for text in ("planned glide path (5.0 deg from the entry, 457 m short, 40 m up)", "flare height 4 m",
                     "decision height 12 m", "touchdown t 111.0 s (metrics.landing, truth): +7.8 m along",
                     "sink 1.11 m/s", "true, approach 2 (last)", "estimated, approach 1 (went around)",
                     "stopped (true), rollout 48 m", "runway centre line (heading 90 deg)"):
            self.assertIn(text, legend)
        # the touchdown point on the field: the truth's last sample at rest plus the item's offset
        self.assertIn("touchdown point on the field (truth at rest + item; -0.0 m along, +0.4 m across)", legend)
        self.assertIn("runway's frame", fig["caption"])
        with open(os.path.join(run, "plots", "index.html")) as f:
            self.assertIn('<img src="landing.png"', f.read())

    def test_no_landing_figure_without_a_land_item_or_an_approach(self):
        # a plain run (no land item: nothing to say, no note): test_full_run_writes_every_figure_and_lists_them
        run = os.path.join(self.tmp, "no_land_item")
        write_landing_run(run, land_item=False, approached=False)
        r = run_plot(run)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertFalse(os.path.exists(os.path.join(run, "plots", "landing.png")))
        self.assertNotIn("landing", r.stdout)
        with open(os.path.join(run, "plots", "figures.json")) as f:
            self.assertNotIn("landing.png", [x["file"] for x in json.load(f)])
        run = os.path.join(self.tmp, "never_approached")
        write_landing_run(run, approached=False)
        r = run_plot(run)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertFalse(os.path.exists(os.path.join(run, "plots", "landing.png")))
        notes = [ln for ln in r.stdout.splitlines() if "landing" in ln]
        self.assertEqual(notes, ["tern plot: note: landing.png not drawn: the land item (topics/waypoints_items.csv) "
                                 "was never approached: no approach phase"])

    def test_missing_topics_are_skipped_with_a_note(self):
        run = os.path.join(self.tmp, "run")
        write_run(run, topics=("state", "controller_command"), config=False)
        cc = os.path.join(run, "topics", "controller_command.csv")
        with open(cc) as f:
            rows = [ln.rstrip("\n").split(",") for ln in f]
        with open(cc, "w") as f:   # a log without chi_c
            f.writelines(",".join(r[:4] + r[5:]) + "\n" for r in rows)
        r = run_plot(run)
        self.assertEqual(r.returncode, 0, r.stderr)
        plots = os.path.join(run, "plots")
        for name in ("ground_track.png", "altitude.png", "airspeed.png", "course.png", "roll_pitch.png"):
            self.assertIsNotNone(png_size(os.path.join(plots, name)), name)
        self.assertFalse(os.path.exists(os.path.join(plots, "estimation_errors.png")))
        notes = [ln for ln in r.stdout.splitlines() if "note:" in ln]
        for what in ("truth.csv", "controller_internals.csv", "current_path.csv", "flight_phase.csv",
                     "config.yaml", "estimation_errors.png", "chi_c"):
            self.assertEqual(sum(what in ln for ln in notes), 1, f"one note about {what}: {notes}")
        self.assertEqual(r.stderr, "")
        r = run_plot(run, "--strict")
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn("--strict", r.stderr)

    def test_a_partial_last_line_is_dropped_with_one_note(self):
        # a flight killed while writing: the last row lacks its line end, and its last value
        # ("-3.5" cut to "-3.") still has every column, so only the missing line end tells
        run = os.path.join(self.tmp, "killed")
        write_run(run)
        state = os.path.join(run, "topics", "state.csv")
        with open(state) as f:
            rows = f.read().splitlines()
        with open(state, "a") as f:
            f.write(rows[-1][:-1])
        r = run_plot(run)
        self.assertEqual(r.returncode, 0, r.stderr)
        notes = [ln for ln in r.stdout.splitlines() if "note:" in ln]
        self.assertEqual(notes, ["tern plot: note: topics/state.csv: the last line is partial "
                                 "(no line end: the flight was cut off while writing it): dropped"])
        self.assertIsNotNone(png_size(os.path.join(run, "plots", "ground_track.png")))
        TL.NOTES.clear()
        topic = TL.read_topic(run, "state", ["w_e"])
        self.assertEqual(len(topic), len(rows) - 1)
        self.assertEqual(topic.get("w_e")[-1], float(rows[-1].split(",")[-1]))

    def test_missing_run_dir_is_one_error_line_and_exit_1(self):
        missing = os.path.join(self.tmp, "no_such_run")
        r = run_plot(missing)
        self.assertEqual(r.returncode, 1)
        self.assertEqual(r.stdout, "")
        lines = r.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, r.stderr)
        self.assertIn(missing, lines[0])
        self.assertIn("error", lines[0])

    def test_directory_without_a_log_is_refused(self):
        empty = os.path.join(self.tmp, "empty")
        os.makedirs(empty)
        r = run_plot(empty)
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn("not a tern run directory", r.stderr)
        self.assertFalse(os.path.exists(os.path.join(empty, "plots")))
        r = run_plot()
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn("usage", r.stderr)


class Pieces(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="tern_plot_test_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_yaml_as_tern_reads_it(self):
        doc = TY.yaml_load(
            "# resolved from /x/y.yaml\nname: demo   # comment\nseed: 42\nlog: {dir: runs, topics: all}\n"
            "plugins:\n  - name: sim\n    params:\n      wind: [3.5, -3.5e-1, 0]\n      gusts: []\n"
            "      label: \"a # b\"\n  - {name: ekf, trigger: imu}\nlist:\n- 1\n- two\n"
            "flag: False\nnothing:\nwps: [[1, 2, 3],\n      [4, 5, 6]]\nrate: 1e-3\n")
        self.assertEqual(doc["name"], "demo")
        self.assertEqual(doc["seed"], 42)
        self.assertEqual(doc["log"], {"dir": "runs", "topics": "all"})
        self.assertEqual(doc["plugins"][0]["params"], {"wind": [3.5, -0.35, 0], "gusts": [], "label": "a # b"})
        self.assertEqual(doc["plugins"][1], {"name": "ekf", "trigger": "imu"})
        self.assertEqual(doc["list"], [1, "two"])
        self.assertIs(doc["flag"], False)
        self.assertIsNone(doc["nothing"])
        self.assertEqual(doc["wps"], [[1, 2, 3], [4, 5, 6]])
        self.assertEqual(doc["rate"], 0.001)  # YAML 1.2's float, as yaml-cpp reads it
        with self.assertRaises(TY.YamlError):
            TY.yaml_load("a: [1, 2\n")

    def test_rosplane_mission_keeps_every_repeated_wp(self):
        text = "".join(f"wp:\n  w: [{n}, {e}, -70.0]\n  chi_d: 1.1518\n  lla: False\n  use_chi: False\n"
                       f"  va_d: 17.0\n" for n, e in ((400, -250), (-400, -50), (-400, -250), (400, -50)))
        wps, loop = TM.parse_mission_text(text)
        self.assertTrue(loop)
        self.assertEqual([w for w, _ in wps], [[400, -250, -70], [-400, -50, -70], [-400, -250, -70],
                                               [400, -50, -70]])
        self.assertFalse(any(is_lla for _, is_lla in wps))

    def test_mission_file_is_relative_to_the_original_config(self):
        cfg_dir = os.path.join(self.tmp, "configs", "missions")
        os.makedirs(cfg_dir)
        with open(os.path.join(cfg_dir, "hourglass.yaml"), "w") as f:
            f.write("wp:\n  w: [400.0, -250.0, -70.0]\n  lla: False\nwp:\n  w: [-400.0, -50.0, -70.0]\n"
                    "wp:\n  w: [40.2463724, -111.6474138, 1457.0]\n  lla: True\n")
        run = os.path.join(self.tmp, "run")
        os.makedirs(run)
        with open(os.path.join(run, "config.yaml"), "w") as f:
            f.write(f"# resolved from {cfg_dir}/mine.yaml\nname: x\nmission:\n  file: hourglass.yaml\n")
        wps, loop = TM.mission_waypoints(run, None, None)  # no state: origin from nowhere
        self.assertTrue(loop)
        self.assertEqual(wps.tolist(), [[400, -250, -70], [-400, -50, -70]])  # the lla one needs an origin
        state = TL.Topic("state", {"t": np.array([0.0, 1.0]), "origin_lat": np.array([0.0, ORIGIN[0]]),
                                   "origin_lon": np.array([0.0, ORIGIN[1]]),
                                   "origin_alt": np.array([0.0, ORIGIN[2]]),
                                   "origin_valid": np.array([0.0, 1.0])})
        wps, _ = TM.mission_waypoints(run, state, None)
        self.assertEqual(len(wps), 3)
        np.testing.assert_allclose(wps[2], [0.0, 0.0, -70.0], atol=1e-6)

    def test_loiter_and_return_home_items_are_read(self):
        wps, loop = TM.parse_mission_text("loop: false\nwaypoints:\n  - [100, 0, -70]\n"
                                          "  - {type: loiter, ned: [100, 100, -70], radius: 60, turns: 2}\n"
                                          "  - {type: return_home, altitude: 80}\n")
        self.assertFalse(loop)
        self.assertEqual([w for w, _ in wps], [[100, 0, -70], [100, 100, -70], [0, 0, -80]])

    def test_markers_of_phases_handovers_fallback_and_failsafes(self):
        s = {"phases": [{"phase": "preflight", "start_s": 0.0}, {"phase": "takeoff", "start_s": 12.2},
                        {"phase": "cruise", "start_s": 30.0}],
             "controller_handovers": [{"t_s": 0.0, "from": "slc", "to": "(none)", "reason": "preflight: on the ground"},
                                      {"t_s": 12.2, "from": "(none)", "to": "slc", "reason": "phase takeoff"},
                                      {"t_s": 30.0, "from": "slc", "to": "ctl", "reason": "phase cruise"},
                                      {"t_s": 41.0, "from": "ctl", "to": "slc", "reason": "fallback for the rest of the flight: x"}],
             "failsafes": [{"t_s": 50.0, "cause": "gnss_loss", "action": "loiter"},
                           {"t_s": 58.0, "cause": "gnss_back", "action": "none"}]}
        self.assertEqual(TL.flight_markers(s), [
            (12.2, "takeoff; (none) -> slc", "handover"), (30.0, "cruise; slc -> ctl", "handover"),
            (41.0, "fallback: ctl -> slc", "fallback"), (50.0, "failsafe gnss_loss", "failsafe"),
            (58.0, "failsafe gnss_back", "cleared")])

    def test_limits_follow_the_controller_and_saturation_spans(self):
        s = {"controller_handovers": [{"t_s": 1.0, "from": "(none)", "to": "slc"}, {"t_s": 3.0, "from": "slc", "to": "ctl"}]}
        params = {"slc.max_a": [(0.0, "0.7")], "ctl.max_a": [(0.0, "0.2"), (4.0, "0.3")]}
        t = np.arange(0.0, 6.0, 0.5)
        lo, hi, sources = TL.actuator_limits(s, params, t)["delta_a"]
        np.testing.assert_array_equal(hi, [np.nan, np.nan, 0.7, 0.7, 0.7, 0.7, 0.2, 0.2, 0.3, 0.3, 0.3, 0.3])
        np.testing.assert_array_equal(lo, -hi)
        self.assertEqual(sources, ["ctl.max_a", "slc.max_a"])
        v = np.array([0.9, 0.0, 0.7, 0.1, 0.1, -0.7, 0.2, 0.2, 0.2, 0.3, 0.1, -0.3])
        self.assertEqual(TL.saturation_spans(t, v, lo, hi), [(1.0, 1.5), (2.5, 4.0), (4.5, 5.0), (5.5, 6.0)])

    def test_landing_approaches_and_the_runway_frame(self):
        import tern_plot_landing as TLand
        spans = [(0.0, 10.0, "preflight"), (10.0, 30.0, "climb"), (30.0, 51.0, "approach"), (51.0, 60.0, "climb"),
                 (60.0, 80.0, "approach"), (80.0, 84.0, "flare"), (84.0, 90.0, "rollout"), (90.0, 95.0, "stopped")]
        a = TLand.approaches(spans)
        self.assertEqual([(x["t0"], x["t1"], x["go_around"]) for x in a], [(30.0, 51.0, 51.0), (60.0, 95.0, None)])
        self.assertEqual([n for _, n in a[1]["phases"]], ["approach", "flare", "rollout", "stopped"])
        # runway heading east, touchdown point at n 10, e 20, d 1 (below the origin)
        spec = {"td": np.array([10.0, 20.0, 1.0]), "heading": math.pi / 2}
        along, across, height = TLand.runway_frame(spec, np.array([10.0, 7.0]), np.array([-80.0, 25.0]), np.array([-9.0, 1.0]))
        np.testing.assert_allclose(along, [-100.0, 5.0], atol=1e-9)
        np.testing.assert_allclose(across, [0.0, 3.0], atol=1e-9)   # south of an eastward runway: right of it
        np.testing.assert_allclose(height, [10.0, 0.0], atol=1e-9)
        tr = (np.array([10.05, 10.1]), np.array([1.0, 2.0]), np.zeros(2), np.zeros(2))  # logged at 20 Hz
        self.assertEqual(TLand.at_time(tr, 10.03), (1.0, 0.0, 0.0))  # a phase change between two samples
        self.assertIsNone(TLand.at_time(tr, 9.9))
        run = {"summary": {}, "state": None, "run_dir": self.tmp, "t_end": 95.0, "phase": None, "waypoints": (None, True),
               "definitions": TL.read_definitions(self.tmp) if write_definitions(self.tmp) is None else None,
               "truth": None, "config": {"mission": {"file": "m.yaml", "waypoints": [
                   {"type": "land", "ned": [0, 0, 0], "heading": 2.3562, "flare_height": 3}]}}}
        spec = TLand.land_item(run, [])   # from config.yaml: definitions.json's defaults for the rest
        self.assertEqual((spec["source"], spec["flare_height"], spec["decision_height"], spec["glide_slope"]),
                         ("config.yaml", 3.0, 12.0, 0.0873))
        self.assertEqual(spec["heading"], 2.3562)
        self.assertEqual(TLand.entry_height(dict(spec, prev_d=-70.0), run, []), 70.0)
        self.assertEqual(TLand.entry_height(dict(spec, prev_d=-10.0), run, []), 24.0)  # raised: 2 decision heights
        # the defaults are the log's, not a copy: another build's
        run["definitions"]["land_item"] = {"glide_slope": 0.05, "flare_height": 2.0, "decision_height": 9.0,
                                           "min_entry_heights": 3.0}
        spec = TLand.land_item(run, [])
        self.assertEqual((spec["flare_height"], spec["decision_height"], spec["glide_slope"]), (3.0, 9.0, 0.05))
        self.assertEqual(TLand.entry_height(dict(spec, prev_d=-10.0), run, []), 27.0)

    def test_waypoints_added_in_flight(self):
        first = (0.0, 1, np.array([[0.0, 0.0, -50.0], [100.0, 0.0, -50.0]]), np.array([0, 0]), np.zeros(2))
        edit = (20.0, 2, np.array([[0.0, 0.0, -50.0], [100.0, 0.0, -50.0], [50.0, 50.0, -60.0]]), np.zeros(3, int),
                np.zeros(3))
        loiter = (35.0, 3, np.array([[50.0, 50.0, -60.0], [7.0, 8.0, -40.0]]), np.array([0, 1]), np.zeros(2))
        self.assertEqual(TL.added_waypoints([first]), [])
        self.assertEqual(TL.added_waypoints([first, edit, loiter]), [(0, 20.0), (1, 35.0)])

    def test_waypoint_lists_from_the_log_a_cleared_one_included(self):
        tp = os.path.join(self.tmp, "topics")
        os.makedirs(tp)
        write_csv(os.path.join(tp, "waypoints.csv"), ["t [s]", "stamp [ns]", "revision []", "count []", "loop [bool]"],
                  [[0, 0, 1, 2, 1], [10, 1e10, 2, 3, 1], [20, 2e10, 3, 0, 1]])
        items = [[0, 0, 1, k, 100.0 * k, 0, -50, 0, 0, 0, 17, 0, 0, 1, 0, 0] for k in range(2)]
        items += [[10, 1e10, 2, k, 100.0 * k, 0, -50, 0, 0, 0, 17, 0, 0, 1, 0, 0] for k in range(3)]
        write_csv(os.path.join(tp, "waypoints_items.csv"),
                  ["t [s]", "stamp [ns]", "revision []", "index []", "w_0 [m|deg]", "w_1 [m|deg]", "w_2 [m|deg]",
                   "lla [bool]", "chi_d [rad]", "use_chi [bool]", "Va_d [m/s]", "type [enum]", "loiter_radius [m]",
                   "loiter_direction []", "loiter_time [s]", "loiter_turns []"], items)
        lists = TL.flown_waypoints(self.tmp)
        self.assertEqual([(t, rev, len(pos)) for t, rev, pos, _, _ in lists], [(0.0, 1, 2), (10.0, 2, 3), (20.0, 3, 0)])
        self.assertEqual(TL.added_waypoints(lists[:2]), [(2, 10.0)])
        self.assertEqual(TL.added_waypoints(lists), [])
        self.assertIsNone(TL.flown_waypoints(os.path.join(self.tmp, "nowhere")))

    def test_euler_sigmas_level_and_banked(self):
        P = np.array([[1e-4, 4e-4, 9e-4]])
        s = TErrors.euler_sigmas(P, np.array([0.0]), np.array([0.0]))
        np.testing.assert_allclose([x[0] for x in s], [0.01, 0.02, 0.03])
        s = TErrors.euler_sigmas(P, np.array([math.pi / 2]), np.array([0.0]))  # banked 90 deg: pitch from body z
        np.testing.assert_allclose([x[0] for x in s], [0.01, 0.03, 0.02], atol=1e-12)

    def test_rmse_window_of_the_summary(self):
        phase = TL.Topic("flight_phase", {"t": np.array([0.0, 10.0, 20.0, 30.0]), "phase": np.array([0.0, 2.0, 1.0, 2.0])})
        run = {"summary": {"metrics": {"window_start_s": 15.0}}, "t_end": 40.0, "params": {}, "phase": phase,
               "definitions": {"phase": {0: "takeoff", 1: "climb", 2: "cruise"}}}
        mask, label = TL.rmse_window(run)
        t = np.array([5.0, 12.0, 16.0, 25.0, 31.0])
        self.assertEqual(mask(t).tolist(), [False, False, True, False, True])
        self.assertEqual(label, "cruise 15-40 s, as summary.json")
        run["definitions"] = {"phase": {1: "cruise", 2: "climb"}}  # the codes are the log's, not a copy
        self.assertEqual(TL.rmse_window(run)[0](t).tolist(), [False, False, False, True, False])
        run["summary"]["metrics"]["window_start_s"] = None
        mask, label = TL.rmse_window(run)
        self.assertTrue(mask(t).all())
        self.assertIn("no RMSE window", label)

    def test_lla_to_ned(self):
        lat, lon, alt = ORIGIN
        a, f = 6378137.0, 1 / 298.257223563
        e2 = f * (2 - f)
        s = math.sin(math.radians(lat))
        m_radius = a * (1 - e2) / (1 - e2 * s * s) ** 1.5     # meridian radius of curvature
        n_radius = a / math.sqrt(1 - e2 * s * s)              # prime vertical
        n, e, d = TM.lla_to_ned((lat + 0.001, lon, alt), ORIGIN)
        self.assertAlmostEqual(n, (m_radius + alt) * math.radians(0.001), delta=0.005)
        self.assertAlmostEqual(e, 0.0, delta=1e-6)
        n, e, d = TM.lla_to_ned((lat, lon - 0.001, alt + 10.0), ORIGIN)
        self.assertAlmostEqual(e, -(n_radius + alt) * math.cos(math.radians(lat)) * math.radians(0.001),
                               delta=0.005)
        self.assertAlmostEqual(d, -10.0, delta=0.01)

    def test_angle_errors_are_wrapped_across_pi(self):
        t = np.linspace(0.0, 10.0, 101)
        truth = TA.wrap_pi(3.0 + 0.1 * t)                      # 3.0 .. 4.0 rad: jumps at pi
        estimate = TA.wrap_pi(3.0 + 0.1 * t + 0.02)            # jumps 0.2 s earlier
        e = TA.wrap_pi(np.interp(t, t, TErrors.nan_unwrap(estimate)) - TErrors.nan_unwrap(truth))
        np.testing.assert_allclose(e, 0.02, atol=1e-12)
        with_gap = estimate.copy()
        with_gap[40:50] = np.nan                               # not valid there: a gap, not NaN ever after
        u = TErrors.nan_unwrap(with_gap)
        self.assertTrue(np.isnan(u[40:50]).all() and np.isfinite(u[50:]).all())

    def test_decimation_keeps_the_envelope(self):
        t = np.arange(100001) * 0.0025
        v = np.sin(t)
        v[54321] = 7.0          # one-sample spike
        v[77777] = -3.0
        v[20000:30000] = np.nan  # estimator not valid there
        td, vd = TDraw.decimate(t, v)
        self.assertLessEqual(len(td), TDraw.MAX_POINTS + 100)
        self.assertTrue(np.all(np.diff(td) > 0))
        self.assertEqual(np.nanmax(vd), 7.0)
        self.assertEqual(np.nanmin(vd), -3.0)
        gap = (td > 50.5) & (td < 74.5)
        self.assertTrue(gap.any() and np.all(np.isnan(vd[gap])))
        self.assertFalse(np.isnan(vd[~((td >= 50.0) & (td < 75.0))]).any())
        short = np.arange(10.0)
        self.assertIs(TDraw.decimate(short, short)[1], short)

    def test_commanded_segments_cover_the_stretch_flown(self):
        t = np.arange(0.0, 20.0, 0.1)
        path = TL.Topic("current_path", {
            "t": t, "path_type": np.where(t < 10, 1.0, 0.0), "r_n": np.zeros_like(t), "r_e": np.zeros_like(t),
            "q_n": np.ones_like(t), "q_e": np.zeros_like(t), "c_n": np.full_like(t, 200.0),
            "c_e": np.zeros_like(t), "rho": np.where(t < 10, 0.0, 50.0), "lambda": np.ones_like(t)})
        # along the line to n = 150 by t = 10, then a quarter of the orbit about (200, 0)
        a = np.clip((t - 10) / 10, 0, 1) * (np.pi / 2)
        pn = np.where(t < 10, 15.0 * t, 200.0 - 50.0 * np.cos(a))
        pe = np.where(t < 10, 0.0, -50.0 * np.sin(a))
        segs = TTrack.path_segments(path, (t, pn, pe))
        self.assertEqual(len(segs), 2)
        (le, ln), (oe, on) = segs
        self.assertEqual(ln.tolist(), [0.0, 150.0])
        self.assertEqual(le.tolist(), [0.0, 0.0])
        np.testing.assert_allclose(np.hypot(on - 200.0, oe), 50.0)
        self.assertAlmostEqual(float(on.min()), 150.0, delta=1e-6)
        self.assertAlmostEqual(float(oe.min()), -50.0, delta=0.1)   # the quarter flown, not the whole circle
        self.assertGreaterEqual(float(oe.max()), -1e-6)
        self.assertLess(float(oe.max()), 1.0)


if __name__ == "__main__":
    sys.modules.setdefault("test_tern_plot", sys.modules["__main__"])  # test_plot_pages imports this module, not again
    from test_plot_pages import ABDifferences, IndexPage, NothingHidden, WrappedCourse  # noqa: F401 (ctest plot)
    unittest.main(verbosity=2)
