"""tern plot: index.html, every figure and summary.json's tables; relative image paths, so the
page opens from disk without a server."""

import html
import json
import math
import os

from tern_plot_log import read_replay_report, rmse_window
from tern_plot_view3d import VIEW3D_STYLE, runs_view3d

# ----------------------------------------------------------------------------------------------
# index.html: every figure and summary.json's tables, relative image paths (no server needed)
# ----------------------------------------------------------------------------------------------

def fmt_value(v):
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if not math.isfinite(v):
            return "-"
        if v == int(v) and abs(v) < 1e12:  # counts and whole seconds
            return str(int(v))
        return f"{v:.3f}" if abs(v) < 1e5 else f"{v:.6g}"
    if v is None:
        return "-"
    return str(v)


def html_table(caption, header, rows, table_id):
    esc = html.escape
    head = "".join(f"<th>{esc(h)}</th>" for h in header)
    body = "".join("<tr>" + "".join(f"<td>{esc(fmt_value(c))}</td>" for c in row) + "</tr>\n" for row in rows)
    return (f'<table id="{esc(table_id)}"><caption>{esc(caption)}</caption>\n<thead><tr>{head}</tr></thead>\n'
            f"<tbody>\n{body}</tbody></table>\n")


RMSE_GROUPS = [("estimation_rmse", "estimation (estimate - truth)"), ("raw_gnss_rmse", "raw GNSS (fix - truth)"),
               ("tracking_rmse", "tracking (command - estimate)")]


def summary_tables(runs):
    """The summary.json tables: flight facts, RMSE by quantity (one column per group and run),
    phases, handovers, failsafes, waypoint passages, instances."""
    one = len(runs) == 1
    col = (lambda r, h: h) if one else (lambda r, h: f"{r['label']}: {h}")
    facts = ["mission", "seed", "duration_s", "end_reason", "sensor_profile", "preflight_s", "fallback_engaged"]
    metric_facts = ["window_start_s", "loops", "max_cross_track_m", "max_altitude_error_m"]
    rows = [[k] + [r["summary"].get(k) for r in runs] for k in facts]
    rows += [[f"metrics.{k}"] + [r["summary"].get("metrics", {}).get(k) for r in runs] for k in metric_facts]
    out = [html_table("flight (summary.json)", ["field"] + [r["label"] for r in runs], rows, "flight")]
    keys = []
    for r in runs:
        for g, _ in RMSE_GROUPS:
            for k in r["summary"].get("metrics", {}).get(g, {}) or {}:
                if k not in keys:
                    keys.append(k)
    header = ["quantity"] + [col(r, title) for r in runs for _, title in RMSE_GROUPS]
    rows = [[k] + [(r["summary"].get("metrics", {}).get(g) or {}).get(k) for r in runs for g, _ in RMSE_GROUPS]
            for k in keys]
    windows = "; ".join(f"{r['label']}: {rmse_window(r)[1]}" for r in runs)
    out.append(html_table(f"RMSE over the metrics window ({windows})", header, rows, "rmse"))
    for r in runs:
        s, pre = r["summary"], "" if one else f"{r['label']}: "
        sid = "" if one else f"-{runs.index(r)}"
        out.append(html_table(pre + "phases", ["phase", "start [s]", "reason"],
                              [[p.get("phase"), p.get("start_s"), p.get("reason")] for p in s.get("phases", [])], "phases" + sid))
        out.append(html_table(pre + "controller handovers", ["t [s]", "from", "to", "reason"],
                              [[h.get("t_s"), h.get("from"), h.get("to"), h.get("reason")]
                               for h in s.get("controller_handovers", [])], "handovers" + sid))
        out.append(html_table(pre + "failsafes", ["t [s]", "cause", "action", "detail"],
                              [[f.get("t_s"), f.get("cause"), f.get("action"), f.get("detail")]
                               for f in s.get("failsafes", [])], "failsafes" + sid))
        out.append(html_table(pre + "waypoint passages", ["t [s]", "waypoint"],
                              [[p.get("t_s"), p.get("waypoint")] for p in s.get("metrics", {}).get("waypoint_passages", [])],
                              "passages" + sid))
        inst_rows = [[name, d.get("plugin"), ", ".join(f"{k} {fmt_value(v)}" for k, v in d.items()
                                                       if k not in ("plugin", "library", "library_fnv1a"))]
                     for name, d in (s.get("instances") or {}).items() if isinstance(d, dict) and name != "metrics"]
        out.append(html_table(pre + "instances", ["instance", "plugin", "figures"], inst_rows, "instances" + sid))
    return out


# replay_report.json's objects come with their keys sorted: shown in this order (the rest after)
REPLAY_ORDER = ["gnss_pos", "gnss_vel", "baro", "diff_pressure", "mag", "sideslip", "normal_force", "roll", "pitch", "yaw",
                "course", "position_horizontal", "position_vertical", "velocity_horizontal", "velocity_vertical", "vs_reference"]


