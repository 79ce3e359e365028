"""tern plot: a run directory read into what the figures draw (load_run): the estimator
instances, truth, commands, path, actuators, phases, summary.json, params.csv, the waypoints
configured and flown, the raw GNSS fixes; the truth and the fixes moved into the main
estimator's NED frame. Before that, check_run_dir refuses what is no run directory, and a
flight logged as MCAP only gets its tables exported."""

import os
import sys

import numpy as np

from tern_plot_draw import INSTANCE_COLOURS
from tern_plot_layout import phase_bands
from tern_plot_log import (
    EXPORTED_TOPICS, STATE_FIELDS, SURFACES, added_waypoints, flight_markers, flown_waypoints, load_estimators,
    read_config, read_definitions, read_params, read_summary, read_topic, topics_dir)
from tern_plot_mission import lla_to_ned, mission_waypoints
from tern_plot_usage import fail

MAIN_TOPICS = ("state", "truth", "controller_command", "controller_internals", "current_path")


def tables_from_mcap(run_dir):
    """A flight logged as MCAP only (log.format mcap, as make fly logs): its tables exported by
    `tern export csv RUN --out TMP` (the tern beside tern-plot, else on PATH), as the CSV log
    writes them (core/apps/export/mcap_csv_export.hpp), into a temporary directory removed at
    exit: the run directory keeps its size."""
    import atexit
    import shutil
    import subprocess
    import tempfile
    tern = os.path.join(os.path.dirname(os.path.abspath(sys.argv[0])), "tern")  # beside tern-plot
    if not os.access(tern, os.X_OK):
        tern = shutil.which("tern")
    if tern is None:
        fail(f"{run_dir}: only flight.mcap, and no tern to export its tables (tern export csv RUN)")
    tmp = tempfile.mkdtemp(prefix="tern-plot-")
    atexit.register(shutil.rmtree, tmp, True)
    out = os.path.join(tmp, "topics")
    p = subprocess.run([tern, "export", "csv", run_dir, "--out", out], capture_output=True, text=True)
    if p.returncode != 0:
        fail(f"{run_dir}: tern export csv failed: {(p.stderr or p.stdout).strip().splitlines()[-1:]}")
    EXPORTED_TOPICS[os.path.realpath(run_dir)] = out


def check_run_dir(run_dir):
    if not os.path.exists(run_dir):
        fail(f"{run_dir}: no such run directory")
    if not os.path.isdir(run_dir):
        fail(f"{run_dir}: not a directory (give the run directory tern fly wrote)")
    if not os.path.isdir(os.path.join(run_dir, "topics")) and os.path.isfile(os.path.join(run_dir, "flight.mcap")):
        tables_from_mcap(run_dir)
    if not os.path.isdir(topics_dir(run_dir)):
        fail(f"{run_dir}: not a tern run directory (no topics/ folder)")
    if not any(os.path.isfile(os.path.join(topics_dir(run_dir), t + ".csv")) for t in MAIN_TOPICS):
        fail(f"{run_dir}: no plottable topic in topics/ (none of {', '.join(t + '.csv' for t in MAIN_TOPICS)})")


def last_origin(topic):
    """The topic's last valid origin (lat, lon, alt), or None."""
    if topic is None:
        return None
    lat, lon, alt, ok = (topic.get(k) for k in ("origin_lat", "origin_lon", "origin_alt", "origin_valid"))
    if lat is None or lon is None or alt is None or ok is None:
        return None
    idx = np.nonzero(ok > 0.5)[0]
    return (float(lat[idx[-1]]), float(lon[idx[-1]]), float(alt[idx[-1]])) if len(idx) else None


