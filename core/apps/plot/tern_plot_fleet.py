"""tern plot: a multi-vehicle run (issue 42): one run directory with fleet.json, summary.json (the
fleet's figures: per vehicle, and the separation), a complete flight log per vehicle in
<vehicle>/ and, with coordination plugins, their log in coordination/.

The fleet's figures put every vehicle in one frame, the world NED: the simulators' shared frame
(each vehicle's truth topic is in it), about the first vehicle's truth origin (else, with no
truth logged, the first vehicle's estimator origin). A vehicle's estimate is in its own NED about
its first GNSS fix (the state's origin_lat/lon/alt) and is moved into the world frame exactly
through ECEF on WGS84 (tern_plot_mission.ned_to_ned: the origins' offset and the tilt between
the two tangent planes), the conversion tern's C++ side and the rest of tern plot use.

The vehicles' times are one clock (the fleet's flight time), so their positions at one t are
compared as logged: each pair's distance on the first vehicle's sample times within both logs'
span, the second's position interpolated linearly."""

import html
import json
import math
import os

import numpy as np

from tern_plot_html import figure_html, fmt_value, html_table, write_page
from tern_plot_log import note
from tern_plot_mission import ned_to_ned
from tern_plot_view3d import VIEW3D_STYLE


class FleetError(Exception):
    """A fleet.json that cannot be drawn: the message names the file and the field."""


def read_fleet(fleet_dir):
    """fleet.json as a dict whose "vehicles" is a non-empty list of distinct directory names,
    each a directory of fleet_dir; FleetError (one line naming the file and field) otherwise."""
    path = os.path.join(os.path.abspath(fleet_dir), "fleet.json")
    try:
        with open(path, encoding="utf-8") as f:
            fleet = json.load(f)
    except OSError as e:
        raise FleetError(f"{path}: cannot read ({e.strerror})") from None
    except ValueError as e:
        raise FleetError(f"{path}: not JSON ({e})") from None
    if not isinstance(fleet, dict):
        raise FleetError(f"{path}: not a JSON object")
    if "vehicles" not in fleet:
        raise FleetError(f'{path}: field "vehicles" missing (the list of the vehicles\' directory names)')
    names = fleet["vehicles"]
    if not isinstance(names, list) or not names:
        raise FleetError(f'{path}: field "vehicles" is not a non-empty list of the vehicles\' directory names')
    for k, name in enumerate(names):
        if not isinstance(name, str) or name in ("", ".", "..") or "/" in name or "\\" in name:
            raise FleetError(f'{path}: field "vehicles"[{k}] ({json.dumps(name)}) is not a directory name')
        if names.index(name) != k:
            raise FleetError(f'{path}: field "vehicles" names "{name}" twice')
        vdir = os.path.join(os.path.dirname(path), name)
        if not os.path.isdir(vdir):
            raise FleetError(f'{path}: field "vehicles"[{k}] "{name}": no such directory {vdir}')
    fleet["_dir"] = os.path.dirname(path)
    fleet["_summary"] = {}
    spath = os.path.join(fleet["_dir"], "summary.json")
    try:
        with open(spath, encoding="utf-8") as f:
            summary = json.load(f)
        fleet["_summary"] = summary if isinstance(summary, dict) else {}
    except OSError:
        note("summary.json missing: no per-vehicle results, closest approach or min_distance from it")
    except ValueError as e:
        note(f"summary.json not readable ({e}): no per-vehicle results, closest approach or min_distance from it")
    return fleet


def fleet_colours(n, base):
    """n distinct colours: tern plot's run colours, then tab20's others, then hues around."""
    import matplotlib
    out = list(base[:n])
    for c in matplotlib.colormaps["tab20"].colors:
        hexc = matplotlib.colors.to_hex(c)
        if len(out) < n and hexc not in out:
            out.append(hexc)
    k = 0
    while len(out) < n:
        out.append(matplotlib.colors.to_hex(matplotlib.colors.hsv_to_rgb(((k * 0.618034) % 1.0, 0.8, 0.7))))
        k += 1
    return out


def _number(x):
    return isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x)


