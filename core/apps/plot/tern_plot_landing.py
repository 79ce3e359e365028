"""tern plot: landing.png, the landing of a flight with a land item (docs/landing.md).

The runway's frame: along (m, along the runway heading from the glide path's aim point; < 0
short of it), across (m, > 0 right of the centre line) and the height above the runway. Along
and across are in the estimate's NED (tern plot's one frame, the truth moved into it) about the
path manager's aim point: the land item's touchdown point moved back by the flare's float in the
wind (plugins/path/include/tern/path/landing.hpp, aim_offset); the gap between the true and the
estimated track is the estimation error. Heights count from home on both sides, as the landing
does: the estimate's above the manager's touchdown point (the item's altitude counted from home,
the estimate at rest before the takeoff), the truth's above its own height at rest plus the
item's (the estimator's altitude origin, its first GNSS fix, is metres off: the other figures
show that as an altitude error; here the gap is the estimate's drift since the takeoff).
summary.json's metrics.landing measures the touchdown on the truth about the touchdown point on
the field (the item's offset from the aircraft's true position at rest,
core/host/record/landing_report.hpp): that point is marked too, and the touchdown marker is
the true position at metrics.landing's touchdown time.

The land item: topics/current_path.csv's landing rows (the glide path flown: touchdown point r,
direction q, flare and decision heights), else the last list of topics/waypoints_items.csv, else
config.yaml's inline mission waypoints (type: land); missing values are the land item's defaults
the log states (definitions.json "land_item": tern/path/item.hpp's LandSpec). The glide path
starts at the approach entry: where it meets the altitude of the item before the land item, at
least min_entry_heights decision heights up (plugins/path/src/landing.cpp)."""

import math

import numpy as np

from tern_plot_log import codes_named, note, read_topic
from tern_plot_mission import geo_origin, lla_to_ned

LAND_KEYS = ("glide_slope", "flare_height", "decision_height")  # a land item's LandSpec (definitions.json)
LANDING = ("approach", "flare", "rollout", "stopped")
CLIMB_OUT = 8.0  # s of an earlier approach's climb-out drawn after its go-around
C_PLAN, C_FLARE, C_DH, C_TD, C_STOP = "#d62728", "#17becf", "#ff7f0e", "#2ca02c", "#393b79"

# ----------------------------------------------------------------------------------------------
# The land item, in the estimate's NED
# ----------------------------------------------------------------------------------------------


def land_defaults(run):
    """definitions.json's land item defaults (glide_slope, flare_height, decision_height,
    min_entry_heights), NaN for those it lacks."""
    d = run.get("definitions", {}).get("land_item", {})
    out = {}
    for k in LAND_KEYS + ("min_entry_heights",):
        try:
            out[k] = float(d[k])
        except (KeyError, TypeError, ValueError):
            out[k] = math.nan
    return out


def land_item(run, spans):
    """{td (n, e, d), item (n, e), heading, glide_slope, flare_height, decision_height, prev_d, source} or
    None; td: the glide path's aim point, item: the land item's touchdown point; spans: phase_spans(run)."""
    spec = _from_items(run) or _from_config(run)
    path = _from_path(run)
    if path is not None:  # the glide path flown; the item and the one before it from the mission
        path["prev_d"] = spec["prev_d"] if spec else None
        path["item"] = spec["td"][:2] if spec else path["td"][:2]
        return path
    if spec is not None:
        spec["td"][2] -= home_altitude(run, spans)  # the manager counts the item's altitude from home
    return spec


def _from_path(run):
    cols = ["landing", "r_n", "r_e", "r_d", "q_n", "q_e", "q_d", "flare_height", "decision_height"]
    p = read_topic(run["run_dir"], "current_path", [], optional=True, extra=cols)
    if p is None or any(p.get(c) is None for c in cols[:7]):
        return None
    rows = np.nonzero(p.get("landing") > 0.5)[0]
    if not len(rows):
        return None
    k = rows[-1]
    q_n, q_e, q_d = (float(p.get(c)[k]) for c in ("q_n", "q_e", "q_d"))
    spec = {"td": np.array([float(p.get(c)[k]) for c in ("r_n", "r_e", "r_d")]), "heading": math.atan2(q_e, q_n),
            "glide_slope": math.atan2(q_d, math.hypot(q_n, q_e)), "source": "topics/current_path.csv"}
    for key in ("flare_height", "decision_height"):
        spec[key] = float(p.get(key)[k]) if p.get(key) is not None else land_defaults(run)[key]
    return spec


