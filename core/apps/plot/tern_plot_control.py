"""tern plot: how the aircraft was controlled, command against response: the tracking figures
(altitude.png, airspeed.png, course.png, roll_pitch.png: true, estimated and commanded, the
tracking RMSE over summary.json's window), actuators.png (the commands against the limits of the
controller flying, the stretches at a limit shaded) and, for a `tern tune` flight, tune.png."""

import os

import numpy as np

from tern_plot_angles import DEG, circle_axis, course_where_moving, wrap_deg, wrap_pi
from tern_plot_draw import C_CMD, C_EST, C_TRUE, est, finish, new_figure, plot_angle, plot_ts, steps
from tern_plot_errors import rmse
from tern_plot_log import SURFACES, actuator_limits, host_limits, rmse_window, saturation_spans

# Tracking figures: (file, title, caption, panels); a panel: (ylabel, truth/estimate field, sign,
# command topic, command field, angle?)
TRACKING = [
    ("altitude.png", "altitude", "Altitude h = -p_d: true, estimated, commanded h_c.",
     [("h = -p_d [m]", "p_d", -1.0, "controller_command", "h_c", False, "altitude_m", "m")]),
    ("airspeed.png", "airspeed", "Airspeed Va: true, estimated, commanded Va_c.",
     [("Va [m/s]", "Va", 1.0, "controller_command", "Va_c", False, "airspeed_mps", "m/s")]),
    ("course.png", "course", "Course chi (deg, wrapped into -180..180, each line broken where it wraps): true, "
     "estimated, commanded chi_c.",
     [("course chi [deg]", "chi", 1.0, "controller_command", "chi_c", True, "course_deg", "deg")]),
    ("roll_pitch.png", "roll and pitch", "Roll phi and pitch theta: true, estimated, commanded (controller_internals).",
     [("roll phi [deg]", "phi", 1.0, "controller_internals", "phi_c", True, "roll_deg", "deg"),
      ("pitch theta [deg]", "theta", 1.0, "controller_internals", "theta_c", True, "pitch_deg", "deg")]),
]


def tracking_rmse(run, field, sign, cmd_topic, cmd_field, angle):
    """RMSE of command minus the main estimate over summary.json's window, as its metrics
    compute it (the latest command at each estimate; angles wrapped, deg), or None."""
    state, cmd = run["state"], run[cmd_topic]
    if state is None or cmd is None or state.get(field) is None or cmd.get(cmd_field) is None:
        return None
    ts, tc = state.get("t"), cmd.get("t")
    idx = np.searchsorted(tc, ts, side="right") - 1
    c = np.where(idx >= 0, cmd.get(cmd_field)[np.clip(idx, 0, len(tc) - 1)], np.nan)
    e = c - sign * est(state, field)
    if angle:
        e = wrap_pi(e) * DEG
    return rmse(e[rmse_window(run)[0](ts)])


def tracking_lines(run, field, sign, cmd_topic, cmd_field):
    """[(label, t, v, colour, lw, ls)]: truth, each estimator (one run) and the command."""
    lines = []
    pre = f"{run['label']}: " if run["overlay"] else ""
    truth, cmd = run["truth"], run[cmd_topic]
    if truth is not None and truth.get(field) is not None:
        lines.append((pre + "true", truth.get("t"), sign * moving(truth, field, truth.get(field)),
                      run["colour"] if run["overlay"] else C_TRUE, 1.2, "-"))
    if not run["overlay"]:
        for e in run["estimators"]:
            tp = e["topic"]
            if tp.get(field) is not None:
                lines.append((f"{e['name']} estimated", tp.get("t"), sign * moving(tp, field, est(tp, field)), e["colour"], 0.9, "-"))
    if cmd is not None and cmd.get(cmd_field) is not None:
        lines.append((f"{pre}commanded {cmd_field}", cmd.get("t"), cmd.get(cmd_field),
                      run["colour"] if run["overlay"] else C_CMD, 1.0, "--"))
    return lines


def moving(topic, field, v):
    """v; the course (chi) only where the ground speed Vg is at least MIN_COURSE_VG (NaN at rest,
    where it is noise)."""
    return course_where_moving(v, topic.get("Vg")) if field == "chi" else v


def with_tracking_rmse(lines, value, unit, window):
    """The command's legend entry (the last line) with its tracking RMSE and window."""
    if value is None or not lines or not lines[-1][0].split(": ")[-1].startswith("commanded"):
        return lines
    label, *rest = lines[-1]
    return lines[:-1] + [(f"{label}: tracking RMSE {value:.3g} {unit} ({window})", *rest)]


def wrap_lines(lines):
    """Angles (rad) in deg, each series wrapped into [-180, 180) on its own."""
    return [(label, t, wrap_deg(v), colour, lw, ls) for label, t, v, colour, lw, ls in lines]


