#!/usr/bin/env python3
"""tern plot on real flight logs: test_plot_flight.py TERN (TERN_PLUGIN_PATH: the test plugins).

Flies two short missions (ctest plot_flight), once each, and checks tern plot's figures on them:
  A: cruise flown by `ctl`, a control_slc with a 0.15 rad aileron limit (slc's is 0.6981), a GNSS
     drop-out that sets off the gnss_loss failsafe (a loiter item added to the mission in flight);
  B: cruise flown by a test_controller that throws at 30 s: the fallback slc takes over.
Checks: the actuator figure's limits follow the controller flying and its shading the samples at
a limit; every time figure carries the phase, handover, fallback and failsafe markers; the
waypoint list flown last with the added loiter; +-3 sigma bands that hold the errors; the legend's
RMSE equal to summary.json's over the same window, which it names; a replay with two estimator
instances (one colour each) and a replay against the recorded estimate; the overlay of A and B;
index.html in headless Chromium (every image loaded, summary values shown, the ground track and the
altitude on the first screen, no table there). And the default mission flown one loop, then its
land item: landing.png's markers (its approach too when state.csv is logged slower than the phase
changes), and its touchdown marker where summary.json's metrics.landing measured it.
"""
import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

from test_tern_plot import SCRIPT, np  # (re-executes with Debian's python3 when numpy is missing)
import tern_plot_landing as TLand  # noqa: E402  (beside tern-plot: on sys.path once test_tern_plot loaded it)
import tern_plot_errors as TErrors  # noqa: E402
import tern_plot_load as TLoad  # noqa: E402
import tern_plot_log as TL  # noqa: E402

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))))  # core/apps/plot/ -> the repository
TERN = None
TIME_FIGURES = ["altitude.png", "airspeed.png", "course.png", "roll_pitch.png", "actuators.png", "estimation_errors.png"]

MISSION = f"""seed: 3
aircraft: {REPO}/configs/aircraft/anaconda.yaml
plugins:
  - name: sim
    plugin: sim_aero
    rate: 400
    params: {{init_mode: ground, init_heading: 2.3562, wind: [3.5355, -3.5355, 0.0], turbulence: light,
              sensor_profile: realistic, gnss_dropout: DROPOUT}}
  - {{name: ekf, plugin: estimator_ekf, rate: 400}}
EXTRA_ESTIMATOR  - {{name: planner, plugin: path_planner, rate: 10}}
  - {{name: manager, plugin: path_manager, rate: 100}}
  - {{name: follower, plugin: path_follower, rate: 100}}
  - {{name: slc, plugin: control_slc, rate: 100, param_file: {REPO}/configs/gains/anaconda.yaml}}
  - CTL
phases: {{takeoff: slc, climb: slc, cruise: ctl}}
fallback: slc
failsafes:
  gnss_loss: {{timeout: 2}}
# every estimate and command logged: the figures' tracking RMSE is then the summary's over the
# same samples (at plot_rate a window that opens in a roll command's ramp, as the GNSS loss's
# loiter does at 57 s, differs by the command's 0.1-s sampling: 2.33 against 3.04 deg)
log: {{rates: {{state: 0, controller_internals: 0, controller_command: 0}}}}
mission:
  loop: true
  waypoints:
    - [-150, 150, -40]
    - [-150, -100, -40]
    - [100, 0, -40]
"""
CTL_A = f"{{name: ctl, plugin: control_slc, rate: 100, param_file: {REPO}/configs/gains/anaconda.yaml, params: {{max_a: 0.15}}}}"
CTL_B = ("{name: ctl, plugin: test_controller, rate: 100, params: {tag: 0.168, h_target: 40, kp: 0.05, "
         "fail_mode: throw, fail_at: 30}}")
EKF_B = ("  - {name: ekf_b, plugin: estimator_ekf, rate: 400, params: {gnss_vel_noise_h: 1.0, wind_walk: 0.05}, "
         "remap: {state: state_b, innovations: innovations_b}}\n")


