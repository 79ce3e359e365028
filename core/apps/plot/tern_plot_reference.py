"""tern plot: a truth-free replay's overlays (issue 43). When a run has topics/reference.csv
(another estimator's solution, docs/sensor-log.md) and no truth: tern's estimate against the
reference and the raw GNSS fixes (attitude and course, track, altitude, wind), and the innovation
test ratios per sensor over time. All in the estimate's frame: the reference's and the fixes'
lat/lon/alt in NED about state.csv's origin. The airborne window of replay_report.json, when
there is one, is shaded."""

import math
import os

import numpy as np

from tern_plot_angles import wrap_deg, wrapped_deg
from tern_plot_log import read_replay_report, read_topic, topics_dir
from tern_plot_mission import lla_to_ned

C_TERN, C_REF, C_GNSS = "#1f77b4", "#d62728", "#7f7f7f"
STATE = ["p_n", "p_e", "p_d", "v_n", "v_e", "phi", "theta", "psi", "w_n", "w_e", "valid",
         "origin_lat", "origin_lon", "origin_alt", "origin_valid"]
REFERENCE = ["phi", "theta", "psi", "lat", "lon", "alt", "v_n", "v_e", "w_n", "w_e"]
SENSORS = ["gnss_pos", "gnss_vel", "baro", "diff_pressure", "mag", "sideslip", "normal_force"]
MIN_COURSE_SPEED = 5.0  # m/s: course drawn from this horizontal speed (as replay_report.json compares it)


def applies(run):
    """A run with a reference and no truth."""
    topics = topics_dir(run["run_dir"])
    return os.path.isfile(os.path.join(topics, "reference.csv")) and not os.path.isfile(os.path.join(topics, "truth.csv"))


def _origin(state):
    """The state's last valid origin (lat, lon, alt), or None."""
    ok = np.nonzero(state.get("origin_valid") > 0.5)[0] if state.get("origin_valid") is not None else []
    if len(ok) == 0:
        return None
    k = ok[-1]
    return (state.get("origin_lat")[k], state.get("origin_lon")[k], state.get("origin_alt")[k])


def _ned(lat, lon, alt, origin):
    """(n, e, d) arrays of geodetic arrays about origin; NaN where a value is NaN."""
    out = np.full((len(lat), 3), np.nan)
    for k in range(len(lat)):
        if math.isfinite(lat[k]) and math.isfinite(lon[k]) and math.isfinite(alt[k]):
            out[k] = lla_to_ned((lat[k], lon[k], alt[k]), origin)
    return out[:, 0], out[:, 1], out[:, 2]


def load(run):
    """run["replay"]: the state (invalid samples NaN), reference and GNSS in the state's NED, the
    innovations and replay_report.json (read once per run)."""
    if "replay" in run:
        return run["replay"]
    d = run["run_dir"]
    state = read_topic(d, "state", STATE)
    ref = read_topic(d, "reference", [], extra=REFERENCE)
    gnss = read_topic(d, "gnss", ["lat", "lon", "alt", "vel_n", "vel_e"], optional=True)
    r = {"state": state, "ref": ref, "gnss": gnss, "innovations": read_topic(d, "innovations", [], optional=True, extra=SENSORS),
         "report": read_replay_report(d), "s": {}, "ref_ned": None, "gnss_ned": None}
    if state is not None:
        bad = state.get("valid") < 0.5
        for f in STATE:
            if state.get(f) is not None:
                r["s"][f] = np.where(bad, np.nan, state.get(f))
        origin = _origin(state)
        if origin is not None and ref is not None and all(ref.get(f) is not None for f in ("lat", "lon", "alt")):
            r["ref_ned"] = _ned(ref.get("lat"), ref.get("lon"), ref.get("alt"), origin)
        if origin is not None and gnss is not None:
            r["gnss_ned"] = _ned(gnss.get("lat"), gnss.get("lon"), gnss.get("alt"), origin)
    run["replay"] = r
    return r