def fig_tracking(runs, out, fname, title, caption, panels):
    rows, table = [], {}
    for ylabel, field, sign, cmd_topic, cmd_field, angle, key, unit in panels:
        lines = []
        for run in runs:
            value = tracking_rmse(run, field, sign, cmd_topic, cmd_field, angle)
            if value is not None:
                table.setdefault(run["label"], {})[key] = value
            lr = with_tracking_rmse(tracking_lines(run, field, sign, cmd_topic, cmd_field), value, unit,
                                    rmse_window(run)[1])
            lines += wrap_lines(lr) if angle else lr
        rows.append((ylabel, lines, angle, field == "chi"))
    if not any(row[1] for row in rows):
        return f"no {', '.join(p[1] for p in panels)} or command logged"
    fig, axes = new_figure(len(rows), title, runs)
    for ax, (ylabel, lines, angle, circle) in zip(axes, rows):
        for label, t, v, colour, lw, ls in lines:
            (plot_angle if angle else plot_ts)(ax, t, v, color=colour, lw=lw, ls=ls, label=label)
        ax.set_ylabel(ylabel)
        if circle:
            circle_axis(ax)
    finish(fig, axes, runs, out, fname, caption + " Tracking RMSE (command - estimate) over summary.json's window "
           "in the legend. Markers: phases, controller handovers, fallback, failsafes.")
    out["figures"][-1]["tracking_rmse"] = table
    return None


def fig_actuators(runs, out):
    """delta_a, delta_e, delta_r (rad) and delta_t against time, with the active controller's
    limits (params.csv: max_a ...; step lines), the host's max_deflection, and the stretches at
    a limit shaded."""
    have = [r for r in runs if r["actuators"] is not None]
    if not have:
        return "no actuators logged"
    fig, axes = new_figure(4, "actuators", runs, row_height=2.0)
    for run in have:
        act = run["actuators"]
        t = act.get("t")
        lims = actuator_limits(run["summary"], run["params"], t)
        host = host_limits(run["params"], t)
        pre = f"{run['label']}: " if run["overlay"] else ""
        col = run["colour"] if run["overlay"] else C_EST
        for ax, (field, name, _) in zip(axes, SURFACES):
            v = act.get(field)
            if v is None:
                continue
            lo, hi, sources = lims[field]
            spans = saturation_spans(t, v, lo, hi)
            at = sum(t1 - t0 for t0, t1 in spans)
            span_t = max(float(t[-1] - t[0]), 1e-9)
            plot_ts(ax, t, v, color=col, lw=0.8, label=f"{pre}{field} (at a limit {100 * at / span_t:.1f} % of the time, shaded)")
            for k, (t0, t1) in enumerate(spans):
                ax.axvspan(t0, t1, color=col if run["overlay"] else C_CMD, alpha=0.18, lw=0, zorder=1)
            lim_col = run["colour"] if run["overlay"] else C_CMD
            if sources:
                ax.plot(*steps(t, hi), color=lim_col, lw=1.2, ls="-" if not run["overlay"] else "-.",
                        drawstyle="steps-post", label=f"{pre}controller limit ({', '.join(sources)}; params.csv)")
                ax.plot(*steps(t, lo), color=lim_col, lw=1.2, ls="-" if not run["overlay"] else "-.", drawstyle="steps-post")
            hlo, hhi = host[field]
            if np.isfinite(hhi).any() and not run["overlay"]:
                what = "host max_deflection (fallback beyond)" if field != "delta_t" else "host 0..1"
                ax.plot(*steps(t, hhi), color="#555555", lw=0.8, ls=":", drawstyle="steps-post", label=what)
                ax.plot(*steps(t, hlo), color="#555555", lw=0.8, ls=":", drawstyle="steps-post")
            ax.set_ylabel(f"{name} {field} [{'rad' if field != 'delta_t' else '0..1'}]")
    finish(fig, axes, runs, out, "actuators.png",
           "Actuator commands (topic actuators) with the active controller's limits from params.csv (step lines: "
           "they change with the controller that flies, summary.json's handovers) and the host's max_deflection; "
           "the stretches at a limit are shaded.")
    return None


def fig_tune(runs, out):
    """tune.png, when the run is a `tern tune` flight: the loop's command and response
    (tune.csv: t, command, response) from the signal's engagement, with each measured step's
    rise time and overshoot (tune_steps.csv) written at its edge."""
    run = runs[0]
    path = os.path.join(run["run_dir"], "tune.csv")
    if len(runs) > 1 or not os.path.isfile(path):
        return None  # not a tune flight: nothing to say
    with open(path, encoding="utf-8") as f:
        header = f.readline().rstrip("\r\n").split(",")
    data = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2, dtype=float)
    if data.shape[0] == 0:
        return "tune.csv has no rows"
    fig, axes = new_figure(1, f"tune: {header[1]} vs {header[2]}", runs)
    plot_ts(axes[0], data[:, 0], data[:, 1], color=C_CMD, lw=1.0, ls="--", label=f"commanded {header[1]}")
    plot_ts(axes[0], data[:, 0], data[:, 2], color=C_EST, lw=0.9, label=f"estimated {header[2]}")
    steps_path = os.path.join(run["run_dir"], "tune_steps.csv")
    if os.path.isfile(steps_path):
        steps = np.loadtxt(steps_path, delimiter=",", skiprows=1, ndmin=2, dtype=float)
        for row in steps:
            axes[0].axvline(row[0], color="0.6", lw=0.5)
            axes[0].annotate(f"tr {row[3]:.2f} s\nOS {row[4]:.0f} %", (row[0], row[2]), fontsize="x-small",
                             xytext=(3, 0), textcoords="offset points")
    axes[0].set_ylabel(header[1].replace("_c", ""))
    finish(fig, axes, runs, out, "tune.png", "tern tune: the tuned loop's command and response, each step's rise "
           "time and overshoot.", xlim=(data[0, 0], data[-1, 0]))
    return None