def _from_items(run):
    cols = ["index", "w_0", "w_1", "w_2", "type", "chi_d", "land_glide_slope", "land_flare_height",
            "land_decision_height"]
    items = read_topic(run["run_dir"], "waypoints_items", [], optional=True, extra=cols)
    if items is None or any(items.get(c) is None for c in cols[:6]):
        return None
    last = items.get("t") == items.get("t")[-1]  # the list the planner published last
    order = np.argsort(items.get("index")[last])
    col = {c: items.get(c)[last][order] for c in cols if items.get(c) is not None}
    lands = np.nonzero(np.isin(col["type"].astype(int), codes_named(run.get("definitions", {}).get("item_type", {}), "land")))[0]
    if not len(lands):
        return None
    k = lands[-1]
    spec = {"td": np.array([col["w_0"][k], col["w_1"][k], col["w_2"][k]], dtype=float),
            "heading": float(col["chi_d"][k]), "source": "topics/waypoints_items.csv",
            "prev_d": float(col["w_2"][k - 1]) if k > 0 else None}
    for key in LAND_KEYS:
        spec[key] = float(col["land_" + key][k]) if "land_" + key in col else land_defaults(run)[key]
    return spec


def _from_config(run):
    """The land item of config.yaml's inline mission waypoints (after a mission file's items)."""
    mission = run.get("config", {}).get("mission")
    entries = mission.get("waypoints") if isinstance(mission, dict) else None
    lands = [k for k, e in enumerate(entries or []) if isinstance(e, dict) and e.get("type") == "land"]
    if not lands:
        return None
    k = lands[-1]
    e = entries[k]
    td = _position(e, run)
    if td is None:
        return None
    spec = {"td": td, "heading": float(e.get("heading", e.get("chi_d", 0.0))), "source": "config.yaml",
            "prev_d": None}
    for key in LAND_KEYS:
        spec[key] = float(e.get(key, land_defaults(run)[key]))
    before = _position(entries[k - 1], run) if k > 0 else None
    wps = run.get("waypoints", (None, True))[0]
    if before is None and k == 0 and wps is not None and len(wps):  # the mission file's last item
        before = wps[-1]
    if before is not None and math.isfinite(before[2]):
        spec["prev_d"] = float(before[2])
    return spec


def _position(entry, run):
    """NED of a mission entry ([n, e, d], ned/w, or lla about the estimator's origin), or None."""
    if isinstance(entry, list) and len(entry) == 3:
        return np.array(entry, dtype=float)
    if not isinstance(entry, dict):
        return None
    for key in ("ned", "w"):
        if isinstance(entry.get(key), list) and len(entry[key]) == 3:
            if entry.get("lla") is True:
                return _lla(entry[key], run)
            return np.array(entry[key], dtype=float)
    if isinstance(entry.get("lla"), list) and len(entry["lla"]) == 3:
        return _lla(entry["lla"], run)
    return None


def _lla(lla, run):
    origin = geo_origin(run["state"], run["truth"], run.get("config", {}))
    return None if origin is None else np.array(lla_to_ned([float(x) for x in lla], origin))


def home_altitude(run, spans):
    """Home's altitude in the estimate's frame (m, up): the path manager's home_altitude_m in
    summary.json, else the mean valid estimate during preflight, else 0."""
    for inst in (run["summary"].get("instances") or {}).values():
        if isinstance(inst, dict) and isinstance(inst.get("home_altitude_m"), (int, float)):
            return float(inst["home_altitude_m"])
    state = run["state"]
    pre = [(t0, t1) for t0, t1, name in spans if name == "preflight"]
    if state is not None and pre and state.get("p_d") is not None:
        t = state.get("t")
        sel = (t >= pre[0][0]) & (t <= pre[0][1]) & (state.get("valid") > 0.5)
        if sel.any():
            return float(-np.mean(state.get("p_d")[sel]))
    return 0.0


