"""tern plot: estimation_errors.png, estimate minus truth: per quantity (north, east, altitude,
roll, pitch, yaw, airspeed) each estimator instance's error on the truth's times, its +-3 sigma
band from the logged covariance diagonal (P_diag; the attitude's through the Euler-angle map),
the RMSE over summary.json's window; one run: the raw GNSS fix minus truth too. An overlay:
each run's main estimator in the run's colour."""

import math

import numpy as np

from tern_plot_angles import DEG, wrap_pi
from tern_plot_draw import GNSS_COLOURS, decimate_max, finish, new_figure, plot_ts
from tern_plot_load import last_origin
from tern_plot_log import rmse_window
from tern_plot_mission import lla_to_ned

# Error panels: (key, ylabel, scale, unit)
ERROR_PANELS = [("n", "north [m]", 1.0, "m"), ("e", "east [m]", 1.0, "m"), ("h", "altitude [m]", 1.0, "m"),
                ("phi", "roll phi [deg]", DEG, "deg"), ("theta", "pitch theta [deg]", DEG, "deg"),
                ("psi", "yaw psi [deg]", DEG, "deg"), ("Va", "airspeed Va [m/s]", 1.0, "m/s")]


def rmse(e):
    e = e[np.isfinite(e)]
    return float(np.sqrt(np.mean(e * e))) if len(e) else math.nan


def nan_unwrap(a):
    """An angle (rad) unwrapped over its finite samples (NaN stays NaN), to interpolate it between samples."""
    out = np.full_like(a, np.nan)
    ok = np.isfinite(a)
    if ok.any():
        out[ok] = np.unwrap(a[ok])
    return out


def gnss_errors(ctx, tt, sel):
    """Latest GNSS fix minus truth at the truth's times tt[sel] (n, e, h), or None."""
    g, truth = ctx.get("gnss_ned"), ctx["truth"]
    if g is None or len(g[0]) == 0:
        return None
    idx = np.searchsorted(g[0], tt[sel], side="right") - 1
    have = idx >= 0
    idx = np.clip(idx, 0, len(g[0]) - 1)
    out = []
    for k, field, sign in ((1, "p_n", 1.0), (2, "p_e", 1.0), (3, "p_d", -1.0)):
        e = sign * (g[k][idx] - truth.get(field)[sel])
        e[~have] = np.nan
        out.append(e)
    return out


def euler_sigmas(P, phi, theta):
    """1-sigma of phi, theta, psi from the body-frame attitude-error variances P (N x 3, rad^2):
    Euler-angle errors = W(phi, theta) dtheta (W: body rates to Euler rates); the logged diagonal
    has no cross-covariances, so they are left out."""
    sp, cp, tt, ct = np.sin(phi), np.cos(phi), np.tan(theta), np.cos(theta)
    w = [(np.ones_like(phi), sp * tt, cp * tt), (np.zeros_like(phi), cp, -sp), (np.zeros_like(phi), sp / ct, cp / ct)]
    return [np.sqrt(sum(c * c * P[:, j] for j, c in enumerate(row))) for row in w]


def instance_sigmas(state, tc, bad):
    """([n, e, d], [phi, theta, psi]) 1-sigma of an estimator instance on the times tc from its
    logged P_diag (None where it is not logged or zero); NaN where the estimate is not valid."""
    ts = state.get("t")

    def at(field):
        v = state.get(field)
        return None if v is None else np.interp(tc, ts, v)

    P = np.column_stack([at(f"P_diag_{k}") if state.get(f"P_diag_{k}") is not None else np.full(len(tc), np.nan)
                         for k in range(9)])
    has_p = np.isfinite(P).all(axis=0) & (np.abs(np.nan_to_num(P)).max(axis=0) > 0)
    sig_pos = [np.sqrt(P[:, k]) if has_p[k] else None for k in range(3)]
    sig_att = euler_sigmas(P[:, 6:9], at("phi"), at("theta")) if has_p[6:9].all() else [None] * 3
    for sig in sig_pos + sig_att:
        if sig is not None:
            sig[bad] = np.nan
    return sig_pos, sig_att


def instance_errors(run, inst):
    """(tc, {key: (error, 1-sigma or None)}) of one estimator instance against the truth, on the
    truth's times within the estimate's span; NaN where the estimate is not valid. None if the
    run has no truth."""
    truth, state = run["truth"], inst["topic"]
    if truth is None or state is None or len(state) < 2:
        return None
    ts, tt = state.get("t"), truth.get("t")
    sel = (tt >= ts[0]) & (tt <= ts[-1])
    tc = tt[sel]
    if len(tc) < 2:
        return None
    valid = state.get("valid")
    bad = np.interp(tc, ts, valid) < 1.0 - 1e-9 if valid is not None else np.zeros(len(tc), bool)
    # the truth was moved into the main estimator's frame: this instance's origin may differ
    shift = np.zeros(3)
    o_i, o_true = last_origin(state), run["truth_origin"]
    if o_i is not None and o_true is not None:
        shift = np.array(lla_to_ned(o_i, o_true)) - run["truth_shift"]

    def err(field, angle=False, sign=1.0, k=None):
        ve, vt = state.get(field), truth.get(field)
        if ve is None or vt is None:
            return None
        if angle:
            e = wrap_pi(np.interp(tc, ts, nan_unwrap(ve)) - nan_unwrap(vt)[sel])
        else:
            e = sign * (np.interp(tc, ts, ve) - (vt[sel] - (shift[k] if k is not None else 0.0)))
        e[bad] = np.nan
        return e

    sig_pos, sig_att = instance_sigmas(state, tc, bad)
    out = {"n": (err("p_n", k=0), sig_pos[0]), "e": (err("p_e", k=1), sig_pos[1]), "h": (err("p_d", sign=-1.0, k=2), sig_pos[2]),
           "phi": (err("phi", True), sig_att[0]), "theta": (err("theta", True), sig_att[1]),
           "psi": (err("psi", True), sig_att[2]), "Va": (err("Va"), None)}
    return tc, {k: v for k, v in out.items() if v[0] is not None}


