#!/usr/bin/env python3
"""Tests of tern plot on a multi-vehicle run (fleet.json; tern_plot_fleet.py, issue 42):
`python3 core/apps/plot/test_plot_fleet.py [TERN]` (plain unittest).

Synthetic fleet (always): three vehicles in one run directory. uav1 logs truth and estimate,
starts at world (0, -200) flying east at 50 m; uav2 logs only its estimate (no truth), in its own
NED about its first fix at world (300, 0, -60), flying south at 60 m; uav3 (truth) orbits far away.
Their closest approach: uav1-uav2 at t 25 s, 70.71 m horizontal, 71.41 m 3-D. Checks the world
frame (uav2's estimate appears at (300, 0)), distinct colours, the pairwise distances, summary.json's
closest approach and min_distance, the per-vehicle figures and index.html's links, and that a
malformed fleet.json is one error line naming the file and the field, exit 1.

With TERN (ctest plot_fleet_flight): two real 30 s flights of the default mission, the second
started at (300, 0) and logged as MCAP only, put under uav1/ and uav2/ with a fleet.json: uav2's
truth starts at (300, 0) in the world frame, its converted estimate within a few metres of it;
uav2's tables exported outside its run directory (no uav2/topics after the plot).
"""

import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

# (test_tern_plot re-executes with Debian's python3 when numpy is missing)
from test_tern_plot import ORIGIN, SCRIPT, STATE_HEADER, np, png_size, run_plot, write_csv, write_definitions
from test_plot_reference import ned_to_lla  # noqa: E402  (the test's own inverse of lla_to_ned)
from test_plot_flight import log_dir_of, run  # noqa: E402
import tern_plot_draw as TDraw  # noqa: E402  (beside tern-plot: on sys.path once test_tern_plot loaded it)
import tern_plot_load as TLoad  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))  # core/apps/plot/ -> the repository
TERN = sys.argv[1] if __name__ == "__main__" and len(sys.argv) > 1 and not sys.argv[1].startswith("-") else None


def uav1(t):
    return 0.0, -200.0 + 10.0 * t, -50.0


def uav2(t):
    return 300.0 - 10.0 * t, 0.0, -60.0


def uav3(t):
    a = 0.1 * t
    return -400.0 + 80.0 * math.cos(a), 400.0 + 80.0 * math.sin(a), -70.0


def write_vehicle(run, path, truth=True, state_origin=ORIGIN, duration=50.0, rate=20.0):
    """A vehicle's log: truth (world NED about ORIGIN) and state in the NED about state_origin,
    given as world NED minus the origin's world position (flat: within 2 cm over 500 m here)."""
    tp = os.path.join(run, "topics")
    os.makedirs(tp)
    o_world = path(0.0) if state_origin is not ORIGIN else (0.0, 0.0, 0.0)
    truth_rows, state_rows = [], []
    for k in range(int(duration * rate) + 1):
        t = k / rate
        n, e, d = path(t)
        common = [15, 0, 0, 0.1, 0.05, 0.3, 15, 0.05, 0.3]
        truth_rows.append([t, t * 1e9, n, e, d] + common + list(ORIGIN) + [1, 1, 0, 0])
        state_rows.append([t, t * 1e9, n - o_world[0], e - o_world[1], d - o_world[2]] + common + list(state_origin)
                          + [1, 1 if t >= 1.0 else 0, 0, 0])
    if truth:
        write_csv(os.path.join(tp, "truth.csv"), STATE_HEADER, truth_rows)
    write_csv(os.path.join(tp, "state.csv"), STATE_HEADER, state_rows)
    write_csv(os.path.join(tp, "flight_phase.csv"), ["t [s]", "stamp [ns]", "phase [enum]", "previous [enum]", "since [ns]"],
              [[0, 0, 2, 0, 0]])
    write_definitions(run)
    with open(os.path.join(run, "summary.json"), "w") as f:
        json.dump({"phases": [{"phase": "cruise", "start_s": 0.0, "reason": "r"}], "controller_handovers": [],
                   "failsafes": [{"t_s": 30.0, "cause": "geofence", "action": "loiter"}] if path is uav3 else [],
                   "metrics": {"window_start_s": None}}, f)


SEPARATION = {"closest_approach_m": 71.41, "pair": ["uav1", "uav2"], "t_s": 25.0, "conflicts": 0, "min_distance_m": 30.0}