def entry_height(spec, run, attempts):
    """Height of the approach entry above the touchdown point (m): the item before the land
    item's altitude, else the estimate's at the first approach; at least min_entry_heights
    (definitions.json) decision heights."""
    h = spec["td"][2] - spec["prev_d"] if spec.get("prev_d") is not None else math.nan
    if not math.isfinite(h) and attempts and run["state"] is not None:
        st = run["state"]
        h = float(spec["td"][2] - np.interp(attempts[0]["t0"], st.get("t"), st.get("p_d")))
    floor = land_defaults(run)["min_entry_heights"] * spec["decision_height"]
    return max(h if math.isfinite(h) else 0.0, floor if math.isfinite(floor) else 0.0)


# ----------------------------------------------------------------------------------------------
# Phases: the approaches flown
# ----------------------------------------------------------------------------------------------


def phase_spans(run):
    """[(t0, t1, name)] of the flight's phases: summary.json's phases, else topics/flight_phase.csv
    (names from definitions.json)."""
    changes = [(float(p["start_s"]), str(p.get("phase", "?"))) for p in run["summary"].get("phases", [])]
    ph = run.get("phase")
    if not changes and ph is not None and ph.get("phase") is not None:
        for t, p in zip(ph.get("t"), ph.get("phase").astype(int)):
            name = run.get("definitions", {}).get("phase", {}).get(p, f"phase {p}")
            if not changes or changes[-1][1] != name:
                changes.append((float(t), name))
    ends = [t for t, _ in changes[1:]] + [run["t_end"]]
    return [(t0, max(t1, t0), name) for (t0, name), t1 in zip(changes, ends)]


def approaches(spans):
    """[{t0, t1, go_around (t or None), phases [(t, name)]}] per approach flown: from the phase
    becoming approach to a phase other than the landing's (a go-around), else the flight's end."""
    out = []
    for k, (t0, _, name) in enumerate(spans):
        if name != "approach" or (k and spans[k - 1][2] == "approach"):
            continue
        a = {"t0": t0, "t1": spans[-1][1], "go_around": None, "phases": []}
        for s0, _, n in spans[k:]:
            if n not in LANDING:
                a["t1"] = a["go_around"] = s0
                break
            a["phases"].append((s0, n))
        out.append(a)
    return out


# ----------------------------------------------------------------------------------------------
# The runway's frame
# ----------------------------------------------------------------------------------------------


def runway_frame(spec, n, e, d):
    """(along, across, height above the touchdown point) of NED positions."""
    dn, de = np.asarray(n) - spec["td"][0], np.asarray(e) - spec["td"][1]
    c, s = math.cos(spec["heading"]), math.sin(spec["heading"])
    return dn * c + de * s, -s * dn + c * de, spec["td"][2] - np.asarray(d)


def track(topic, spec, t0, t1, masked=None, dz=0.0):
    """(t, along, across, height - dz) of a state topic's positions within [t0, t1], or None."""
    if topic is None or any(topic.get(f) is None for f in ("p_n", "p_e", "p_d")):
        return None
    t = topic.get("t")
    sel = (t >= t0) & (t <= t1)
    if not sel.any():
        return None
    n, e, d = ((masked(topic, f) if masked else topic.get(f))[sel] for f in ("p_n", "p_e", "p_d"))
    along, across, height = runway_frame(spec, n, e, d)
    return t[sel], along, across, height - dz