def truth_into_estimator_frame(ctx):
    """Shifts the truth's positions into the main estimator's NED frame (the two origins differ
    by the GNSS error of the fix the estimator took as its origin; the shift is kept as
    ctx["truth_shift"]), and adds the GNSS fixes in that frame as ctx["gnss_ned"] = (t, n, e, d)."""
    truth, state, gnss = ctx["truth"], ctx["state"], ctx["gnss"]
    o_est, o_true = last_origin(state), last_origin(truth)
    ctx["truth_shift"] = np.zeros(3)
    ctx["truth_origin"] = o_true
    if truth is not None and o_est is not None and o_true is not None:
        off = lla_to_ned(o_est, o_true)  # the estimator's origin in the truth's frame
        ctx["truth_shift"] = np.array(off)
        for k, field in enumerate(("p_n", "p_e", "p_d")):
            if truth.get(field) is not None:
                truth.cols[field] = truth.get(field) - off[k]
    ctx["gnss_ned"] = None
    o = o_est or o_true
    if gnss is not None and o is not None and gnss.get("lat") is not None:
        ok = gnss.get("fix_type") >= 3 if gnss.get("fix_type") is not None else np.ones(len(gnss), bool)
        pts = np.array([lla_to_ned((la, lo, al), o) for la, lo, al in
                        zip(gnss.get("lat")[ok], gnss.get("lon")[ok], gnss.get("alt")[ok])]).reshape(-1, 3)
        ctx["gnss_ned"] = (gnss.get("t")[ok], pts[:, 0], pts[:, 1], pts[:, 2])


def load_run(run_dir, overlay):
    """Everything the figures draw of one run directory."""
    run_dir = os.path.abspath(run_dir)
    cfg, cfg_source = read_config(run_dir)
    ctx = {"run_name": os.path.basename(run_dir.rstrip("/")), "run_dir": run_dir, "overlay": overlay}
    ctx["label"] = ctx["run_name"]
    ctx["config"] = cfg
    ctx["estimators"] = load_estimators(run_dir, cfg, cfg_source)
    for k, e in enumerate(ctx["estimators"]):
        e["colour"] = INSTANCE_COLOURS[k % len(INSTANCE_COLOURS)]
    ctx["state"] = next((e["topic"] for e in ctx["estimators"] if e["topic"].name == "state"), None)
    ctx["truth"] = read_topic(run_dir, "truth", STATE_FIELDS + ["w_n", "w_e"], extra=["Vg"])
    ctx["controller_command"] = read_topic(run_dir, "controller_command", ["Va_c", "h_c", "chi_c"])
    ctx["controller_internals"] = read_topic(run_dir, "controller_internals", ["phi_c", "theta_c"])
    ctx["current_path"] = read_topic(run_dir, "current_path", ["path_type", "r_n", "r_e", "q_n", "q_e",
                                                               "c_n", "c_e", "rho", "lambda"])
    ctx["actuators"] = read_topic(run_dir, "actuators", [f for f, _, _ in SURFACES])
    ctx["phase"] = read_topic(run_dir, "flight_phase", ["phase"])
    present = [ctx[k] for k in MAIN_TOPICS if ctx[k] is not None]
    if not present:
        fail(f"{run_dir}: no plottable rows in topics/ ({', '.join(t + '.csv' for t in MAIN_TOPICS)})")
    ctx["t_end"] = max(float(tp.get("t")[-1]) for tp in present)
    ctx["definitions"] = read_definitions(run_dir)
    ctx["bands"] = phase_bands(ctx["phase"], ctx["t_end"], ctx["definitions"]["phase"])
    ctx["summary"] = read_summary(run_dir)
    ctx["params"] = read_params(run_dir)
    ctx["markers"] = flight_markers(ctx["summary"])
    # the raw-GNSS baseline is optional (a flight on hardware or a replay without gnss has none)
    ctx["gnss"] = read_topic(run_dir, "gnss", ["lat", "lon", "alt", "fix_type"], optional=True)
    ctx["waypoints"] = mission_waypoints(run_dir, ctx["state"], ctx["truth"])
    ctx["flown"] = flown_waypoints(run_dir)
    ctx["added"] = added_waypoints(ctx["flown"])
    loop = read_topic(run_dir, "waypoints", ["loop"], optional=True)
    ctx["flown_loop"] = bool(loop.get("loop")[-1] > 0.5) if loop is not None and loop.get("loop") is not None else True
    truth_into_estimator_frame(ctx)
    return ctx