class Fleet:
    """The fleet's figures (tracks.png, altitude.png, separation.png) from the vehicles' loaded
    runs; helpers: the drawing functions of tern_plot_draw.py (new_figure, finish, save, plot_ts, plt,
    est, RUN_COLOURS) and tern_plot_load.py's last_origin."""

    def __init__(self, helpers):
        self.h = helpers

    # -- positions in the world frame ----------------------------------------------------------

    def world_origin(self, vehicles):
        """(origin, what it is): the first vehicle's truth origin, else its state's."""
        for v in vehicles:
            if v["run"]["truth_origin"] is not None:
                return v["run"]["truth_origin"], f"{v['name']}'s truth origin (the simulators' shared origin)"
        for v in vehicles:
            o = self.h["last_origin"](v["run"]["state"])
            if o is not None:
                return o, f"{v['name']}'s estimator origin (no truth logged)"
        return None, "none: no truth and no valid estimator origin"

    def track(self, v, origin):
        """(source, t, N x 3 world NED) of a vehicle: its truth when logged, else its estimate
        (NaN where not valid) moved into the world frame; None (with a note) if neither can be."""
        run, name = v["run"], v["name"]
        truth = run["truth"]
        if truth is not None and all(truth.get(f) is not None for f in ("p_n", "p_e", "p_d")):
            # load_run moved the truth into the vehicle's estimator frame by truth_shift: undone
            p = np.column_stack([truth.get(f) for f in ("p_n", "p_e", "p_d")]) + run["truth_shift"]
            o_true = run["truth_origin"]
            if o_true is not None and origin is not None and tuple(o_true) != tuple(origin):
                p = ned_to_ned(p, o_true, origin)
            return "true", truth.get("t"), p
        state = run["state"]
        o_est = self.h["last_origin"](state)
        if state is None or state.get("p_n") is None:
            note(f"{name}: no truth and no state: not in the fleet's figures")
            return None
        if o_est is None or origin is None:
            note(f"{name}: no truth and no valid origin in topics/state.csv: not in the fleet's figures")
            return None
        p = np.column_stack([self.h["est"](state, f) for f in ("p_n", "p_e", "p_d")])
        return "estimated", state.get("t"), ned_to_ned(p, o_est, origin)

    # -- figures -------------------------------------------------------------------------------

    def draw(self, fleet, vehicles, out):
        colours = fleet_colours(len(vehicles), self.h["RUN_COLOURS"])
        origin, origin_what = self.world_origin(vehicles)
        for v, c in zip(vehicles, colours):
            v["colour"] = c
            v["track"] = self.track(v, origin)
        self.origin, self.origin_what = origin, origin_what
        self.mission = str(fleet.get("mission", os.path.basename(fleet["_dir"])))
        drawn = [v for v in vehicles if v["track"] is not None]
        summary = fleet.get("_summary", {})
        sep = summary.get("separation") if isinstance(summary.get("separation"), dict) else {}
        self.pairs = pair_distances(drawn)
        closest = self.summary_closest(sep, drawn) or self.computed_closest("3d")
        if not drawn:
            note("tracks.png, altitude.png, separation.png not drawn: no vehicle has truth or a placed estimate")
            return
        self.fig_tracks(drawn, out, closest)
        self.fig_altitude(drawn, out)
        why = self.fig_separation(drawn, out, sep)
        if why:
            note(f"separation.png not drawn: {why}")

    def summary_closest(self, sep, drawn):
        """summary.json's closest approach as {pair, t_s, distance_m, source}, or None."""
        pair, t, d = sep.get("pair"), sep.get("t_s"), sep.get("closest_approach_m")
        names = [v["name"] for v in drawn]
        if (isinstance(pair, list) and len(pair) == 2 and all(p in names for p in pair) and _number(t)
                and _number(d)):
            return {"pair": list(pair), "t_s": float(t), "distance_m": float(d), "source": "summary.json"}
        return None

    def computed_closest(self, kind):
        """The smallest pairwise distance of the logs (kind "3d" or "horizontal"), or None."""
        best = None
        for p in self.pairs:
            d = p[kind]
            if np.isfinite(d).any():
                k = int(np.nanargmin(d))
                if best is None or d[k] < best["distance_m"]:
                    best = {"pair": [p["a"], p["b"]], "t_s": float(p["t"][k]), "distance_m": float(d[k]),
                            "source": "the logs"}
        return best

    def _time_runs(self, drawn):
        """Pseudo-runs for finish(): each vehicle's failsafe, fallback and handover markers (not
        its phases) in its colour, named; no phase bands."""
        t_end = max(float(v["track"][1][-1]) for v in drawn)
        return [{"label": v["name"], "colour": v["colour"], "overlay": True, "bands": [], "t_end": t_end,
                 "markers": [m for m in v["run"]["markers"] if m[2] != "phase"]} for v in drawn]

    def fig_tracks(self, drawn, out, closest):
        plt = self.h["plt"]
        fig, ax = plt.subplots(figsize=(9, 10))
        ax.set_title(f"tracks - fleet {self.mission} ({len(drawn)} vehicles), world NED", loc="left", fontsize="medium")
        info = {}
        for v in drawn:
            source, t, p = v["track"]
            ax.plot(p[:, 1], p[:, 0], color=v["colour"], lw=1.2, label=f"{v['name']} ({source})", zorder=3)
            ok = np.nonzero(np.isfinite(p[:, 0]) & np.isfinite(p[:, 1]))[0]
            if len(ok):
                s, e = p[ok[0]], p[ok[-1]]
                ax.plot(s[1], s[0], "o", color=v["colour"], mec="black", ms=9, zorder=5)
                ax.plot(e[1], e[0], "s", color=v["colour"], mec="black", ms=7, zorder=5)
                ax.annotate(v["name"], (s[1], s[0]), xytext=(7, 7), textcoords="offset points", fontsize="small",
                            color=v["colour"])
                info[v["name"]] = {"source": source, "colour": v["colour"], "start_ne": [float(s[0]), float(s[1])],
                                   "end_ne": [float(e[0]), float(e[1])]}
        ax.plot([], [], "o", color="white", mec="black", ms=9, label="start")
        ax.plot([], [], "s", color="white", mec="black", ms=7, label="end")
        if closest is not None:
            pts = [self.position_at(v, closest["t_s"]) for v in drawn if v["name"] in closest["pair"]]
            pts = [q for q in pts if q is not None]
            if len(pts) == 2:
                ax.plot([pts[0][1], pts[1][1]], [pts[0][0], pts[1][0]], "k:", lw=1.2, zorder=6)
                ax.plot([q[1] for q in pts], [q[0] for q in pts], "*", color="gold", mec="black", ms=15, zorder=6,
                        label=closest_label(closest))
        self.h["top_view"](fig, ax)
        self.h["save"](fig, out, "tracks.png",
                       f"Every vehicle's track, north up, in the world NED about {self.origin_what} (a vehicle's truth "
                       "when logged, else its estimate moved from its own origin into the world frame), one colour per "
                       "vehicle; start (circle), end (square), the closest approach (stars, the pair's positions).",
                       legend=ax.get_legend_handles_labels()[1])
        out["figures"][-1].update({"vehicles": info, "world_origin": list(self.origin) if self.origin else None,
                                   "closest": closest})

    def position_at(self, v, t):
        _, tv, p = v["track"]
        if not len(tv) or t < tv[0] or t > tv[-1]:
            return None
        return [float(np.interp(t, tv, p[:, k])) for k in range(3)]

    def fig_altitude(self, drawn, out):
        fig, axes = self.h["new_figure"](1, "altitude", [{"label": f"fleet {self.mission}"}])
        for v in drawn:
            source, t, p = v["track"]
            self.h["plot_ts"](axes[0], t, -p[:, 2], color=v["colour"], lw=1.0, label=f"{v['name']} ({source})")
        axes[0].set_ylabel("h = -p_d [m], world")
        self.h["finish"](fig, axes, self._time_runs(drawn), out, "altitude.png",
                         "Every vehicle's altitude above the world origin (h = -p_d in the world NED; truth when "
                         "logged, else the estimate), one colour per vehicle; markers: each vehicle's handovers, "
                         "fallbacks and failsafes in its colour.")

    def fig_separation(self, drawn, out, sep):
        if not self.pairs:
            return "fewer than two vehicles with a track over a common time"
        fig, axes = self.h["new_figure"](2, "separation", [{"label": f"fleet {self.mission}"}], row_height=2.8)
        colour = {v["name"]: v["colour"] for v in drawn}
        closest = {}
        for p in self.pairs:  # a pair's line striped in its two vehicles' colours
            name = f"{p['a']}-{p['b']}"
            for ax, kind in zip(axes, ("horizontal", "3d")):
                d = p[kind]
                m = int(np.nanargmin(d)) if np.isfinite(d).any() else None
                what = f": min {d[m]:.1f} m at {p['t'][m]:.1f} s" if m is not None else ""
                self.h["plot_ts"](ax, p["t"], d, color=colour[p["a"]], gapcolor=colour[p["b"]], ls=(0, (5, 5)), lw=1.8,
                                  label=f"{name}{what}")
        for ax, kind in zip(axes, ("horizontal", "3d")):
            c = self.computed_closest(kind)
            closest[kind] = c
            if c is not None:
                ax.plot(c["t_s"], c["distance_m"], "v", color="black", ms=8, zorder=6,
                        label=f"closest ({c['source']}): {'-'.join(c['pair'])} {c['distance_m']:.1f} m at {c['t_s']:.1f} s")
        s = self.summary_closest(sep, drawn)
        if s is not None:
            axes[1].plot(s["t_s"], s["distance_m"], "*", color="gold", mec="black", ms=15, zorder=7,
                         label=closest_label(s))
        md = sep.get("min_distance_m")
        if _number(md):
            conflicts = sep.get("conflicts")
            extra = f", {conflicts} conflict(s)" if _number(conflicts) else ""
            for k, ax in enumerate(axes):
                ax.axhline(md, color="#d62728", lw=1.2, ls="--", zorder=4,
                           label=f"min_distance {md:g} m (summary.json{extra})" if k == 0 else None)
        axes[0].set_ylabel("horizontal [m]")
        axes[1].set_ylabel("3-D [m]")
        for ax in axes:
            ax.set_ylim(bottom=0.0)
        self.h["finish"](fig, axes, self._time_runs(drawn), out, "separation.png",
                         "Distance between each pair of vehicles over time, horizontal and 3-D (world NED, truth when "
                         "logged, else the estimate), each pair's line striped in its two vehicles' colours; the "
                         "closest approach of the logs "
                         "(triangle) and summary.json's (star, 3-D panel); summary.json's min_distance (dashed red).")
        out["figures"][-1].update({"pairs": [[p["a"], p["b"]] for p in self.pairs], "closest": closest,
                                   "summary_closest": s, "min_distance_m": md if _number(md) else None})
        return None


