"""tern plot: ground_track.png, the flight seen from above (north up, east on x, equal axes):
true and estimated tracks, the commanded path segments over the stretch the aircraft flew them,
the waypoints as flown (or as configured), the failsafe, fallback and handover positions
numbered on the map, the mean true wind; in an overlay each run's truth, path and waypoints in
the run's colour."""

import math

import numpy as np
import matplotlib.pyplot as plt

import tern_plot_draw as draw  # draw.save: looked up when called (test_plot_pages.py watches it)
from tern_plot_draw import C_CMD, C_TRUE, est
from tern_plot_layout import top_view
from tern_plot_log import MARKER_STYLE

def path_segments(path, pos):
    """Commanded path pieces to draw: [('line', e_xy, n_xy) ...] over the stretch flown."""
    need = ("path_type", "r_n", "r_e", "q_n", "q_e", "c_n", "c_e", "rho")
    if path is None or any(path.get(k) is None for k in need):
        return []
    lam = path.get("lambda") if path.get("lambda") is not None else np.zeros(len(path))
    params = np.column_stack([path.get(k) for k in need] + [lam])
    t = path.get("t")
    change = np.nonzero(np.any(params[1:] != params[:-1], axis=1))[0] + 1
    starts = np.concatenate([[0], change])
    ends = np.concatenate([change, [len(t)]])
    # draw each distinct segment once, over the union of the times it was active
    runs = {}
    for s, e in zip(starts, ends):
        key = tuple(np.round(params[s], 3))
        t0, t1 = t[s], (t[e] if e < len(t) else t[-1])
        runs.setdefault(key, []).append((t0, t1))
    out = []
    pt, pn, pe = pos
    for key, spans in runs.items():
        ptype, r_n, r_e, q_n, q_e, c_n, c_e, rho, _ = key
        sel = np.zeros(len(pt), dtype=bool)
        for t0, t1 in spans:
            sel |= (pt >= t0) & (pt <= t1)
        sel &= np.isfinite(pn) & np.isfinite(pe)
        if int(ptype) == 0 and rho > 0:
            if sel.any():
                ang = np.unwrap(np.arctan2(pe[sel] - c_e, pn[sel] - c_n))
                a0, a1 = ang.min(), ang.max()
                if a1 - a0 >= 2 * np.pi:
                    a0, a1 = 0.0, 2 * np.pi
            else:
                a0, a1 = 0.0, 2 * np.pi
            a = np.linspace(a0, a1, max(8, int(abs(a1 - a0) / (2 * np.pi) * 180)))
            out.append((c_e + rho * np.sin(a), c_n + rho * np.cos(a)))
        elif int(ptype) == 1:
            norm = math.hypot(q_n, q_e)
            if norm < 1e-9:
                continue
            u_n, u_e = q_n / norm, q_e / norm
            s = (pn[sel] - r_n) * u_n + (pe[sel] - r_e) * u_e if sel.any() else np.array([0.0])
            s0, s1 = min(0.0, float(s.min())), max(0.0, float(s.max()))
            out.append((np.array([r_e + s0 * u_e, r_e + s1 * u_e]), np.array([r_n + s0 * u_n, r_n + s1 * u_n])))
    return out


def draw_wind(ax, truth):
    """Arrow (blowing direction) and text of the flight's mean true wind, lower left."""
    if truth is None or truth.get("w_n") is None or truth.get("w_e") is None:
        return
    w_n, w_e = float(np.nanmean(truth.get("w_n"))), float(np.nanmean(truth.get("w_e")))
    speed = math.hypot(w_n, w_e)
    if not math.isfinite(speed):
        return
    text = f"mean wind {speed:.1f} m/s"
    if speed > 0.05:
        frm = math.degrees(math.atan2(-w_e, -w_n)) % 360.0
        text += f" from {frm:.0f} deg"
        u_e, u_n = w_e / speed, w_n / speed
        ax.annotate("", xy=(0.09, 0.12), xycoords="axes fraction", xytext=(-28 * u_e, -28 * u_n),
                    textcoords="offset points", arrowprops=dict(arrowstyle="-|>", color="#444444", lw=1.5))
    ax.text(0.02, 0.03, text, transform=ax.transAxes, fontsize="small", color="#444444")


def draw_mission(ax, run):
    """The waypoints as flown: the list the planner published last (diamonds, dotted order;
    loiter orbits dashed), the list at the start hollow when it differs, the waypoints added in
    flight starred with the time they appeared. Without logged lists: the configured mission."""
    wps, loop = run["waypoints"]
    lists = run["flown"]
    col = run["colour"] if run["overlay"] else C_CMD
    pre = f"{run['label']}: " if run["overlay"] else ""
    if not lists:
        if wps is not None:
            draw_waypoints(ax, wps, loop, col, f"{pre}waypoints")
        return
    t_last, rev, pos, types, radii = lists[-1]
    if len(lists) > 1 and len(lists[0][2]):
        wps0 = lists[0][2]
        ax.plot(wps0[:, 1], wps0[:, 0], "D", color="none", mec="#777777", ms=7,
                label=f"{pre}waypoints at start (rev {lists[0][1]})", zorder=3)
    if not len(pos):
        ax.plot([], [], "D", color=col, ms=7, mec="black", label=f"{pre}waypoints flown last: none (cleared at t {t_last:.4g} s)")
        return
    what = f"flown last (rev {rev}, t {t_last:.4g} s)" if len(lists) > 1 else f"(rev {rev}, no edit in flight)"
    draw_waypoints(ax, pos, run["flown_loop"], col, f"{pre}waypoints {what}")
    for w, typ, r in zip(pos, types, radii):
        if typ == 1 and r > 0:
            a = np.linspace(0, 2 * np.pi, 90)
            ax.plot(w[1] + r * np.sin(a), w[0] + r * np.cos(a), ls="--", color=col, lw=0.8, zorder=2)
    for j, (k, t_add) in enumerate(run["added"]):
        ax.plot(pos[k, 1], pos[k, 0], "*", color="gold", ms=16, mec="black", zorder=6,
                label=f"{pre}added in flight" if j == 0 else None)
        ax.annotate(f"added t {t_add:.4g} s", (pos[k, 1], pos[k, 0]), xytext=(8, -12), textcoords="offset points",
                    fontsize="x-small")


