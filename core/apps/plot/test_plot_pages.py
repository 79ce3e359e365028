#!/usr/bin/env python3
"""Tests of what a newcomer sees first (issue 63): `python3 core/apps/plot/test_plot_pages.py` (plain
unittest; test_tern_plot.py runs these too, as ctest plot).

index.html opens on the flight (the ground track, the altitude and the landing before any table);
course.png draws the course wrapped into [-180, 180] deg, its lines broken where they wrap; an A/B
overlay names what differs between the two runs (mission, duration, seed, sensor profile, plugins,
parameters) on the terminal and at the top of its index.html, with a warning when the missions
differ, and says so when only the compared parameters differ.
"""

import os
import re
import shutil
import sys
import tempfile
import unittest

# (test_tern_plot re-executes with Debian's python3 when numpy is missing)
from test_tern_plot import np, run_plot, write_landing_run, write_run
import tern_plot_angles as TA  # noqa: E402  (beside tern-plot: on sys.path once test_tern_plot loaded it)
import tern_plot_compare as TC  # noqa: E402
import tern_plot_draw as TDraw  # noqa: E402
import tern_plot_log as TL  # noqa: E402
import tern_plot_output as TOutput  # noqa: E402
from matplotlib.legend import Legend  # noqa: E402


def edit(path, old, new):
    with open(path) as f:
        text = f.read()
    if old not in text:
        raise AssertionError(f"{path} has no '{old}'")
    with open(path, "w") as f:
        f.write(text.replace(old, new))


def watched(run_dirs, out_dir, look, draw=None):
    """{figure file (below out_dir): look(fig)}: tern-plot's figures of run_dirs (one run or an overlay; or
    draw(run_dirs, out_dir), e.g. TOutput.plot_fleet), drawn in this process with tern_plot_draw.save watching."""
    seen, save = {}, TDraw.save

    def watch(fig, out, fname, *args, **kw):
        seen[os.path.relpath(os.path.join(out["dir"], fname), out_dir)] = look(fig)
        return save(fig, out, fname, *args, **kw)
    TDraw.save = watch
    try:
        (draw or TOutput.plot_runs)(run_dirs, out_dir)
    finally:
        TDraw.save = save
        TL.NOTES.clear()
    return seen


def drawn_lines(run_dir, out_dir):
    """{figure file: [[(label, x, y) of each line] of each axes]}."""
    return watched([run_dir], out_dir, lambda fig: [[(ln.get_label(), np.asarray(ln.get_xdata(), float),
                                                      np.asarray(ln.get_ydata(), float)) for ln in ax.lines]
                                                    for ax in fig.axes])


def drawn_texts(fig):
    """The texts a figure shows: titles, axis labels, the tick labels within the axes' limits,
    annotations, legend texts."""
    out = list(fig.texts)
    for ax in fig.axes:
        out += [ax.title, ax._left_title, ax._right_title, ax.xaxis.label, ax.yaxis.label, ax.yaxis.offsetText]
        out += list(ax.texts)
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            tol = 1e-6 * (hi - lo)
            out += [t.label1 for t in axis.get_major_ticks() if lo - tol <= t.get_loc() <= hi + tol and t.label1.get_visible()]
        for legend in [c for c in ax.get_children() if isinstance(c, Legend)]:
            out += list(legend.get_texts()) + [legend.get_title()]
    return [t for t in out if t.get_visible() and t.get_text().strip()]


def _overlap(a, b, px=1.0):
    return min(a.x1, b.x1) - max(a.x0, b.x0) > px and min(a.y1, b.y1) - max(a.y0, b.y0) > px