def closest_label(c):
    return f"closest approach ({c['source']}): {c['pair'][0]}-{c['pair'][1]} {c['distance_m']:.1f} m at {c['t_s']:.1f} s"


def pair_distances(drawn):
    """[{a, b, t, horizontal, 3d}] of every pair with a common time: on a's sample times within
    both tracks' spans, b's position interpolated linearly (NaN where either is not valid)."""
    out = []
    for i, va in enumerate(drawn):
        for vb in drawn[i + 1:]:
            _, ta, pa = va["track"]
            _, tb, pb = vb["track"]
            sel = (ta >= max(ta[0], tb[0])) & (ta <= min(ta[-1], tb[-1]))
            if sel.sum() < 2:
                continue
            t = ta[sel]
            d = pa[sel] - np.column_stack([np.interp(t, tb, pb[:, k]) for k in range(3)])
            out.append({"a": va["name"], "b": vb["name"], "t": t, "horizontal": np.hypot(d[:, 0], d[:, 1]),
                        "3d": np.sqrt(np.sum(d * d, axis=1))})
    return out


# ----------------------------------------------------------------------------------------------
# The fleet's index.html
# ----------------------------------------------------------------------------------------------

def _plain(v):
    return not isinstance(v, (dict, list)) or (isinstance(v, list) and all(not isinstance(x, (dict, list)) for x in v))