def landing_mission():
    """configs/missions/default.yaml flown one loop of the hourglass, then its land item."""
    with open(os.path.join(REPO, "configs", "missions", "default.yaml")) as f:
        text = f.read()
    for old, new in (("name: default", "name: plot_land"), ("aircraft: ../", f"aircraft: {REPO}/configs/"),
                     ("param_file: ../", f"param_file: {REPO}/configs/"), ("loops: 5", "loops: 1"),
                     ("file: fixedwing_mission.yaml", f"file: {REPO}/configs/missions/fixedwing_mission.yaml")):
        if old not in text:
            raise AssertionError(f"default.yaml has no '{old}'")
        text = text.replace(old, new)
    return text


def mission(name, ctl, dropout, extra_estimator=""):
    text = MISSION.replace("CTL", ctl).replace("DROPOUT", dropout).replace("EXTRA_ESTIMATOR", extra_estimator)
    return f"name: {name}\n" + text


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    if r.returncode != 0:
        raise AssertionError(f"{' '.join(cmd)} exited {r.returncode}: {r.stderr[-2000:]}")
    return r


def log_dir_of(stdout):
    return next(line.split(": ", 1)[1].strip() for line in stdout.splitlines() if line.startswith("log: "))


def plot(*args):
    r = run([sys.executable, SCRIPT, *args])
    return r.stdout.strip().splitlines()[-1].split(": ", 1)[1].rstrip("/")


def figures(plots):
    with open(os.path.join(plots, "figures.json")) as f:
        return {fig["file"]: fig for fig in json.load(f)}


def summary(run_dir):
    with open(os.path.join(run_dir, "summary.json")) as f:
        return json.load(f)


def column(run_dir, topic, name):
    with open(os.path.join(run_dir, "topics", topic + ".csv")) as f:
        rows = list(csv.reader(f))
    k = [h.split(" [")[0] for h in rows[0]].index(name)
    return np.array([float(r[k]) for r in rows[1:]]), np.array([float(r[0]) for r in rows[1:]])


