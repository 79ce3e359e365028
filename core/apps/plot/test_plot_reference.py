#!/usr/bin/env python3
"""Tests of tern plot on a truth-free replay (tern_plot_reference.py): run as
`python3 core/apps/plot/test_plot_reference.py` (plain unittest).

Writes a synthetic replay run directory (state, reference 3 m east of the estimate and 1 deg off
in roll, GNSS fixes, innovations, replay_report.json as `tern replay` writes it), runs tern-plot
on it and checks the overlay figures, the frame the reference is drawn in, and index.html's
replay report tables; and that a simulated flight (with truth) gets none of them.
"""

import json
import math
import os
import shutil
import sys
import tempfile
import unittest

from test_tern_plot import ORIGIN, SCRIPT, np, run_plot, write_csv, write_run  # (re-executes with Debian's python3 when numpy is missing)
import tern_plot_reference as TR  # noqa: E402  (on sys.path: test_tern_plot loaded tern-plot)
from tern_plot_mission import _ecef  # noqa: E402

DEG = math.pi / 180.0
REPLAY_FIGURES = ["replay_attitude.png", "replay_track.png", "replay_altitude.png", "replay_wind.png", "replay_nis.png"]
STATE_HEADER = ["t [s]", "stamp [ns]", "p_n [m]", "p_e [m]", "p_d [m]", "v_n [m/s]", "v_e [m/s]", "phi [rad]", "theta [rad]",
                "psi [rad]", "Va [m/s]", "chi [rad]", "w_n [m/s]", "w_e [m/s]", "origin_lat [deg]", "origin_lon [deg]",
                "origin_alt [m]", "origin_valid [bool]", "valid [bool]"]


def ned_to_lla(ned, origin):
    """Inverse of lla_to_ned by Newton steps on the ECEF difference (the test's own conversion)."""
    lat0, lon0 = math.radians(origin[0]), math.radians(origin[1])
    sl, cl, so, co = math.sin(lat0), math.cos(lat0), math.sin(lon0), math.cos(lon0)
    n, e, d = ned
    target = _ecef(*origin) + [-sl * co * n - so * e - cl * co * d, -sl * so * n + co * e - cl * so * d, cl * n - sl * d]
    lla = list(origin)
    for _ in range(5):
        h = 1e-7
        f0 = _ecef(*lla) - target
        jac = []
        for k, step in enumerate((h, h, 1e-3)):
            p = list(lla)
            p[k] += step
            jac.append((_ecef(*p) - _ecef(*lla)) / step)
        lla = list(np.array(lla) - np.linalg.solve(np.array(jac).T, f0))
    return lla


def write_replay(run, duration=40.0, rate=10.0):
    """An estimate flying east at 15 m/s, 30 m up, valid from 1 s; a reference 3 m further east
    and 1 deg more roll; 1 Hz GNSS fixes on the estimate; innovations with a rejected baro."""
    os.makedirs(os.path.join(run, "topics"))
    tp = os.path.join(run, "topics")
    n = int(duration * rate) + 1
    state, ref, inn, gnss = [], [], [], []
    for k in range(n):
        t = k / rate
        p_e = 15.0 * t
        state.append([t, t * 1e9, 0.0, p_e, -30.0, 0.0, 15.0, 0.2, 0.05, math.pi / 2, 15.0, math.pi / 2, 2.0, -1.0,
                      ORIGIN[0], ORIGIN[1], ORIGIN[2], 1, 1 if t >= 1.0 else 0])
        if k % 5 == 0:
            lat, lon, alt = ned_to_lla((0.0, p_e + 3.0, -30.0), ORIGIN)
            ref.append([t, t * 1e9, 0.2 + DEG, 0.05, math.pi / 2, lat, lon, alt, 0.0, 15.0, 0.0, 2.5, -1.0])
        inn.append([t, t * 1e9, 0.3 if k % 10 == 0 else -1, 0.2 if k % 10 == 0 else -1, 2.0 if k == 100 else 0.4, -1, 0.1, -1, -1])
        if k % 10 == 0:
            lat, lon, alt = ned_to_lla((0.0, p_e, -30.0), ORIGIN)
            gnss.append([t, t * 1e9, t * 1e9, 3, 12, lat, lon, alt, 0.0, 15.0, 0.0, 1.0, 2.0, 0.3])
    write_csv(os.path.join(tp, "state.csv"), STATE_HEADER, state)
    write_csv(os.path.join(tp, "reference.csv"), ["t [s]", "stamp [ns]", "phi [rad]", "theta [rad]", "psi [rad]", "lat [deg]",
                                                  "lon [deg]", "alt [m]", "v_n [m/s]", "v_e [m/s]", "v_d [m/s]", "w_n [m/s]",
                                                  "w_e [m/s]"], ref)
    write_csv(os.path.join(tp, "innovations.csv"), ["t [s]", "stamp [ns]", "gnss_pos []", "gnss_vel []", "baro []",
                                                    "diff_pressure []", "mag []", "sideslip []", "normal_force []"], inn)
    write_csv(os.path.join(tp, "gnss.csv"), ["t [s]", "stamp [ns]", "time_of_validity [ns]", "fix_type [enum]", "num_sats []",
                                             "lat [deg]", "lon [deg]", "alt [m]", "vel_n [m/s]", "vel_e [m/s]", "vel_d [m/s]",
                                             "h_acc [m]", "v_acc [m]", "s_acc [m/s]"], gnss)
    fig = {"rms": 1.0, "max": 1.0, "unit": "deg", "samples": 390, "rule": "roll: valid state samples in the window",
           "window": "sensor_log.yaml airborne: [2, 38] s"}
    report = {"window": {"start_s": 2.0, "end_s": 38.0, "rule": "sensor_log.yaml airborne: [2, 38] s"},
              "validity": {"share_valid": 1.0, "first_valid_s": 1.0, "divergences": 0, "valid_to_invalid": 0,
                           "filter_resets": 0, "nan_cells": 0},
              "measurements": {"rule": "per innovations message", "baro": {"gate": "ekf.baro_gate = 10.828", "whole": {
                  "count": 401, "share_rejected": 1 / 401, "mean_nis": 4.35, "p50_nis": 4.33, "p95_nis": 4.33, "p99_nis": 4.33},
                  "window": {"count": 361, "share_rejected": 1 / 361, "mean_nis": 4.36, "p50_nis": 4.33, "p95_nis": 4.33,
                             "p99_nis": 4.33}}},
              "estimator": {"instance": "ekf", "models": {"baro": {"accepted": 400, "rejected": 1, "mean_nis": 0.5}},
                            "resets": {"gnss_resets": 0, "mag_resets": 2}},
              "reference": {"status": "compared", "roll": fig},
              "gnss": {"status": "absent (no topics/gnss.csv)"},
              "wind": {"status": "estimated", "vs_reference": dict(fig, rms=0.5, unit="m/s")}}
    with open(os.path.join(run, "replay_report.json"), "w") as f:
        json.dump(report, f)