def _scalar_rows(d, skip=()):
    """[[key, value]] of a JSON object's plain fields (lists of plain values joined)."""
    return [[k, ", ".join(map(fmt_value, v)) if isinstance(v, list) else v]
            for k, v in d.items() if k not in skip and _plain(v)]


def _link(out_dir, path, text):
    return f'<a href="{html.escape(os.path.relpath(path, out_dir))}">{html.escape(text)}</a>'


def write_fleet_index(fleet, vehicles, out):
    """out["dir"]/index.html: the fleet's figures first, then fleet.json's and summary.json's
    tables, a section per vehicle (a link to its own page and its figures), the coordination log."""
    esc = html.escape
    fleet_dir = fleet["_dir"]
    summary = fleet.get("_summary", {})
    body = [f"<p>{esc(fleet_dir)}: {len(vehicles)} vehicles, "
            + ", ".join(f'<a href="#vehicle-{esc(v["name"])}" style="color:{v.get("colour", "#222")}">'
                        f'{esc(v["name"])}</a>' for v in vehicles) + "</p>",
            out.get("view3d", ""), "<h2>Figures</h2>", figure_html(out["figures"]), "<h2>Fleet</h2>",
            html_table("fleet.json", ["field", "value"], _scalar_rows({k: v for k, v in fleet.items()
                                                                       if not k.startswith("_")}), "fleet")]
    per = summary.get("vehicles") if isinstance(summary.get("vehicles"), dict) else {}
    keys = []
    for d in per.values():
        for k, v in (d.items() if isinstance(d, dict) else []):
            if not isinstance(v, (dict, list)) and k not in keys:
                keys.append(k)
    rows = []
    for v in vehicles:
        d = per.get(v["name"]) if isinstance(per.get(v["name"]), dict) else {}
        track = v.get("track")
        rows.append([v["name"], v.get("colour"), track[0] if track else "not drawn"] + [d.get(k) for k in keys])
    body.append(html_table("vehicles (summary.json's vehicles; colour and track drawn in the fleet's figures)",
                           ["vehicle", "colour", "track"] + keys, rows, "vehicles"))
    sep = summary.get("separation") if isinstance(summary.get("separation"), dict) else {}
    if sep:
        body.append(html_table("separation (summary.json)", ["field", "value"], _scalar_rows(sep), "separation"))
    rest = _scalar_rows(summary, skip=("vehicles", "separation"))
    if rest:
        body.append(html_table("summary.json", ["field", "value"], rest, "summary"))
    body.append("<h2>Vehicles</h2>")
    for v in vehicles:
        vout = v["out"]
        body.append(f'<h3 id="vehicle-{esc(v["name"])}" style="color:{v.get("colour", "#222")}">{esc(v["name"])}</h3>')
        page = _link(out["dir"], os.path.join(vout["dir"], "index.html"), v["name"] + ": every figure and its summary tables")
        body.append(f"<p>{page}"
                    f" (run directory {esc(v['run']['run_dir'])})</p>")
        rel = [esc(os.path.relpath(os.path.join(vout["dir"], f["file"]), out["dir"])) for f in vout["figures"]]
        body.append('<div class="thumbs">' + "".join(
            f'<a href="{src}"><img src="{src}" alt="{esc(v["name"])}: {esc(f["file"])}" title="{esc(f["file"])}"></a>'
            for src, f in zip(rel, vout["figures"])) + "</div>")
    coord = os.path.join(fleet_dir, "coordination")
    if os.path.isdir(coord):
        body.append('<h2 id="coordination">Coordination</h2><p>The coordination plugins\' log: '
                    + ", ".join(_link(out["dir"], os.path.join(coord, f), f) for f in ("summary.json", "tern.log")
                                if os.path.isfile(os.path.join(coord, f))) + "</p>")
        try:
            with open(os.path.join(coord, "summary.json"), encoding="utf-8") as f:
                cs = json.load(f)
            if isinstance(cs, dict):
                body.append(html_table("coordination/summary.json", ["field", "value"], _scalar_rows(cs), "coordination"))
        except (OSError, ValueError):
            pass
    figures = out["figures"] + [dict(f, file=os.path.join(v["name"], f["file"]), vehicle=v["name"])
                                for v in vehicles for f in v["out"]["figures"]]
    out["written"].append(write_page(out["dir"], f"fleet {fleet.get('mission', os.path.basename(fleet_dir))}",
                                     "\n".join(body), figures, style=THUMBS + VIEW3D_STYLE))


THUMBS = """
.thumbs { display: flex; flex-wrap: wrap; gap: 0.5em; align-items: flex-start; margin-bottom: 1.5em; }
.thumbs a { width: 32%; }
.thumbs img { width: 100%; }
"""