def write_fleet(fleet, vehicles=("uav1", "uav2", "uav3"), coordination=True):
    os.makedirs(fleet)
    write_vehicle(os.path.join(fleet, "uav1"), uav1)
    origin2 = ned_to_lla(uav2(0.0), ORIGIN)  # uav2's first fix: its estimator's origin
    write_vehicle(os.path.join(fleet, "uav2"), uav2, truth=False, state_origin=tuple(origin2))
    write_vehicle(os.path.join(fleet, "uav3"), uav3)
    with open(os.path.join(fleet, "fleet.json"), "w") as f:
        json.dump({"mission": "synthetic_fleet", "seed": 7, "vehicles": list(vehicles), "coordination": coordination}, f)
    with open(os.path.join(fleet, "summary.json"), "w") as f:
        json.dump({"mission": "synthetic_fleet", "vehicles": {v: {"end_reason": "duration", "ok": True} for v in vehicles},
                   "separation": SEPARATION}, f)
    if coordination:
        os.makedirs(os.path.join(fleet, "coordination", "topics"))
        with open(os.path.join(fleet, "coordination", "summary.json"), "w") as f:
            json.dump({"end_reason": "duration", "mission_edits": 3}, f)
        with open(os.path.join(fleet, "coordination", "tern.log"), "w") as f:
            f.write("coordination log\n")


def figures(plots):
    with open(os.path.join(plots, "figures.json")) as f:
        return {fig["file"]: fig for fig in json.load(f)}


class SyntheticFleet(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="tern_plot_fleet_")
        cls.fleet = os.path.join(cls.tmp, "20260101T000000Z-synthetic_fleet")
        write_fleet(cls.fleet)
        cls.r = run_plot(cls.fleet)
        cls.plots = os.path.join(cls.fleet, "plots")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_fleet_and_vehicle_figures_are_written_and_listed(self):
        self.assertEqual(self.r.returncode, 0, self.r.stderr)
        self.assertEqual(self.r.stderr, "")
        out = self.r.stdout.strip().splitlines()
        self.assertEqual(out[-1], f"plots: {self.plots}/")
        for name in ("tracks.png", "altitude.png", "separation.png", "index.html", *[
                os.path.join(v, f) for v in ("uav1", "uav2", "uav3") for f in ("ground_track.png", "altitude.png", "index.html")]):
            path = os.path.join(self.plots, name)
            self.assertIn(path, out)
            if name.endswith(".png"):
                self.assertIsNotNone(png_size(path), name)
        self.assertTrue(os.path.isfile(os.path.join(self.plots, "uav1", "estimation_errors.png")))
        self.assertFalse(os.path.exists(os.path.join(self.plots, "uav2", "estimation_errors.png")))  # no truth
        # the notes say which vehicle they are about
        notes = [ln for ln in out if "note:" in ln]
        self.assertTrue(notes)
        self.assertTrue(all(ln.startswith("tern plot: note: uav") for ln in notes), notes)
        self.assertTrue(any(ln.startswith("tern plot: note: uav2: topics/truth.csv missing") for ln in notes), notes)

    def test_tracks_in_the_world_frame_one_colour_per_vehicle(self):
        fig = figures(self.plots)["tracks.png"]
        v = fig["vehicles"]
        self.assertEqual(list(v), ["uav1", "uav2", "uav3"])
        self.assertEqual([v[k]["source"] for k in v], ["true", "estimated", "true"])
        self.assertEqual(len({v[k]["colour"] for k in v}), 3)
        np.testing.assert_allclose(v["uav1"]["start_ne"], [0.0, -200.0], atol=1e-6)
        # uav2's estimate (valid from 1 s) is in its own NED about (300, 0): it appears there
        np.testing.assert_allclose(v["uav2"]["start_ne"], [290.0, 0.0], atol=0.05)
        np.testing.assert_allclose(v["uav2"]["end_ne"], [-200.0, 0.0], atol=0.05)
        np.testing.assert_allclose(fig["world_origin"], ORIGIN)
        self.assertEqual(fig["legend"][:3], ["uav1 (true)", "uav2 (estimated)", "uav3 (true)"])
        # the closest approach on the tracks: summary.json's
        self.assertEqual(fig["closest"], {"pair": ["uav1", "uav2"], "t_s": 25.0, "distance_m": 71.41, "source": "summary.json"})

    def test_separation_of_every_pair_and_the_closest_approach(self):
        fig = figures(self.plots)["separation.png"]
        self.assertEqual(fig["pairs"], [["uav1", "uav2"], ["uav1", "uav3"], ["uav2", "uav3"]])
        c = fig["closest"]
        self.assertEqual(c["horizontal"]["pair"], ["uav1", "uav2"])
        self.assertAlmostEqual(c["horizontal"]["t_s"], 25.0, delta=0.05)
        self.assertAlmostEqual(c["horizontal"]["distance_m"], math.sqrt(5000.0), delta=0.05)
        self.assertAlmostEqual(c["3d"]["distance_m"], math.sqrt(5100.0), delta=0.05)
        self.assertEqual(fig["summary_closest"]["distance_m"], 71.41)
        self.assertEqual(fig["min_distance_m"], 30.0)
        legend = " ".join(fig["legend"])
        self.assertIn("min_distance 30 m (summary.json, 0 conflict(s))", legend)
        self.assertIn("closest approach (summary.json): uav1-uav2 71.4 m at 25.0 s", legend)
        self.assertIn("uav1-uav2: min 70.7 m at 25.0 s", legend)
        # uav3's failsafe marker, in its colour and named
        self.assertIn("uav3: failsafe geofence", fig["markers"])

    def test_altitude_of_every_vehicle(self):
        fig = figures(self.plots)["altitude.png"]
        self.assertEqual(fig["legend"], ["uav1 (true)", "uav2 (estimated)", "uav3 (true)"])

    def test_index_links_every_vehicle_and_the_coordination_log(self):
        with open(os.path.join(self.plots, "index.html")) as f:
            page = f.read()
        for src in ("tracks.png", "altitude.png", "separation.png", "uav1/index.html", "uav2/ground_track.png",
                    "uav3/altitude.png", "../coordination/summary.json", "../coordination/tern.log"):
            self.assertIn(f'"{src}"', page)
        for text in ("synthetic_fleet", "closest_approach_m", "71.410", "duration", "mission_edits"):
            self.assertIn(text, page)
        self.assertLess(page.index('<img src="separation.png"'), page.index("<table"), "the fleet's figures first")
        with open(os.path.join(self.plots, "uav1", "index.html")) as f:
            self.assertIn('<img src="ground_track.png"', f.read())
        self.assertIn("uav2/ground_track.png", figures(self.plots))

    def test_a_fleet_with_other_runs_is_refused(self):
        r = run_plot(self.fleet, os.path.join(self.fleet, "uav1"))
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn("fleet.json", r.stderr)