class Flights(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="tern_plot_flight_")
        logs = os.path.join(cls.tmp, "runs")
        paths = {}
        for name, ctl, dropout, extra in (("plot_a", CTL_A, "[55, 63]", ""), ("plot_b", CTL_B, "[]", ""),
                                          ("plot_a2", CTL_A, "[55, 63]", EKF_B)):
            paths[name] = os.path.join(cls.tmp, name + ".yaml")
            with open(paths[name], "w") as f:
                f.write(mission(name, ctl, dropout, extra))
        paths["plot_land"] = os.path.join(cls.tmp, "plot_land.yaml")
        with open(paths["plot_land"], "w") as f:
            f.write(landing_mission())
        cls.a = log_dir_of(run([TERN, "fly", paths["plot_a"], "--duration", "75", "--log-dir", logs, "-q"]).stdout)
        cls.b = log_dir_of(run([TERN, "fly", paths["plot_b"], "--duration", "45", "--log-dir", logs, "-q"]).stdout)
        # replays of A: with its own config (the recorded estimate beside), with two estimators
        cls.r1 = log_dir_of(run([TERN, "replay", cls.a, "--log-dir", logs, "-q"]).stdout)
        cls.r2 = log_dir_of(run([TERN, "replay", cls.a, "--config", paths["plot_a2"], "--log-dir", logs, "-q"]).stdout)
        cls.plots_a = plot("--strict", cls.a)
        cls.plots_b = plot(cls.b)
        cls.plots_r2 = plot(cls.r2)
        cls.plots_ab = plot(cls.a, cls.b)
        cls.land = log_dir_of(run([TERN, "fly", paths["plot_land"], "--log-dir", logs, "-q"]).stdout)
        cls.plots_land = plot("--strict", cls.land)
        cls.sa = summary(cls.a)
        TL.NOTES.clear()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_every_figure_and_the_index_are_written(self):
        figs = figures(self.plots_a)
        self.assertEqual(sorted(figs), sorted(["ground_track.png"] + TIME_FIGURES))
        for name in figs:
            self.assertGreater(os.path.getsize(os.path.join(self.plots_a, name)), 20000, name)
        self.assertTrue(os.path.isfile(os.path.join(self.plots_a, "index.html")))

    def test_markers_on_every_time_figure(self):
        hand = self.sa["controller_handovers"]
        self.assertEqual(hand[-1]["to"], "ctl")
        expected = ["takeoff; (none) -> slc", "climb", "cruise; slc -> ctl", "failsafe gnss_loss", "failsafe gnss_back"]
        figs = figures(self.plots_a)
        for name in TIME_FIGURES:
            self.assertEqual(figs[name]["markers"], expected, name)
        fb = figures(self.plots_b)
        self.assertTrue(summary(self.b)["fallback_engaged"])
        for name in TIME_FIGURES:
            self.assertIn("fallback: ctl -> slc", fb[name]["markers"], name)

    def test_actuator_limits_follow_the_controller_and_saturation_is_shaded(self):
        delta_a, t = column(self.a, "actuators", "delta_a")
        lo, hi, sources = TL.actuator_limits(self.sa, TL.read_params(self.a), t)["delta_a"]
        t_cruise = next(p["start_s"] for p in self.sa["phases"] if p["phase"] == "cruise")
        self.assertEqual(sources, ["ctl.max_a", "slc.max_a"])
        np.testing.assert_array_equal(hi[t >= t_cruise + 0.01], 0.15)
        np.testing.assert_array_equal(lo[t >= t_cruise + 0.01], -0.15)
        np.testing.assert_array_equal(hi[(t > 13) & (t < t_cruise - 0.01)], 0.6981)
        with np.errstate(invalid="ignore"):  # no limit (NaN) before the first controller flies
            at_limit = (delta_a >= hi * (1 - 1e-4)) | (delta_a <= lo * (1 - 1e-4))
        self.assertGreater(np.sum(at_limit & (t > t_cruise)), 100, "ctl's aileron never at its 0.15 rad limit")
        spans = TL.saturation_spans(t, delta_a, lo, hi)
        shaded = np.zeros(len(t), bool)
        for t0, t1 in spans:
            shaded |= (t >= t0) & (t < t1)
        np.testing.assert_array_equal(shaded, at_limit)
        legend = " ".join(figures(self.plots_a)["actuators.png"]["legend"])
        share = 100.0 * sum(t1 - t0 for t0, t1 in spans) / (t[-1] - t[0])
        self.assertIn(f"delta_a (at a limit {share:.1f} % of the time, shaded)", legend)
        self.assertIn("controller limit (ctl.max_a, slc.max_a; params.csv)", legend)

    def test_waypoints_as_flown_include_the_failsafe_loiter(self):
        lists = TL.flown_waypoints(self.a)
        self.assertGreaterEqual(len(lists), 2)
        self.assertEqual(lists[0][2].tolist(), [[-150, 150, -40], [-150, -100, -40], [100, 0, -40]])
        added = TL.added_waypoints(lists)
        self.assertEqual(len(added), 1)
        k, t_add = added[0]
        fs = next(f for f in self.sa["failsafes"] if f["cause"] == "gnss_loss")
        self.assertLess(abs(t_add - fs["t_s"]), 0.2)
        self.assertEqual(lists[-1][3][k], 1)  # a loiter item
        self.assertIn("added in flight", figures(self.plots_a)["ground_track.png"]["legend"])

    def test_sigma_bands_hold_the_errors(self):
        TL.NOTES.clear()
        ctx = TLoad.load_run(self.a, False)
        tc, errs = TErrors.instance_errors(ctx, ctx["estimators"][0])
        for key in ("n", "e", "h", "phi", "theta", "psi"):
            e, sig = errs[key]
            ok = np.isfinite(e) & np.isfinite(sig) & (tc > 20.0)
            inside = np.mean(np.abs(e[ok]) <= 3.0 * sig[ok])
            self.assertGreater(inside, 0.9, f"{key}: only {inside:.2f} of the errors within 3 sigma")
            self.assertLess(np.median(sig[ok]), 10.0 if key in "neh" else 0.2, key)
        self.assertIn("ekf: +-3 sigma", figures(self.plots_a)["estimation_errors.png"]["legend"])

    def test_legend_rmse_is_summary_rmse_over_the_same_window(self):
        m = self.sa["metrics"]
        self.assertIsNotNone(m["window_start_s"])
        fig = figures(self.plots_a)["estimation_errors.png"]
        mine = fig["rmse"]["ekf"]
        for key, field in (("n", "north_m"), ("e", "east_m"), ("h", "altitude_m"), ("phi", "roll_deg"),
                           ("theta", "pitch_deg"), ("psi", "heading_deg"), ("Va", "airspeed_mps")):
            want = m["estimation_rmse"][field]
            self.assertAlmostEqual(mine[key], want, delta=0.01 * want + 1e-3, msg=field)
        window = f"cruise {m['window_start_s']:.4g}-{self.sa['duration_s']:.4g} s, as summary.json"
        self.assertIn(f"ekf: RMSE {mine['n']:.3g} m ({window})", fig["legend"])
        figs = figures(self.plots_a)
        label = os.path.basename(self.a)
        for name, keys in (("altitude.png", ["altitude_m"]), ("airspeed.png", ["airspeed_mps"]),
                           ("course.png", ["course_deg"]), ("roll_pitch.png", ["roll_deg", "pitch_deg"])):
            for key in keys:
                want = m["tracking_rmse"][key]
                # 2 %: the figure pairs each logged estimate with the latest logged command, the
                # summary each tick's; in the loiter's roll ramp (86 deg/s) that is 3.006 vs 3.043 deg
                self.assertAlmostEqual(figs[name]["tracking_rmse"][label][key], want, delta=0.02 * want + 1e-3, msg=key)
        h = figs["altitude.png"]["tracking_rmse"][label]["altitude_m"]
        self.assertIn(f"commanded h_c: tracking RMSE {h:.3g} m ({window})", figs["altitude.png"]["legend"])

    def test_replay_instances_one_colour_each(self):
        fig = figures(self.plots_r2)["estimation_errors.png"]
        self.assertEqual(sorted(fig["rmse"]), ["ekf", "ekf_b"])
        self.assertIn("ekf_b estimated", figures(self.plots_r2)["altitude.png"]["legend"])
        TL.NOTES.clear()
        inst = TLoad.load_run(self.r2, False)["estimators"]
        self.assertEqual([e["name"] for e in inst], ["ekf", "ekf_b"])
        self.assertNotEqual(inst[0]["colour"], inst[1]["colour"])
        cfg, source = TL.read_config(self.r1)
        inst = TL.load_estimators(self.r1, cfg, source)
        self.assertEqual([e["name"] for e in inst],
                         ["ekf (replayed)", f"ekf (recorded in flight {os.path.basename(self.a)})"])

    def test_overlay_of_two_runs(self):
        self.assertEqual(self.plots_ab, os.path.join(self.a, "plots", "vs-" + os.path.basename(self.b)))
        figs = figures(self.plots_ab)
        names = ("plot_a", "plot_b")  # the directory names without their time stamps
        for name in ("ground_track.png", "altitude.png", "airspeed.png", "course.png", "roll_pitch.png",
                     "actuators.png", "estimation_errors.png"):
            self.assertIn(name, figs)
            legend = " ".join(figs[name]["legend"])
            for n in names:
                self.assertIn(n + ": ", legend, name)
        self.assertEqual(sorted(figs["estimation_errors.png"]["rmse"]), sorted(f"{n}: ekf" for n in names))
        markers = figs["altitude.png"]["markers"]
        self.assertIn(f"{names[1]}: fallback: ctl -> slc", markers)
        self.assertEqual(len(markers), len(set(markers)), "a marker both runs share is drawn once")
        self.assertIn(f"{names[0]}: failsafe gnss_loss", markers)

    def test_landing_figure_marks_the_touchdown_metrics_landing_measured(self):
        s = summary(self.land)
        self.assertEqual(s["end_reason"], "landed")
        m = s["metrics"]["landing"]
        fig = figures(self.plots_land)["landing.png"]
        self.assertEqual(fig["markers"], ["approach 1", "flare", "rollout", "stopped", "touchdown", "stop"])
        self.assertIn(f"touchdown t {m['touchdown_t_s']:.1f} s (metrics.landing, truth): {m['touchdown_along_m']:+.1f} m "
                      f"along, {m['touchdown_across_m']:+.1f} m across the touchdown point", " ".join(fig["legend"]))
        self.assertNotIn("landing.png", [f for f in figures(self.plots_a)])  # no land item: none
        TL.NOTES.clear()
        ctx = TLoad.load_run(self.land, False)
        spans = TLand.phase_spans(ctx)
        spec = TLand.land_item(ctx, spans)  # the manager's aim point: land_aim_offset_m short of the item (0, 0, 0)
        # from home, on the runway its range finder measured on the final (runway_altitude_m) or at home's altitude
        mgr = next(i for i in s["instances"].values() if isinstance(i, dict) and "home_altitude_m" in i)
        back = mgr["land_aim_offset_m"] * np.array([math.cos(spec["heading"]), math.sin(spec["heading"])])
        np.testing.assert_allclose(spec["td"], [-back[0], -back[1], -mgr.get("runway_altitude_m", mgr["home_altitude_m"])],
                                   atol=1e-3)
        last = TLand.approaches(spans)[-1]
        tr = TLand.track(ctx["truth"], spec, last["t0"], last["t1"], dz=TLand.truth_rebase(ctx, spans, spec))
        along, across, height = TLand.at_time(tr, m["touchdown_t_s"])
        aim = TLand.true_touchdown_point(ctx, spec, spans)
        # at_time's sample is the truth's first at or after the touchdown (10 Hz in this log): the
        # aircraft rolled on by the ground speed times the time between them (up to 0.6 m)
        later = tr[0][min(int(np.searchsorted(tr[0], m["touchdown_t_s"])), len(tr[0]) - 1)] - m["touchdown_t_s"]
        self.assertAlmostEqual(along - aim[0], m["touchdown_along_m"], delta=0.1 + m["ground_speed_mps"] * later)
        self.assertAlmostEqual(across - aim[1], m["touchdown_across_m"], delta=0.1)
        self.assertAlmostEqual(height, 0.0, delta=0.1)  # the true CG at its height at rest: on the wheels

    def test_index_html_in_headless_chromium(self):
        try:
            driver = browser()
        except Exception as e:  # noqa: BLE001 (missing chromium, driver or selenium)
            self.skipTest(f"headless Chromium not available: {e}")
        try:
            for plots, run_dirs in ((self.plots_a, [self.a]), (self.plots_ab, [self.a, self.b])):
                driver.get("file://" + os.path.join(plots, "index.html"))
                imgs = driver.execute_script(
                    "return Array.from(document.images).map(i => [i.getAttribute('src'), i.complete, i.naturalWidth]);")
                self.assertEqual(sorted(i[0] for i in imgs), sorted(figures(plots)))
                for src, complete, width in imgs:
                    self.assertTrue(complete and width > 500, f"{src} did not load")
                # the first screen (1400 x 1000) shows the flight: the ground track whole, the altitude beside it
                boxes = driver.execute_script(
                    "const box = s => document.querySelector(s).getBoundingClientRect();"
                    "return [box('img[src=\"ground_track.png\"]'), box('img[src=\"altitude.png\"]'), box('table')]"
                    ".map(b => [b.left, b.top, b.bottom]);")
                (track_left, track_top, track_bottom), (alt_left, alt_top, _), (_, table_top, _) = boxes
                self.assertLess(track_bottom, 1000, "the ground track is not on the first screen")
                self.assertLess(alt_top, 1000)
                self.assertGreater(alt_left, track_left, "the altitude beside the ground track")
                self.assertGreater(table_top, 1000, "a table on the first screen")
                cell = driver.execute_script(
                    "const t = document.getElementById('rmse'); const row = Array.from(t.rows)"
                    ".find(r => r.cells[0].textContent === 'north_m'); return Array.from(row.cells).map(c => c.textContent);")
                for k, d in enumerate(run_dirs):
                    want = summary(d)["metrics"]["estimation_rmse"]["north_m"]  # B: too short for a window
                    self.assertEqual(cell[1 + 3 * k], "-" if want is None else f"{want:.3f}")
                self.assertNotEqual(cell[1], "-")
                text = driver.find_element("id", "failsafes" if len(run_dirs) == 1 else "failsafes-0").text
                self.assertIn("gnss_loss", text)
        finally:
            driver.quit()


def browser():
    from selenium import webdriver
    chromium = shutil.which("chromium") or "/usr/bin/chromium"
    driver_exe = shutil.which("chromedriver") or "/usr/bin/chromedriver"
    opts = webdriver.ChromeOptions()
    opts.binary_location = chromium
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage", "--window-size=1400,1000"):
        opts.add_argument(a)
    try:
        return webdriver.Chrome(service=webdriver.ChromeService(executable_path=driver_exe), options=opts)
    except AttributeError:  # selenium < 4.10
        from selenium.webdriver.chrome.service import Service
        return webdriver.Chrome(service=Service(driver_exe), options=opts)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: test_plot_flight.py TERN")
    TERN = sys.argv.pop(1)
    unittest.main(verbosity=2)