def draw_waypoints(ax, wps, loop, colour, label):
    """The waypoints (diamonds, dotted order), each numbered once (an overlay's runs that fly the
    same waypoints: one number)."""
    order = np.vstack([wps, wps[:1]]) if loop and len(wps) > 2 else wps
    ax.plot(order[:, 1], order[:, 0], ls=":", color="#555555", lw=0.8, zorder=2)
    ax.plot(wps[:, 1], wps[:, 0], "D", color=colour, ms=7, mec="black", label=label, zorder=4)
    for k, w in enumerate(wps):
        if not annotated(ax, f"{k}", (w[1], w[0]), (6, 6)):
            ax.annotate(f"{k}", (w[1], w[0]), xytext=(6, 6), textcoords="offset points", fontsize="small")


def annotated(ax, text, xy, offset, tol=1.0):
    """Whether ax already has the annotation `text` at xy (within tol, data units), written at
    `offset` points from it."""
    return any(getattr(t, "xy", None) is not None and t.get_text() == text and tuple(t.xyann) == offset
               and abs(t.xy[0] - xy[0]) <= tol and abs(t.xy[1] - xy[1]) <= tol for t in ax.texts)


def draw_track_events(ax, run):
    """The estimated position at each failsafe, fallback and handover (not phase) marker: an X
    numbered in time order on the map, named in the legend ("1: failsafe gnss_loss, t 55.0 s"),
    so that no long label lies over the tracks."""
    state = run["state"]
    if state is None or state.get("p_n") is None or len(state) == 0:
        return
    st, sn, se = state.get("t"), est(state, "p_n"), est(state, "p_e")
    pre = f"{run['label']}: " if run["overlay"] else ""
    number = 0
    for t, label, kind in run["markers"]:
        k = min(int(np.searchsorted(st, t)), len(st) - 1)
        if kind == "phase" or not (np.isfinite(sn[k]) and np.isfinite(se[k])):
            continue
        number += 1
        colour = run["colour"] if run["overlay"] else MARKER_STYLE[kind][0]
        ax.plot(se[k], sn[k], "X", color=colour, ms=9, mec="black", zorder=6, label=f"{pre}{number}: {label}, t {t:.1f} s")
        if annotated(ax, f"{number}", (se[k], sn[k]), (-6, -12)):
            continue  # an earlier run's event of the same number at the same place: its number stands
        ax.annotate(f"{number}", (se[k], sn[k]), xytext=(-6, -12), textcoords="offset points", ha="right", fontsize="small",
                    color=colour, fontweight="bold", zorder=7,
                    bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.7))


def fig_ground_track(runs, out):
    fig, ax = plt.subplots(figsize=(9, 10))
    ax.set_title(f"ground track - {' vs '.join(r['label'] for r in runs)}", loc="left", fontsize="medium")
    drew = False
    for first, run in enumerate(runs):
        truth, path = run["truth"], run["current_path"]
        tracks = []
        pre = f"{run['label']}: " if run["overlay"] else ""
        if truth is not None and truth.get("p_n") is not None and truth.get("p_e") is not None:
            tracks.append((pre + "true", truth.get("t"), truth.get("p_n"), truth.get("p_e"),
                           run["colour"] if run["overlay"] else C_TRUE, 1.2))
        if not run["overlay"]:
            for e in run["estimators"]:
                tp = e["topic"]
                if tp.get("p_n") is not None:
                    tracks.append((f"{e['name']} estimated", tp.get("t"), est(tp, "p_n"), est(tp, "p_e"), e["colour"], 0.9))
        segs = path_segments(path, tracks[0][1:4]) if tracks else []
        if not tracks and not segs and run["waypoints"][0] is None and not run["flown"]:
            continue
        drew = True
        for k, (e, n) in enumerate(segs):
            ax.plot(e, n, color=run["colour"] if run["overlay"] else C_CMD, lw=3.0, alpha=0.3, solid_capstyle="round",
                    label=pre + "commanded path" if k == 0 else None, zorder=1)
        draw_mission(ax, run)
        for label, t, n, e, color, lw in tracks:
            ax.plot(e, n, color=color, lw=lw, label=label, zorder=3)
        if tracks:
            _, _, n, e, _, _ = tracks[0]
            ok = np.nonzero(np.isfinite(n) & np.isfinite(e))[0]
            if len(ok):
                ax.plot(e[ok[0]], n[ok[0]], "o", color="#2ca02c", ms=8, label="start" if first == 0 else None, zorder=5)
                ax.plot(e[ok[-1]], n[ok[-1]], "s", color="black", ms=7, label="end" if first == 0 else None, zorder=5)
        draw_track_events(ax, run)
        if first == 0:
            draw_wind(ax, truth)
    if not drew:
        plt.close(fig)
        return "no truth, state, current_path or waypoints"
    top_view(fig, ax)
    draw.save(fig, out, "ground_track.png", "Ground track, north up: true and estimated tracks, the commanded path, "
              "the waypoints (as flown: the last list the planner published, waypoints added in flight starred), "
              "failsafe, fallback and handover positions.", legend=ax.get_legend_handles_labels()[1])
    return None