class ReplayOverlays(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix="tern_plot_reference_test_")

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_overlays_and_report_tables(self):
        run = os.path.join(self.tmp, "20260101T000000Z-replay-replay")
        write_replay(run)
        p = run_plot(run)
        self.assertEqual(p.returncode, 0, p.stderr)
        for name in REPLAY_FIGURES:
            self.assertNotIn(name + " not drawn", p.stdout)
        plots = os.path.join(run, "plots")
        with open(os.path.join(plots, "figures.json")) as f:
            figures = {x["file"]: x for x in json.load(f)}
        for name in REPLAY_FIGURES:
            self.assertTrue(os.path.getsize(os.path.join(plots, name)) > 1000, name)
        self.assertIn("reference", figures["replay_attitude.png"]["legend"])
        self.assertIn("GNSS (fix time t)", figures["replay_attitude.png"]["legend"])
        self.assertIn("report window", figures["replay_attitude.png"]["legend"])
        self.assertEqual(figures["replay_track.png"]["legend"], ["tern", "reference", "GNSS fixes"])
        self.assertIn("baro: 401 messages, 0.2 % rejected", figures["replay_nis.png"]["legend"])
        drawn = [x.split(":")[0] for x in figures["replay_nis.png"]["legend"] if x != "report window"]
        self.assertEqual(drawn, ["gnss_pos", "gnss_vel", "baro", "mag"])  # the sensors with a fused sample only
        with open(os.path.join(plots, "index.html")) as f:
            page = f.read()
        for needle in ("<h2>Replay report</h2>", 'id="replay"', 'id="replay-nis"', 'id="replay-compare"', 'id="replay-counters"',
                       "sensor_log.yaml airborne: [2, 38] s", "ekf.baro_gate = 10.828", "mag_resets", "absent (no topics/gnss.csv)"):
            self.assertIn(needle, page)

    def test_reference_in_the_estimates_frame(self):
        run = os.path.join(self.tmp, "frame")
        write_replay(run)
        r = TR.load({"run_dir": run})
        n, e, d = r["ref_ned"]
        p_e = r["ref"].get("t") * 15.0
        self.assertLess(abs(n).max(), 1e-3)
        self.assertLess(abs(e - (p_e + 3.0)).max(), 1e-3)  # 3 m east of the estimate, as written
        self.assertLess(abs(d + 30.0).max(), 1e-3)
        self.assertTrue(math.isnan(r["s"]["phi"][0]))  # not valid before 1 s: not drawn

    def test_simulated_flight_gets_none(self):
        run = os.path.join(self.tmp, "sim")
        write_run(run)
        p = run_plot(run)
        self.assertEqual(p.returncode, 0, p.stderr)
        self.assertNotIn("replay_", p.stdout)
        with open(os.path.join(run, "plots", "index.html")) as f:
            self.assertNotIn("Replay report", f.read())


if __name__ == "__main__":
    assert os.path.isfile(SCRIPT)
    unittest.main(argv=sys.argv[:1] + sys.argv[1:])