def error_series(runs):
    """[(label, colour, tc, errors, window mask, window label)]: each estimator instance of one run
    in its colour, or each run's main estimator in the run's colour (several)."""
    series = []
    for run in runs:
        mask, wlabel = rmse_window(run)
        for inst in run["estimators"][:1] if run["overlay"] else run["estimators"]:
            r = instance_errors(run, inst)
            if r is None:
                continue
            label = f"{run['label']}: {inst['name']}" if run["overlay"] else inst["name"]
            series.append((label, run["colour"] if run["overlay"] else inst["colour"], r[0], r[1], mask(r[0]), wlabel))
    return series


def draw_error_panel(ax, panel, series, first_key, rmse_table):
    """One quantity's panel: each series' error with its RMSE over the window (legend; into
    rmse_table) and its +-3 sigma band (named in the legend of the first panel, first_key)."""
    key, ylabel, scale, unit = panel
    top = 0.0
    for label, colour, tc, errs, win, wlabel in series:
        if key not in errs:
            continue
        e, sig = errs[key]
        value = rmse(e[win]) * scale
        rmse_table.setdefault(label, {})[key] = value
        plot_ts(ax, tc, e * scale, color=colour, lw=0.8, label=f"{label}: RMSE {value:.3g} {unit} ({wlabel})")
        top = max(top, float(np.nanmax(np.abs(e))) * scale if np.isfinite(e).any() else 0.0)
        if sig is not None:
            tb, sb = decimate_max(tc, 3.0 * sig * scale)
            ax.fill_between(tb, -sb, sb, color=colour, alpha=0.15, lw=0, zorder=1,
                            label=f"{label}: +-3 sigma" if key == first_key else None)
            top = max(top, float(np.nanmax(sb)) if np.isfinite(sb).any() else 0.0)
    ax.axhline(0.0, color="black", lw=0.5)
    ax.set_ylabel(ylabel)
    if top > 0:
        ax.set_ylim(-1.1 * top, 1.1 * top)


def raw_gnss_panel(run, first):
    """[(name, latest GNSS fix minus truth, RMSE over the window)] for n, e, h, or None."""
    tt = run["truth"].get("t")
    tc, win = first[2], first[4]
    raw = gnss_errors(run, tt, np.isin(tt, tc))
    if raw is None:
        return None
    return [(name, e, rmse(e[win])) for name, e in zip(("n", "e", "h"), raw)]


def draw_raw_gnss(ax, raw, first):
    """The raw GNSS fix minus truth (n, e, h) on the first series' times, RMSE over its window."""
    for (name, e, value), colour in zip(raw, GNSS_COLOURS):
        plot_ts(ax, first[2], e, color=colour, lw=0.7, label=f"{name}: RMSE {value:.3g} m ({first[5]})")
    ax.axhline(0.0, color="black", lw=0.5)
    ax.set_ylabel("raw GNSS fix [m]")


def fig_errors(runs, out):
    """One panel per quantity (north, east, altitude, roll, pitch, yaw, airspeed): estimate minus
    truth of each estimator instance in its colour (one run) or each run's main estimator in the
    run's colour (several), its +-3 sigma band (P_diag), and the RMSE over summary.json's window
    in the legend; one run: a panel of the raw GNSS fix minus truth (n, e, h) after the altitude."""
    series = error_series(runs)
    if not series:
        return "needs truth and an estimate over the same time"
    panels = [p for p in ERROR_PANELS if any(p[0] in s[3] for s in series)]
    raw = raw_gnss_panel(runs[0], series[0]) if len(runs) == 1 else None
    n_rows = len(panels) + (raw is not None)
    fig, axes = new_figure(n_rows, "estimation error (estimate - truth), +-3 sigma (P_diag)", runs, row_height=1.7)
    rmse_table = {}
    error_axes = axes[:3] + axes[4:] if raw is not None and len(panels) > 3 else axes[:len(panels)]
    for ax, panel in zip(error_axes, panels):
        draw_error_panel(ax, panel, series, panels[0][0], rmse_table)
    if raw is not None:
        draw_raw_gnss(axes[3] if len(panels) > 3 else axes[-1], raw, series[0])
    finish(fig, axes, runs, out, "estimation_errors.png",
           "Estimate minus truth per quantity, each estimator instance in its colour with its +-3 sigma band from "
           "the logged covariance diagonal (P_diag; attitude through the Euler-angle map, cross-covariances left out); "
           "the raw GNSS fix (latest) minus truth; RMSE over the window summary.json uses (legend).")
    out["figures"][-1]["rmse"] = rmse_table
    return None