def _ordered(d):
    rank = {k: n for n, k in enumerate(REPLAY_ORDER)}
    return sorted(d.items(), key=lambda kv: rank.get(kv[0], len(rank)))


def _pct(x):
    return None if x is None else 100.0 * x


def _replay_tables(report, pre, sid):
    """replay_report.json's tables: facts, NIS per sensor, comparisons, the estimator's counters."""
    v, w = report.get("validity") or {}, report.get("window") or {}
    resets = ((report.get("estimator") or {}).get("resets")) or {}
    facts = [["window", f"{fmt_value(w.get('start_s'))} - {fmt_value(w.get('end_s'))} s: {w.get('rule')}"],
             ["valid [%] (from the first valid state)", _pct(v.get("share_valid"))],
             ["first valid [s]", v.get("first_valid_s")],
             ["divergences (valid -> invalid + filter resets)",
              f"{fmt_value(v.get('divergences'))} ({fmt_value(v.get('valid_to_invalid'))} + {fmt_value(v.get('filter_resets'))})"],
             ["NaN cells in state.csv", v.get("nan_cells")]] + [[k, n] for k, n in resets.items()]
    g, wind = report.get("gnss") or {}, report.get("wind") or {}
    if g.get("status") == "compared":
        facts.append(["GNSS fixes accepted: position, velocity [%] (estimator counters)",
                      f"{fmt_value(_pct(g.get('share_pos_accepted')))}, {fmt_value(_pct(g.get('share_vel_accepted')))}"])
    if wind.get("status") == "estimated":
        facts.append(["wind speed in the window: mean, max [m/s]", f"{fmt_value(wind.get('mean_speed'))}, {fmt_value(wind.get('max_speed'))}"])
    out = [html_table(pre + "replay report (replay_report.json)", ["figure", "value"], facts, "replay" + sid)]
    meas = report.get("measurements") or {}
    rows = []
    for name, m in _ordered(meas):
        if isinstance(m, dict) and "whole" in m:
            rows.append([name] + [x for part in ("whole", "window") for x in
                                  (m[part].get("count"), _pct(m[part].get("share_rejected")), m[part].get("mean_nis"),
                                   m[part].get("p50_nis"), m[part].get("p95_nis"), m[part].get("p99_nis"))] + [m.get("gate")])
    head = ["measurement"] + [f"{p} {c}" for p in ("whole", "window") for c in ("n", "rejected [%]", "mean NIS", "p50", "p95", "p99")]
    out.append(html_table(pre + "NIS per innovations message (" + str(meas.get("rule", meas.get("status", ""))) + ")",
                          head + ["gate"], rows, "replay-nis" + sid))
    rows = []
    for section in ("reference", "gnss", "wind"):
        sec = report.get(section) or {}
        if sec.get("status") not in ("compared", "estimated"):
            rows.append([section, sec.get("status"), None, None, None, None, None, None])
            continue
        for name, f in _ordered(sec):
            if isinstance(f, dict) and "rms" in f:
                rows.append([section, name, f.get("rms"), f.get("max"), f.get("mean"), f.get("unit"), f.get("samples"), f.get("rule")])
    out.append(html_table(pre + "estimate against the reference and the GNSS (window)",
                          ["against", "quantity", "RMS", "max", "mean (bias)", "unit", "samples", "rule"], rows,
                          "replay-compare" + sid))
    models = ((report.get("estimator") or {}).get("models")) or {}
    out.append(html_table(pre + "the estimator's counters (whole replay)", ["model", "accepted", "rejected", "mean NIS"],
                          [[k, m.get("accepted"), m.get("rejected"), m.get("mean_nis")] for k, m in models.items()],
                          "replay-counters" + sid))
    return out


def replay_report_tables(runs):
    """The tables of every run's replay_report.json ([] when none has one)."""
    out = []
    for k, r in enumerate(runs):
        report = read_replay_report(r["run_dir"])
        if report is not None:
            one = len(runs) == 1
            out += _replay_tables(report, "" if one else f"{r['label']}: ", "" if one else f"-{k}")
    return out


STYLE = """<style>
body { font-family: sans-serif; margin: 1.5em; color: #222; }
table { border-collapse: collapse; margin: 0 0 1.5em 0; font-size: 0.9em; }
caption { text-align: left; font-weight: bold; padding: 0.3em 0; }
th, td { border: 1px solid #ccc; padding: 0.2em 0.6em; text-align: left; vertical-align: top; }
img { max-width: 100%; border: 1px solid #ddd; }
figure { margin: 0 0 2em 0; }
figcaption { font-size: 0.9em; color: #444; }
</style>"""