def at_time(tr, t, slack=0.1):
    """(along, across, height) of a track at time t (its first sample at or after t; the first
    one for t up to `slack` s before it, as a track logged slower than the phase changes starts
    after the approach began; the last one for t up to `slack` s after it), or None."""
    if tr is None or not (tr[0][0] - slack <= t <= tr[0][-1] + slack):
        return None
    k = min(int(np.searchsorted(tr[0], t)), len(tr[0]) - 1)
    p = (float(tr[1][k]), float(tr[2][k]), float(tr[3][k]))
    return p if all(math.isfinite(x) for x in p) else None


def truth_home(run, spans):
    """The truth's position at rest (n, e, d; its last sample before the takeoff), or None."""
    truth = run["truth"]
    pre = [s for s in spans if s[2] == "preflight"]
    if truth is None or any(truth.get(f) is None for f in ("p_n", "p_e", "p_d")) or not pre:
        return None
    k = int(np.searchsorted(truth.get("t"), pre[0][1], side="left")) - 1
    return None if k < 0 else np.array([truth.get(f)[k] for f in ("p_n", "p_e", "p_d")])


def true_touchdown_point(run, spec, spans):
    """The touchdown point on the field in the runway frame (along, across): the truth's position at
    rest plus the land item's offset, as metrics.landing measures; None without a truth at rest."""
    home = truth_home(run, spans)
    if home is None:
        return None
    item = spec.get("item", spec["td"])
    along, across, _ = runway_frame(spec, home[0] + item[0], home[1] + item[1], 0.0)
    return float(along), float(across)


def truth_rebase(run, spans, spec):
    """How much higher the truth is at rest than the touchdown point of `spec` (m): the truth's
    heights count from its own height at rest, as metrics.landing's do, the estimate's from the
    manager's touchdown point (home's altitude, or the runway its range finder measured; the
    estimator's altitude origin, its first GNSS fix, is metres off; at rest both are on the
    ground). 0 without a truth at rest."""
    home = truth_home(run, spans)
    return 0.0 if home is None else float(-home[2] + spec["td"][2])


# ----------------------------------------------------------------------------------------------
# The figure
# ----------------------------------------------------------------------------------------------

CAPTION = ("Landing in the runway's frame: along the runway heading from the path manager's aim point (the glide "
           "path's end on the runway: the land item's touchdown point moved back by the flare's float in the wind; < 0 "
           "short of it), across the centre line (> 0 right of it), in the estimate's NED with the truth moved into "
           "it. Top: side view, the height above the touchdown point (the estimate's above the manager's touchdown "
           "point, counted from home; the truth's above its own height at rest, as metrics.landing counts): the "
           "planned glide path (the glide slope from the approach entry down to the touchdown point, level beyond), "
           "the flare and decision heights, the true and estimated trajectory of the last approach, its flare and "
           "rollout (earlier approaches that went around fainter, to their go-around and climb-out), the phase "
           "changes, the touchdown (summary.json's metrics.landing, on the truth). Bottom: top view, across (drawn "
           "downwards: seen from above, flying to the right) against along: the centre line, the touchdown point, "
           "the touchdown point on the field (the truth at rest plus the land item's offset, which metrics.landing measures "
           "from), the true and estimated tracks, the touchdown and where the rollout stopped. Right: the same, "
           "closer, from above the decision height to the stop.")