class MalformedFleet(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="tern_plot_fleet_")
        self.fleet = os.path.join(self.tmp, "fleet")
        write_fleet(self.fleet)

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def refused(self, fleet_json, *expect):
        path = os.path.join(self.fleet, "fleet.json")
        with open(path, "w") as f:
            f.write(fleet_json if isinstance(fleet_json, str) else json.dumps(fleet_json))
        r = run_plot(self.fleet)
        self.assertEqual(r.returncode, 1, r.stdout)
        lines = r.stderr.strip().splitlines()
        self.assertEqual(len(lines), 1, r.stderr)
        self.assertTrue(lines[0].startswith(f"tern plot: error: {path}: "), lines[0])
        for text in expect:
            self.assertIn(text, lines[0])
        self.assertFalse(os.path.exists(os.path.join(self.fleet, "plots")))
        return lines[0]

    def test_missing_vehicles(self):
        self.refused({"mission": "m"}, 'field "vehicles" missing')

    def test_vehicles_not_a_list_or_empty(self):
        self.refused({"vehicles": "uav1"}, 'field "vehicles" is not a non-empty list')
        self.refused({"vehicles": []}, 'field "vehicles" is not a non-empty list')

    def test_a_named_vehicle_dir_missing(self):
        self.refused({"vehicles": ["uav1", "uav9"]}, 'field "vehicles"[1] "uav9": no such directory',
                     os.path.join(self.fleet, "uav9"))

    def test_bad_names(self):
        self.refused({"vehicles": ["uav1", "../uav2"]}, 'field "vehicles"[1] ("../uav2") is not a directory name')
        self.refused({"vehicles": ["uav1", 2]}, 'field "vehicles"[1] (2) is not a directory name')
        self.refused({"vehicles": ["uav1", "uav1"]}, 'field "vehicles" names "uav1" twice')

    def test_not_json(self):
        self.refused("{vehicles: [", "not JSON")
        self.refused("[1, 2]", "not a JSON object")

    def test_a_vehicle_dir_without_a_log(self):
        shutil.rmtree(os.path.join(self.fleet, "uav2", "topics"))
        r = run_plot(self.fleet)
        self.assertEqual(r.returncode, 1)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertIn(os.path.join(self.fleet, "uav2") + ": not a tern run directory", r.stderr)