def course(vn, ve):
    """atan2(v_e, v_n), NaN below MIN_COURSE_SPEED."""
    return np.where(np.hypot(vn, ve) >= MIN_COURSE_SPEED, np.arctan2(ve, vn), np.nan)


def shade_window(axes, report):
    w = (report or {}).get("window") or {}
    if "start_s" in w and "end_s" in w:
        for k, ax in enumerate(axes):
            ax.axvspan(w["start_s"], w["end_s"], color="#2ca02c", alpha=0.06, lw=0, zorder=0,
                       label="report window" if k == 0 else None)


class Overlays:
    """The figures, drawn with tern plot's helpers (new_figure, finish, save, plot_ts)."""

    def __init__(self, helpers):
        self.h = helpers

    def figures(self):
        return [("replay_attitude.png", self.attitude), ("replay_track.png", self.track),
                ("replay_altitude.png", self.altitude), ("replay_wind.png", self.wind), ("replay_nis.png", self.nis)]

    def _one(self, runs):
        """(the replay's data, None), or (None, why not drawn): "" (no note) for a run these
        figures are not for (a simulated flight, an overlay of several runs)."""
        if len(runs) != 1 or not applies(runs[0]):
            return None, ""
        r = load(runs[0])
        if r["state"] is None or r["ref"] is None:
            return None, "no state or reference rows"
        return r, None

    def _angle(self, ax, t, a, **kw):
        d, at = wrapped_deg(a)
        ax.plot(np.insert(np.asarray(t, dtype=float), at, np.nan), d, **kw)

    def attitude(self, runs, out):
        r, why = self._one(runs)
        if r is None:
            return why or None
        fig, axes = self.h["new_figure"](4, "attitude and course: tern, reference, GNSS", runs, row_height=2.0)
        s, ref, t, tr = r["s"], r["ref"], r["state"].get("t"), r["ref"].get("t")
        for ax, f, label in zip(axes, ("phi", "theta", "psi"), ("roll phi [deg]", "pitch theta [deg]", "yaw psi [deg]")):
            self._angle(ax, t, s[f], color=C_TERN, lw=0.9, label="tern")
            if ref.get(f) is not None:
                self._angle(ax, tr, ref.get(f), color=C_REF, lw=0.9, label="reference")
            ax.set_ylabel(label)
        self._angle(axes[3], t, course(s["v_n"], s["v_e"]), color=C_TERN, lw=0.9, label="tern")
        if ref.get("v_n") is not None and ref.get("v_e") is not None:
            self._angle(axes[3], tr, course(ref.get("v_n"), ref.get("v_e")), color=C_REF, lw=0.9, label="reference")
        g = r["gnss"]
        if g is not None:
            c = course(g.get("vel_n"), g.get("vel_e"))
            axes[3].plot(g.get("t"), wrap_deg(c), ".", color=C_GNSS, ms=2,
                         label="GNSS (fix time t)")
        axes[3].set_ylabel(f"course [deg] (Vg >= {MIN_COURSE_SPEED:g} m/s)")
        shade_window(axes, r["report"])
        self.h["finish"](fig, axes, runs, out, "replay_attitude.png",
                         "Roll, pitch, yaw and course (deg, wrapped): tern's estimate (where valid), the reference "
                         "estimator, the GNSS course; the report's window shaded.")
        return None

    def track(self, runs, out):
        r, why = self._one(runs)
        if r is None:
            return why or None
        plt = self.h["plt"]
        fig, ax = plt.subplots(figsize=(9, 10))
        ax.set_title(f"track, north up: tern, reference, GNSS - {runs[0]['label']}", loc="left", fontsize="medium")
        ax.plot(r["s"]["p_e"], r["s"]["p_n"], color=C_TERN, lw=0.9, label="tern", zorder=3)
        if r["ref_ned"] is not None:
            ax.plot(r["ref_ned"][1], r["ref_ned"][0], color=C_REF, lw=0.9, label="reference", zorder=2)
        if r["gnss_ned"] is not None:
            ax.plot(r["gnss_ned"][1], r["gnss_ned"][0], ".", color=C_GNSS, ms=2, label="GNSS fixes", zorder=1)
        self.h["top_view"](fig, ax)
        self.h["save"](fig, out, "replay_track.png", "Track, north up (m, the estimate's NED about its origin): tern's "
                       "estimate, the reference's and the GNSS fixes' lat/lon converted into it.",
                       legend=ax.get_legend_handles_labels()[1])
        return None

    def altitude(self, runs, out):
        r, why = self._one(runs)
        if r is None:
            return why or None
        fig, axes = self.h["new_figure"](1, "altitude: tern, reference, GNSS", runs)
        ax = axes[0]
        self.h["plot_ts"](ax, r["state"].get("t"), -r["s"]["p_d"], color=C_TERN, lw=0.9, label="tern")
        if r["ref_ned"] is not None:
            self.h["plot_ts"](ax, r["ref"].get("t"), -r["ref_ned"][2], color=C_REF, lw=0.9, label="reference")
        if r["gnss_ned"] is not None:
            ax.plot(r["gnss"].get("t"), -r["gnss_ned"][2], ".", color=C_GNSS, ms=2, label="GNSS fixes (fix time t)")
        ax.set_ylabel("h = -p_d [m] above the origin")
        shade_window(axes, r["report"])
        self.h["finish"](fig, axes, runs, out, "replay_altitude.png",
                         "Altitude above the estimate's origin: tern, the reference's and the fixes' altitude in its frame.")
        return None

    def wind(self, runs, out):
        r, why = self._one(runs)
        if r is None:
            return why or None
        if r["s"].get("w_n") is None:
            return "state.csv has no wind"
        fig, axes = self.h["new_figure"](3, "wind: tern, reference", runs, row_height=2.0)
        s, ref = r["s"], r["ref"]
        t, tr = r["state"].get("t"), ref.get("t")
        series = [("w_n [m/s]", s["w_n"], ref.get("w_n")), ("w_e [m/s]", s["w_e"], ref.get("w_e")),
                  ("|w| [m/s]", np.hypot(s["w_n"], s["w_e"]),
                   np.hypot(ref.get("w_n"), ref.get("w_e")) if ref.get("w_n") is not None and ref.get("w_e") is not None else None)]
        for ax, (label, mine, theirs) in zip(axes, series):
            self.h["plot_ts"](ax, t, mine, color=C_TERN, lw=0.9, label="tern")
            if theirs is not None and np.isfinite(theirs).any():
                self.h["plot_ts"](ax, tr, theirs, color=C_REF, lw=0.9, label="reference")
            ax.set_ylabel(label)
        shade_window(axes, r["report"])
        self.h["finish"](fig, axes, runs, out, "replay_wind.png",
                         "Wind (the air's velocity over the ground, NED): tern's estimate and the reference's, if it has one.")
        return None

    def nis(self, runs, out):
        r, why = self._one(runs)
        if r is None:
            return why or None
        inn = r["innovations"]
        if inn is None:
            return "no topics/innovations.csv"
        used = [f for f in SENSORS if inn.get(f) is not None and (inn.get(f) >= 0).any()]
        if not used:
            return "no sensor fused"
        fig, axes = self.h["new_figure"](len(used), "innovation test ratios NIS / gate (log scale; > 1 rejected)", runs,
                                         row_height=1.5)
        for ax, f in zip(axes, used):
            v = inn.get(f)
            ok = v >= 0
            rej = float(np.mean(v[ok] > 1.0))
            ax.semilogy(inn.get("t")[ok], np.maximum(v[ok], 1e-4), ".", ms=1.5, color=C_TERN,
                        label=f"{f}: {ok.sum()} messages, {100 * rej:.1f} % rejected")
            ax.axhline(1.0, color=C_REF, lw=0.9, ls="--")
            ax.set_ylabel(f)
        shade_window(axes, r["report"])
        self.h["finish"](fig, axes, runs, out, "replay_nis.png",
                         "Innovation test ratios (NIS / gate) per sensor, each innovations message's largest since the "
                         "previous (log scale, 1e-4 floor); above the dashed line at 1: rejected.")
        return None