class Landing:
    """landing.png, drawn with tern plot's helpers (save, plt, est, colours)."""

    def __init__(self, helpers):
        self.h = helpers

    def figure(self, runs, out):
        """None when drawn; "" (no note) for several runs or a flight without a land item; else why not."""
        if len(runs) != 1:
            return ""
        run = runs[0]
        spans = phase_spans(run)
        spec = land_item(run, spans)
        if spec is None:
            return ""
        atts = approaches(spans)
        if not atts:
            return f"the land item ({spec['source']}) was never approached: no approach phase"
        spec["entry"] = entry_height(spec, run, atts)
        spec["truth_dz"] = truth_rebase(run, spans, spec)
        spec["field"] = true_touchdown_point(run, spec, spans)
        drawn = [self._tracks(run, spec, a, k + 1 == len(atts)) for k, a in enumerate(atts)]
        if drawn[-1]["truth"] is None and drawn[-1]["est"] is None:
            return "no truth or estimate over the approach"
        fig, axes = self._axes(run, spec)
        self._limits(spec, drawn[-1], axes)
        markers = self._draw(run, spec, drawn, axes)
        side, top = axes["side"][0], axes["top"][0]
        # the legends outside the views (a go-around climbs into any corner): above the side view, below the top view
        side.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), fontsize="x-small", frameon=False, borderaxespad=0.2)
        top.legend(loc="upper center", bbox_to_anchor=(0.75, -0.13), ncol=3, fontsize="x-small", frameon=False)
        legend = side.get_legend_handles_labels()[1] + top.get_legend_handles_labels()[1]
        fig.subplots_adjust(left=0.07, right=0.985, bottom=0.13, top=0.86, hspace=0.22, wspace=0.3)
        self.h["save"](fig, out, "landing.png", CAPTION, markers, legend)
        return None

    def _axes(self, run, spec):
        """The figure: {"side": (whole, closer), "top": (whole, closer)}; the closer ones on the right."""
        fig = self.h["plt"].figure(figsize=(11, 10))
        grid = fig.add_gridspec(2, 3, height_ratios=[1.1, 1.0])
        side, zoom = fig.add_subplot(grid[0, :2]), fig.add_subplot(grid[0, 2])
        top, top_zoom = fig.add_subplot(grid[1, :2], sharex=side), fig.add_subplot(grid[1, 2], sharex=zoom)
        heading = math.degrees(spec["heading"]) % 360.0
        fig.suptitle(f"landing - {run['label']}: runway heading {heading:.0f} deg, glide slope "
                     f"{math.degrees(spec['glide_slope']):.1f} deg, from {spec['source'].split('/')[-1]}{_abandoned(run)}",
                     x=0.01, ha="left", fontsize="medium")
        return fig, {"side": (side, zoom), "top": (top, top_zoom)}

    def _tracks(self, run, spec, a, last):
        """One approach's true and estimated tracks in the runway frame (an earlier one to its
        go-around plus CLIMB_OUT s)."""
        t1 = a["t1"] if last or a["go_around"] is None else a["go_around"] + CLIMB_OUT
        return {"a": a, "last": last, "truth": track(run["truth"], spec, a["t0"], t1, dz=spec["truth_dz"]),
                "est": track(run["state"], spec, a["t0"], t1, self.h["est"])}

    def _draw(self, run, spec, drawn, axes):
        """Everything on the axes; returns the markers' labels (phase changes, go-arounds,
        touchdown, stop)."""
        for ax in axes["side"]:
            self._plan(ax, spec, drawn[-1], ax is axes["side"][0])
        field = spec["field"]
        for k, ax in enumerate(axes["top"]):
            ax.axhline(0.0, color="0.3", lw=1.0, zorder=1, label=None if k else
                       f"runway centre line (heading {math.degrees(spec['heading']) % 360.0:.0f} deg)")
            ax.plot(0.0, 0.0, "D", color=C_PLAN, mec="black", ms=7, zorder=6,
                    label=None if k else "glide path's aim point (path manager's)")
            if field is not None:
                ax.plot(*field, "P", color="gold", mec="black", ms=9, zorder=6, label=None if k else
                        f"touchdown point on the field (truth at rest + item; {field[0]:+.1f} m along, {field[1]:+.1f} m across)")
        markers = []
        for k, d in enumerate(drawn):
            markers += self._approach(d, k + 1, axes)
        return markers + self._touchdown(run, drawn[-1], axes)

    def _plan(self, ax, spec, last, labels):
        """The planned glide path (entry to touchdown, level beyond), flare and decision heights."""
        tan = math.tan(spec["glide_slope"])
        x_end = max(_max_along(last), 50.0)
        length = spec["entry"] / tan
        ax.plot([-length, 0.0, x_end], [spec["entry"], 0.0, 0.0], color=C_PLAN, lw=3.0, alpha=0.35, zorder=1,
                solid_capstyle="round", label=f"planned glide path ({math.degrees(spec['glide_slope']):.1f} deg from the "
                f"entry, {length:.0f} m short, {spec['entry']:.0f} m up)" if labels else None)
        ax.axhline(spec["flare_height"], color=C_FLARE, ls="--", lw=0.9, zorder=1,
                   label=f"flare height {spec['flare_height']:g} m" if labels else None)
        ax.axhline(spec["decision_height"], color=C_DH, ls="--", lw=0.9, zorder=1,
                   label=f"decision height {spec['decision_height']:g} m" if labels else None)
        ax.axvline(0.0, color="0.5", lw=0.6, zorder=1)
        ax.axhline(0.0, color="0.5", lw=0.6, zorder=1)

    def _approach(self, d, number, axes):
        """One approach's tracks (the last full, earlier ones faint) and its phase changes."""
        a, last = d["a"], d["last"]
        style = {"lw": 1.2, "alpha": 1.0} if last else {"lw": 0.8, "alpha": 0.35}
        what = ", ".join((["last"] if last else []) + (["went around"] if a["go_around"] is not None else []))
        what = f"approach {number} ({what})"
        for key, colour, name in (("truth", self.h["C_TRUE"], "true"), ("est", self.h["C_EST"], "estimated")):
            tr = d[key]
            if tr is None:
                continue
            for ax in axes["side"]:
                ax.plot(tr[1], tr[3], color=colour, zorder=3, **style)
            for k, ax in enumerate(axes["top"]):
                ax.plot(tr[1], tr[2], color=colour, zorder=3, label=None if k else f"{name}, {what}", **style)
        ref = d["est"] if d["est"] is not None else d["truth"]
        events = [(t, f"{name} {number}" if name == "approach" or not last else name) for t, name in a["phases"]]
        if a["go_around"] is not None:
            events.append((a["go_around"], f"go-around {number}"))
        out = []
        for j, (t, label) in enumerate(events):
            p = at_time(ref, t)
            if p is not None:
                self._event(axes["side"], p, label, j + number)
                out.append(label)
        return out

    def _event(self, sides, p, label, j):
        """A phase change on the side views: a dot, its label (on the whole view only where the
        closer one does not show it) at one of two heights by j's parity, so that the next event
        and the same event of the approach before do not hide it."""
        for ax in sides:
            ax.plot(p[0], p[2], "o", color="white", mec="black", ms=5, zorder=5)
            x0, x1 = ax.get_xlim()
            if ax is sides[0] and sides[1].get_xlim()[0] <= p[0] <= sides[1].get_xlim()[1]:
                continue
            right = p[0] > x0 + 0.8 * (x1 - x0)  # near the right edge: the label to the left
            ax.annotate(label, (p[0], p[2]), xytext=(-4 if right else 4, 6 + 10 * (j % 2)), textcoords="offset points",
                        ha="right" if right else "left", fontsize="x-small", annotation_clip=True, zorder=8,
                        bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.75))

    def _touchdown(self, run, last, axes):
        """metrics.landing's touchdown (the truth at its time) and the stop point."""
        out = []
        m = run["summary"].get("metrics", {}).get("landing")
        if isinstance(m, dict) and isinstance(m.get("touchdown_t_s"), (int, float)):
            p = at_time(last["truth"], float(m["touchdown_t_s"]))
            if p is not None:
                label = (f"touchdown t {m['touchdown_t_s']:.1f} s (metrics.landing, truth): {_num(m, 'touchdown_along_m')} "
                         f"m along, {_num(m, 'touchdown_across_m')} m across the touchdown point, sink "
                         f"{_num(m, 'sink_rate_mps', '.2f')} m/s")
                for ax in axes["side"]:
                    ax.plot(p[0], p[2], "v", color=C_TD, mec="black", ms=9, zorder=7,
                            label=label if ax is axes["side"][0] else None)
                for ax in axes["top"]:
                    ax.plot(p[0], p[1], "v", color=C_TD, mec="black", ms=9, zorder=7)
                out.append("touchdown")
        stop = self._stop(last, m)
        if stop is not None:
            for k, ax in enumerate(axes["top"]):
                ax.plot(stop[0], stop[1], "s", color=C_STOP, mec="black", ms=8, zorder=7, label=None if k else stop[2])
            out.append("stop")
        return out

    def _stop(self, last, m):
        """(along, across, label) where the rollout stopped (the phase stopped began) or, not
        stopped, ended; on the truth, else the estimate. None before a rollout."""
        tr = last["truth"] if last["truth"] is not None else last["est"]
        stop = [t for t, name in last["a"]["phases"] if name == "stopped"]
        if tr is None or not (stop or last["a"]["phases"][-1][1] == "rollout"):
            return None
        p = at_time(tr, stop[0]) if stop else (float(tr[1][-1]), float(tr[2][-1]), float(tr[3][-1]))
        if p is None:
            return None
        rollout = f", rollout {m['rollout_m']:.0f} m (metrics.landing)" if isinstance(m, dict) and \
            isinstance(m.get("rollout_m"), (int, float)) else ""
        what = "stopped" if stop else "end of the rollout (not stopped)"
        return p[0], p[1], f"{what} ({'true' if tr is last['truth'] else 'estimated'}){rollout}"

    def _limits(self, spec, last, axes):
        """The whole views from the entry to the stop; the closer ones from 1.3 decision heights."""
        (side, zoom), (top, top_zoom) = axes["side"], axes["top"]
        tan = math.tan(spec["glide_slope"])
        lo = min(-spec["entry"] / tan, _min_along(last))
        hi = max(_max_along(last), 20.0)
        pad = 0.02 * (hi - lo)
        side.set_xlim(lo - pad, hi + pad)
        side.set_ylim(min(-2.0, _min_height(last) - 1.0), 1.2 * max(spec["entry"], _max_height(last)))
        z0 = -1.3 * spec["decision_height"] / tan
        zoom.set_xlim(z0, hi + 0.05 * (hi - z0))
        zoom.set_ylim(min(-0.5, _min_height(last, z0) - 0.3), 1.35 * spec["decision_height"])
        for ax in (top, top_zoom):
            ax.invert_yaxis()  # right of the centre line downwards: seen from above, flying to the right
        side.set_ylabel("height above the touchdown point [m]")
        zoom.set_title("closer: decision height to the stop", fontsize="small")
        top.set_ylabel("across [m], > 0 right (down)")
        top.set_xlabel("along the runway heading from the glide path's aim point [m] (< 0 short)")
        top_zoom.set_xlabel("along [m]")
        for ax in (side, zoom, top, top_zoom):
            ax.grid(True, lw=0.4, alpha=0.6)


