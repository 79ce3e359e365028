"""tern plot: what goes into a plots directory. plot_runs: every figure of one run or of an
overlay of several (the runs coloured and labelled by their directory names), a note for each
figure that cannot be drawn, what differs between the runs (tern_plot_compare.py) and
index.html. plot_fleet: a multi-vehicle run's, each vehicle's figures in a folder of its own,
then the fleet's figures and page (tern_plot_fleet.py)."""

import os
import re

from tern_plot_compare import compare_runs, html_block, param_rows
from tern_plot_control import TRACKING, fig_actuators, fig_tracking, fig_tune
from tern_plot_draw import C_EST, C_TRUE, RUN_COLOURS, est, figure_helpers
from tern_plot_errors import fig_errors
from tern_plot_fleet import Fleet, FleetError, read_fleet, write_fleet_index
from tern_plot_html import write_index
from tern_plot_landing import Landing
from tern_plot_load import check_run_dir, last_origin, load_run
from tern_plot_log import NOTE_SCOPE, note
from tern_plot_reference import Overlays
from tern_plot_track import fig_ground_track
from tern_plot_usage import fail
from tern_plot_view3d import fleet_view3d

def figures():
    """[(file, function of (runs, out) returning None or why it was not drawn)]."""
    out = [("ground_track.png", fig_ground_track)]
    for fname, title, caption, panels in TRACKING:
        out.append((fname, lambda runs, o, a=(fname, title, caption, panels): fig_tracking(runs, o, *a)))
    out += [("actuators.png", fig_actuators), ("estimation_errors.png", fig_errors), ("tune.png", fig_tune)]
    helpers = figure_helpers()
    landing = Landing(dict(helpers, est=est, C_TRUE=C_TRUE, C_EST=C_EST))  # tern_plot_landing.py
    out.append(("landing.png", landing.figure))
    return out + Overlays(helpers).figures()  # a truth-free replay's (tern_plot_reference.py)


def plot_runs(run_dirs, out_dir):
    """Draws run_dirs (one run, or the overlay of several) into out_dir (default: the first
    run's plots/, or its plots/vs-<others>/), index.html included; returns (runs, out)."""
    for d in run_dirs:
        check_run_dir(d)
    overlay = len(run_dirs) > 1
    runs = [load_run(d, overlay) for d in run_dirs]
    for k, run in enumerate(runs):
        run["colour"] = RUN_COLOURS[k % len(RUN_COLOURS)]
    short = [re.sub(r"^\d{8}T\d{6}Z-", "", r["run_name"]) for r in runs]
    if overlay and len(set(short)) == len(runs):  # labels: the names without tern fly's time stamp
        for run, label in zip(runs, short):
            run["label"] = label
    if len(set(r["label"] for r in runs)) < len(runs):  # the same directory name twice: number them
        for k, run in enumerate(runs):
            run["label"] = f"{k + 1}:{run['label']}"
    if out_dir is None:
        out_dir = os.path.join(runs[0]["run_dir"], "plots")
        if overlay:
            out_dir = os.path.join(out_dir, "vs-" + "+".join(r["run_name"] for r in runs[1:]))
    out = make_out_dir(out_dir)
    for fname, func in figures():
        why = func(runs, out)
        if why:
            note(f"{fname} not drawn: {why}")
    if not out["written"]:
        fail(f"{run_dirs[0]}: nothing to plot")
    out["differences"] = compare_runs(runs)
    try:
        write_index(runs, out, html_block(out["differences"]), param_rows(out["differences"]))
    except OSError as e:
        fail(f"{out['dir']}/index.html: cannot write ({e.strerror})")
    return runs, out


def make_out_dir(out_dir):
    """Creates out_dir; the record of what is drawn into it: {dir, written, figures}."""
    try:
        os.makedirs(out_dir, exist_ok=True)
    except OSError as e:
        fail(f"{out_dir}: cannot create the plots directory ({e.strerror})")
    return {"dir": os.path.abspath(out_dir), "written": [], "figures": []}


def plot_fleet(fleet_dir, out_dir):
    """A multi-vehicle run (fleet.json, tern_plot_fleet.py): each vehicle's standard figures into
    <plots>/<vehicle>/, the fleet's tracks, altitude and separation and its index.html into
    <plots>/ (default FLEET_DIR/plots)."""
    try:
        fleet = read_fleet(fleet_dir)
    except FleetError as e:
        fail(str(e))
    out_dir = out_dir if out_dir is not None else os.path.join(fleet_dir, "plots")
    for name in fleet["vehicles"]:
        check_run_dir(os.path.join(fleet_dir, name))
    vehicles = []
    for name in fleet["vehicles"]:
        NOTE_SCOPE[0] = f"{name}: "
        runs, vout = plot_runs([os.path.join(fleet_dir, name)], os.path.join(out_dir, name))
        vehicles.append({"name": name, "run": runs[0], "out": vout})
    NOTE_SCOPE[0] = ""
    out = make_out_dir(out_dir)
    drawing = Fleet(dict(figure_helpers(), est=est, last_origin=last_origin, RUN_COLOURS=RUN_COLOURS))
    drawing.draw(fleet, vehicles, out)
    out["view3d"] = fleet_view3d(vehicles, drawing.origin, out["dir"])
    try:
        write_fleet_index(fleet, vehicles, out)
    except OSError as e:
        fail(f"{out['dir']}/index.html: cannot write ({e.strerror})")
    return [p for v in vehicles for p in v["out"]["written"]] + out["written"], out