def overlaps(fig):
    """["text / text" of two texts that overlap, "legend 'text' over an axes" of a legend on a
    panel's data area, "'text' cut by the figure's edge"]: what hides what in the figure as drawn."""
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    boxes = [(t.get_text(), t.get_window_extent(r)) for t in drawn_texts(fig)]
    out = [f"{a[0]!r} / {b[0]!r}" for k, a in enumerate(boxes) for b in boxes[k + 1:] if _overlap(a[1], b[1])]
    w, h = fig.bbox.width, fig.bbox.height
    out += [f"{text!r} cut by the figure's edge" for text, b in boxes if b.x0 < -1 or b.y0 < -1 or b.x1 > w + 1 or b.y1 > h + 1]
    for ax in fig.axes:
        for legend in [c for c in ax.get_children() if isinstance(c, Legend)]:
            box = legend.get_window_extent(r)
            out += [f"legend {legend.get_texts()[0].get_text()!r} over an axes" for other in fig.axes
                    if _overlap(box, other.get_window_extent(r))]
    return out


class IndexPage(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="tern_plot_pages_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def page(self, run_dir):
        with open(os.path.join(run_dir, "plots", "index.html")) as f:
            return f.read()

    def test_the_page_opens_on_the_flight_and_the_tables_follow_the_figures(self):
        run = os.path.join(self.tmp, "landing")
        write_landing_run(run)
        r = run_plot(run)
        self.assertEqual(r.returncode, 0, r.stderr)
        page = self.page(run)
        imgs = re.findall(r'<img src="([^"]+)"', page)
        self.assertEqual(imgs[:3], ["ground_track.png", "altitude.png", "landing.png"])
        self.assertEqual(sorted(imgs), sorted(["ground_track.png", "altitude.png", "airspeed.png", "course.png",
                                               "roll_pitch.png", "estimation_errors.png", "landing.png"]))
        last_img = max(m.start() for m in re.finditer("<img ", page))
        self.assertLess(last_img, page.index("<table"), "a table before the last figure")
        first = page[:page.index("<h2>Figures</h2>")]   # the first screen: the three, side by side
        self.assertIn('<div class="flight">', first)
        self.assertEqual(re.findall(r'<img src="([^"]+)"', first), imgs[:3])
        self.assertIn('id="flight"', page[page.index("<h2>Summary</h2>"):])  # summary.json's tables kept

    def test_a_flight_without_a_landing_opens_on_its_track_and_altitude(self):
        run = os.path.join(self.tmp, "orbit")
        write_run(run)
        self.assertEqual(run_plot(run).returncode, 0)
        page = self.page(run)
        self.assertEqual(re.findall(r'<img src="([^"]+)"', page)[:2], ["ground_track.png", "altitude.png"])
        self.assertLess(max(m.start() for m in re.finditer("<img ", page)), page.index("<table"))


class NothingHidden(unittest.TestCase):
    """No text over another and no legend over the data, in every figure of a flight, a landing
    and an overlay of two runs."""

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="tern_plot_pages_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def check(self, run_dirs, want, draw=None):
        found = watched(run_dirs, os.path.join(self.tmp, "plots"), overlaps, draw)
        self.assertEqual(sorted(found), sorted(want))
        for name, what in found.items():
            self.assertEqual(what, [], name)

    def test_a_fleet(self):
        from test_plot_fleet import write_fleet
        fleet = os.path.join(self.tmp, "fleet")
        write_fleet(fleet)
        each = ["ground_track.png", "altitude.png", "airspeed.png", "course.png", "roll_pitch.png"]
        self.check(fleet, [f"{v}/{f}" for v in ("uav1", "uav3") for f in each + ["estimation_errors.png"]]
                   + [f"uav2/{f}" for f in each] + ["tracks.png", "altitude.png", "separation.png"], draw=TOutput.plot_fleet)

    def test_a_flight_and_its_overlay(self):
        a, b = os.path.join(self.tmp, "a"), os.path.join(self.tmp, "b")
        write_run(a)
        write_run(b, duration=50.0)
        figures = ["ground_track.png", "altitude.png", "airspeed.png", "course.png", "roll_pitch.png", "actuators.png",
                   "estimation_errors.png"]
        self.check([a], figures)
        self.check([a, b], figures)

    def test_a_landing(self):
        run = os.path.join(self.tmp, "landing")
        write_landing_run(run)
        self.check([run], ["ground_track.png", "altitude.png", "airspeed.png", "course.png", "roll_pitch.png",
                           "estimation_errors.png", "landing.png"])


class WrappedCourse(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="tern_plot_pages_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_break_wraps_breaks_the_line_at_180(self):
        t = np.arange(6.0)
        t2, d = TA.break_wraps(t, np.array([170.0, 178.0, -178.0, -170.0, 179.0, 10.0]))
        np.testing.assert_array_equal(np.isnan(d), [False, False, True, False, False, True, False, False])
        self.assertTrue(np.isnan(t2[2]) and np.isnan(t2[5]))
        np.testing.assert_array_equal(d[~np.isnan(d)], [170.0, 178.0, -178.0, -170.0, 179.0, 10.0])
        np.testing.assert_allclose(TA.wrap_deg(np.radians([190.0, -190.0, 540.0, 0.0])), [-170.0, 170.0, -180.0, 0.0])

    def test_course_is_drawn_within_180_deg_without_lines_across(self):
        run = os.path.join(self.tmp, "orbit")
        write_run(run, duration=60.0)   # a 100-m orbit at 17 m/s: the course goes round 1.6 times
        course = drawn_lines(run, os.path.join(self.tmp, "plots"))["course.png"][0]
        labels = [label for label, _, _ in course]
        for want in ("true", "state estimated"):
            self.assertIn(want, labels)
        for label, t, y in course:
            if label.startswith("_"):   # markers, not data
                continue
            ok = np.isfinite(y)
            self.assertGreater(ok.sum(), 100, label)
            self.assertTrue(np.all((y[ok] >= -180.0) & (y[ok] <= 180.0)), f"{label}: {y[ok].min()}..{y[ok].max()}")
            pairs = ok[1:] & ok[:-1]
            self.assertLess(np.abs(np.diff(y))[pairs].max(), 180.0, f"{label}: a line across the axes")
            self.assertGreaterEqual(int(np.isnan(y).sum()), 1, f"{label}: never broken where it wraps")


class ABDifferences(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="tern_plot_pages_")
        self.a = os.path.join(self.tmp, "20260101T000000Z-synthetic")
        write_run(self.a)

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def other(self, name, duration=60.0):
        run = os.path.join(self.tmp, name)
        write_run(run, duration=duration)
        return run

    def ab(self, b):
        r = run_plot(self.a, b)
        self.assertEqual(r.returncode, 0, r.stderr)
        lines = r.stdout.strip().splitlines()
        self.assertTrue(lines[-1].startswith("plots: "), lines[-1])
        block = [ln for ln in lines if ln.startswith("A/B: ")]
        self.assertEqual(block, lines[-1 - len(block):-1], "the block is one, just before the plots line")
        plots = lines[-1].split(": ", 1)[1]
        with open(os.path.join(plots, "index.html")) as f:
            return block, f.read()

    def test_a_changed_mission_seed_and_duration_are_named_with_a_warning(self):
        b = self.other("20260101T000100Z-my_ctl", duration=40.0)
        config = os.path.join(b, "config.yaml")
        edit(config, "name: synthetic\nseed: 1\n", "name: my_ctl\nseed: 7\n")
        edit(config, "    - [100, 0, -50]\n", "    - [300, 0, -50]\n")
        block, page = self.ab(b)
        self.assertEqual(len(block), 2, block)
        self.assertEqual(block[0], "A/B: synthetic vs my_ctl: these runs differ in: mission synthetic vs my_ctl; "
                                   "duration 60.0 vs 40.0 s; seed 1 vs 7")
        self.assertIn("warning: the missions differ (synthetic vs my_ctl)", block[1])
        top = page[:page.index("<img ")]
        for text in ("these runs differ in:", "<li>mission synthetic vs my_ctl</li>", "<li>duration 60.0 vs 40.0 s</li>",
                     "<li>seed 1 vs 7</li>", 'class="warning"'):
            self.assertIn(text, top)

    def test_only_a_parameter_differs(self):
        b = self.other("20260101T000100Z-synthetic")
        edit(os.path.join(b, "params.csv"), "0,slc.max_a,0.5,config", "0,slc.max_a,0.3,config")
        block, page = self.ab(b)
        self.assertEqual(block, ["A/B: 20260101T000000Z-synthetic vs 20260101T000100Z-synthetic: same mission, sensor "
                                 "profile, duration, seed and aircraft: only the compared plugins/parameters differ: "
                                 "parameters (1): slc.max_a 0.5 vs 0.3"])
        top = page[:page.index("<img ")]
        self.assertIn("only the compared plugins/parameters differ", top)
        self.assertNotIn('class="warning"', top)
        self.assertIn('id="param-differences"', page)

    def test_waypoints_moved_under_the_same_name_warn_too(self):
        b = self.other("20260101T000100Z-moved")
        edit(os.path.join(b, "config.yaml"), "    - [100, 0, -50]\n", "    - [100, 80, -50]\n")
        block, _ = self.ab(b)
        self.assertIn("mission waypoints", block[0])
        self.assertIn("warning: the missions differ", block[1])

    def test_identical_runs_differ_in_nothing(self):
        block, page = self.ab(self.other("20260101T000100Z-again"))
        self.assertEqual(block, ["A/B: synthetic vs again: these runs differ in nothing tern plot compares (mission, "
                                 "sensor profile, duration, seed, aircraft, plugins, phases, parameters)"])

    def test_facts_and_plugins_from_summary_and_config(self):
        base = {"label": "A", "run_dir": self.tmp, "t_end": 10.0, "waypoints": (None, True), "flown": None, "params": {},
                "summary": {"mission": "default", "seed": 1, "duration_s": 715.04, "sensor_profile": "realistic"},
                "config": {"aircraft": "/x/anaconda.yaml", "plugins": [{"name": "sim", "plugin": "sim_aero"},
                                                                       {"name": "slc", "plugin": "control_slc"}],
                           "phases": {"takeoff": "slc", "cruise": "slc"}}}
        other = dict(base, label="B", summary={"mission": "default", "seed": 1, "duration_s": 715.0, "sensor_profile": "ideal"},
                     config={"aircraft": "/y/zagi.yaml", "plugins": [{"name": "sim", "plugin": "sim_aero"},
                                                                    {"name": "slc", "plugin": "control_tecs"},
                                                                    {"name": "ctl", "plugin": "my_ctl"}],
                             "phases": {"takeoff": "slc", "cruise": "ctl"}})
        base["summary"]["instances"] = {"sim": {"plugin": "sim_aero", "library_fnv1a": "0f07"}}
        other["summary"]["instances"] = {"sim": {"plugin": "sim_aero", "library_fnv1a": "7284"}}
        base["params"] = {"sim.wind": [(0.0, "[3.5, -3.5, 0]")], "slc.max_a": [(0.0, "0.15")], "slc.kp": [(0.0, "1")]}
        other["params"] = {"sim.wind": [(0.0, "[3.5, -3.5, 0]")], "slc.max_a": [(0.0, "1.5e-1")], "ctl.kp": [(0.0, "2")],
                           "sim.gyro_resolution": [(0.0, "0.001")]}
        d = TC.compare(base, other)
        self.assertEqual([text for _, text in d["facts"]], ["sensor profile realistic vs ideal", "aircraft anaconda.yaml vs zagi.yaml"])
        self.assertEqual(d["setup"], ["instance ctl (my_ctl) only in B", "plugin library of sim (sim_aero): another build "
                                      "(FNV-1a 0f07 vs 7284)", "plugin of slc control_slc vs control_tecs",
                                      "phases.cruise slc vs ctl"])
        # 0.15 = 1.5e-1; ctl's parameters go with its instance; a parameter only one build of sim has
        self.assertEqual(TC.param_items(d), ["parameters only in B (1): sim.gyro_resolution",
                                             "parameters only in A (1): slc.kp"])
        self.assertFalse(d["missions_differ"])
        self.assertIsNone(TC.warning(d))


if __name__ == "__main__":
    unittest.main(verbosity=2, argv=sys.argv[:1] + sys.argv[1:])