def _values(last, k, lo=-math.inf):
    """Finite values of column k (1 along, 2 across, 3 height) of the last approach's tracks
    where along >= lo."""
    vals = [tr[k][np.isfinite(tr[k]) & (tr[1] >= lo)] for tr in (last["truth"], last["est"]) if tr is not None]
    return np.concatenate(vals) if vals else np.zeros(0)


def _max_along(last):
    v = _values(last, 1)
    return float(v.max()) if len(v) else 0.0


def _min_along(last):
    v = _values(last, 1)
    return float(v.min()) if len(v) else 0.0


def _max_height(last):
    v = _values(last, 3)
    return float(v.max()) if len(v) else 0.0


def _min_height(last, lo=-math.inf):
    v = _values(last, 3, lo)
    return float(v.min()) if len(v) else 0.0


def _abandoned(run):
    """The title's "; abandoned after N approaches" when the path manager abandoned the landing
    (summary.json's instances), else ""."""
    for inst in (run["summary"].get("instances") or {}).values():
        if isinstance(inst, dict) and inst.get("land_abandoned") == 1:
            return f"; abandoned after {inst.get('land_approaches', 0):.0f} approaches"
    return ""


def _num(m, key, spec="+.1f"):
    v = m.get(key)
    return format(v, spec) if isinstance(v, (int, float)) else "-"