# the first screen: the flight itself (ground track on the left, altitude and landing on the right)
FLIGHT_FIGURES = ("ground_track.png", "altitude.png", "landing.png")
FLIGHT_STYLE = """
h1 { font-size: 1.3em; margin: 0 0 0.3em 0; }
.runs { margin: 0 0 0.5em 0; font-size: 0.9em; color: #444; }
.flight { display: grid; grid-template-columns: minmax(0, 9fr) minmax(0, 11fr); gap: 0 1em; align-items: start; }
.flight figure { margin: 0 0 0.6em 0; }
.flight img { width: 100%; }
.flight .track { grid-row: span 2; }
.flight figcaption { font-size: 0.8em; }
.differences { border: 1px solid #bbb; background: #f6f6f6; padding: 0.2em 0.8em; margin: 0 0 0.8em 0; font-size: 0.9em; }
.differences ul { margin: 0.2em 0 0.4em 0; }
.warning { color: #a00; font-weight: bold; }
"""


def figure_html(figures, prefix=""):
    """<figure> elements of out["figures"] entries, images at prefix + file (relative)."""
    esc = html.escape
    return "".join(f'<figure id="{esc(prefix + f["file"])}"><img src="{esc(prefix + f["file"])}" alt="{esc(f["file"])}">'
                   f"<figcaption>{esc(f['file'])}: {esc(f['caption'])}</figcaption></figure>\n" for f in figures)


def flight_html(figures):
    """The first screen's figures (FLIGHT_FIGURES, those drawn) side by side: the ground track on
    the left, the altitude and the landing stacked on its right; each caption folded."""
    esc = html.escape
    parts = []
    for f in figures:
        cls = ' class="track"' if f["file"] == FLIGHT_FIGURES[0] else ""
        parts.append(f'<figure id="{esc(f["file"])}"{cls}><img src="{esc(f["file"])}" alt="{esc(f["file"])}">'
                     f"<figcaption><details><summary>{esc(f['file'])}</summary>{esc(f['caption'])}</details>"
                     "</figcaption></figure>\n")
    return f'<div class="flight">\n{"".join(parts)}</div>\n' if parts else ""


def split_flight(figures):
    """(the flight figures in FLIGHT_FIGURES' order, the others in drawing order)."""
    first = [f for name in FLIGHT_FIGURES for f in figures if f["file"] == name]
    return first, [f for f in figures if f not in first]


def write_page(out_dir, title, body, figures, style=""):
    """out_dir/index.html (title, body, STYLE and `style`'s further rules) and out_dir/figures.json
    (figures); returns the page's path."""
    esc = html.escape
    text = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>tern plot: {esc(title)}</title>
{STYLE}{"<style>" + style + "</style>" if style else ""}</head>
<body>
<h1>tern plot: {esc(title)}</h1>
{body}
</body></html>
"""
    path = os.path.join(out_dir, "index.html")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    with open(os.path.join(out_dir, "figures.json"), "w", encoding="utf-8") as f:
        json.dump(figures, f, indent=1)
    return path


def flight_line(run):
    """One line of what the flight was: mission, how long, how it ended, seed, sensor profile."""
    s = run["summary"]
    parts = [f"mission {s['mission']}" if s.get("mission") else None,
             f"{s['duration_s']:.1f} s" if isinstance(s.get("duration_s"), (int, float)) else None,
             f"ended: {s['end_reason']}" if s.get("end_reason") else None,
             f"seed {s['seed']}" if s.get("seed") is not None else None,
             f"sensor profile {s['sensor_profile']}" if s.get("sensor_profile") else None]
    return ", ".join(p for p in parts if p)


def write_index(runs, out, differences_html="", param_rows=()):
    """index.html: the runs, what differs between them (differences_html, several runs), the flight
    figures on the first screen, the other figures, then the tables (summary.json's, the
    parameters that differ, replay_report.json's)."""
    esc = html.escape
    runs_list = "".join(f"<li>{esc(r['label'])}: {esc(flight_line(r) + ' ' if flight_line(r) else '')}({esc(r['run_dir'])})</li>"
                        for r in runs)
    first, rest = split_flight(out["figures"])
    tables = summary_tables(runs)
    if param_rows:
        tables.append(html_table("parameters that differ (the values each flight started with)",
                                 ["runs", "parameter", "A", "B"], param_rows, "param-differences"))
    replay = replay_report_tables(runs)
    body = f"""<ul class="runs">{runs_list}</ul>
{differences_html}
{flight_html(first)}
{runs_view3d(runs, out["dir"])}
<h2>Figures</h2>
{figure_html(rest)}
<h2>Summary</h2>
{"".join(tables)}
{"<h2>Replay report</h2>" + "".join(replay) if replay else ""}"""
    out["written"].append(write_page(out["dir"], " vs ".join(r["label"] for r in runs), body, out["figures"], FLIGHT_STYLE + VIEW3D_STYLE))