@unittest.skipIf(TERN is None, "no tern given (ctest plot_fleet_flight gives it)")
class FlownFleet(unittest.TestCase):
    """Two real flights of the default mission (30 s), the second from (300, 0) and MCAP only."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="tern_plot_fleet_flight_")
        logs = os.path.join(cls.tmp, "runs")
        mission = os.path.join(REPO, "configs", "missions", "default.yaml")
        a = log_dir_of(run([TERN, "fly", mission, "--duration", "30", "--log-dir", logs, "-q"]).stdout)
        b = log_dir_of(run([TERN, "fly", mission, "--duration", "30", "--log-dir", logs, "--log-format", "mcap",
                            "--set", "sim.init_position=[300,0]", "-q"]).stdout)
        cls.fleet = os.path.join(cls.tmp, "20260101T000000Z-two")
        os.makedirs(cls.fleet)
        shutil.copytree(a, os.path.join(cls.fleet, "uav1"))
        shutil.copytree(b, os.path.join(cls.fleet, "uav2"))
        with open(os.path.join(cls.fleet, "fleet.json"), "w") as f:
            json.dump({"mission": "two", "seed": 1, "vehicles": ["uav1", "uav2"], "coordination": False}, f)
        path = os.path.dirname(os.path.abspath(TERN)) + os.pathsep + os.environ.get("PATH", "")
        cls.r = subprocess.run([sys.executable, SCRIPT, cls.fleet], capture_output=True, text=True, timeout=300,
                               env=dict(os.environ, PATH=path))  # uav2's tables: tern export csv, tern on PATH
        if cls.r.returncode != 0:
            raise AssertionError(f"tern plot exited {cls.r.returncode}: {cls.r.stderr[-2000:]}")
        cls.plots = os.path.join(cls.fleet, "plots")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_the_second_vehicle_starts_at_300_0(self):
        fig = figures(self.plots)["tracks.png"]
        v = fig["vehicles"]
        self.assertEqual([v[k]["source"] for k in ("uav1", "uav2")], ["true", "true"])
        np.testing.assert_allclose(v["uav1"]["start_ne"], [0.0, 0.0], atol=0.5)
        np.testing.assert_allclose(v["uav2"]["start_ne"], [300.0, 0.0], atol=0.5)
        self.assertNotEqual(v["uav1"]["colour"], v["uav2"]["colour"])
        # uav2's tables exported from its flight.mcap outside the run directory (it keeps its size)
        self.assertFalse(os.path.exists(os.path.join(self.fleet, "uav2", "topics")))
        self.assertIn(os.path.join(self.plots, "uav2", "ground_track.png"), self.r.stdout.splitlines())
        sep = figures(self.plots)["separation.png"]
        self.assertEqual(sep["pairs"], [["uav1", "uav2"]])
        self.assertLess(sep["closest"]["horizontal"]["distance_m"], 300.5)

    def test_the_estimate_moved_into_the_world_frame(self):
        # the same track from uav2's estimate (its own NED about its first fix) lands on its truth
        import tern_plot_fleet as TF
        import tern_plot_log as TL
        src = os.path.join(self.fleet, "uav2")
        path = os.environ["PATH"]
        os.environ["PATH"] = os.path.dirname(os.path.abspath(TERN)) + os.pathsep + path
        try:
            TLoad.check_run_dir(src)  # MCAP only: its tables exported (tern export csv, tern on PATH) for this process
        finally:
            os.environ["PATH"] = path
        ctx = TLoad.load_run(src, False)
        ctx["truth"] = None
        fleet = TF.Fleet({"est": TDraw.est, "last_origin": TLoad.last_origin})
        world = TL.read_topic(os.path.join(self.fleet, "uav1"), "truth", TL.STATE_FIELDS)
        origin = TLoad.last_origin(world)
        source, t, p = fleet.track({"name": "uav2", "run": ctx}, origin)
        self.assertEqual(source, "estimated")
        truth = TL.read_topic(src, "truth", ["p_n", "p_e", "p_d"])
        ok = np.isfinite(p[:, 0])
        self.assertGreater(ok.sum(), 100)
        err = np.hypot(p[ok, 0] - np.interp(t[ok], truth.get("t"), truth.get("p_n")),
                       p[ok, 1] - np.interp(t[ok], truth.get("t"), truth.get("p_e")))
        self.assertLess(float(np.median(err)), 5.0)  # the estimate's error, not a frame's offset (300 m)


if __name__ == "__main__":
    if TERN is not None:  # ctest plot_fleet_flight: the flights only (plot_fleet runs the rest)
        sys.argv.pop(1)
        unittest.main(defaultTest="FlownFleet", verbosity=2)
    unittest.main(verbosity=2)
