"""tern plot: what a run directory holds (core/host/record/flight_log.hpp): the topic tables, summary.json,
params.csv, config.yaml, and what the figures take from them: the estimator instances, the
markers, the actuator limits, the waypoint lists as flown, summary.json's RMSE window."""

import csv
import json
import math
import os
import re
import warnings

import numpy as np

from tern_plot_yaml import YamlError, yaml_load

PROG = "tern plot"

# ----------------------------------------------------------------------------------------------
# Notes
# ----------------------------------------------------------------------------------------------

NOTES = []
NOTE_SCOPE = [""]  # what the notes are about when several run directories are drawn (a fleet's "uav1: ")


def note(msg):
    NOTES.append(NOTE_SCOPE[0] + msg)
    print(f"{PROG}: note: {NOTE_SCOPE[0]}{msg}")


# ----------------------------------------------------------------------------------------------
# Topic CSVs
# ----------------------------------------------------------------------------------------------

class Topic:
    """Columns of one topic CSV by field name (unit stripped); "t" is the flight time."""

    def __init__(self, name, cols):
        self.name = name
        self.cols = cols

    def get(self, field):
        return self.cols.get(field)

    def __len__(self):
        return len(self.cols["t"])


_HEADER_RE = re.compile(r"^\s*(.*?)\s*(\[[^\]]*\])?\s*$")


# Runs logged as MCAP only have their tables exported outside the run (tern_plot_load.py's
# tables_from_mcap): real path of the run directory -> the directory of its tables.
EXPORTED_TOPICS = {}


def topics_dir(run_dir):
    """The directory of a run's topic tables: RUN/topics, or where they were exported from its
    flight.mcap."""
    return EXPORTED_TOPICS.get(os.path.realpath(run_dir), os.path.join(run_dir, "topics"))


def read_topic(run_dir, name, fields, optional=False, extra=()):
    """Reads topics/<name>.csv, only `fields` (plus t) and those of `extra` it has (no note
    when they are not). None (with a note) when missing/empty; an optional topic that is
    missing is None without a note."""
    path = os.path.join(topics_dir(run_dir), name + ".csv")
    if not os.path.isfile(path):
        if not optional:
            note(f"topics/{name}.csv missing: skipped")
        return None
    with open(path, encoding="utf-8", errors="replace") as f:
        header = f.readline().rstrip("\r\n").split(",")
    names = [_HEADER_RE.match(h).group(1) for h in header]
    index = {n: k for k, n in enumerate(names)}
    if "t" not in index:
        note(f"topics/{name}.csv has no 't [s]' column: skipped")
        return None
    lacking = [f for f in fields if f not in index]
    if lacking:
        note(f"topics/{name}.csv has no column {', '.join(lacking)}: not drawn")
    want = ["t"] + [f for f in list(fields) + list(extra) if f in index and f != "t"]
    use = [index[f] for f in want]
    rows = _complete_rows(path, name)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            data = np.loadtxt(rows, delimiter=",", usecols=use, ndmin=2, dtype=float)
    except (ValueError, IndexError):
        data = _read_lenient(rows, len(header), use)
        note(f"topics/{name}.csv has malformed rows: {len(data)} good rows kept")
    if data.shape[0] == 0:
        note(f"topics/{name}.csv has no rows: skipped")
        return None
    return Topic(name, {f: data[:, k] for k, f in enumerate(want)})


def _complete_rows(path, name):
    """The data rows of a topic CSV. A last line without a line end (a flight killed while
    writing it) is dropped, with one note: its last value may be cut short."""
    with open(path, encoding="utf-8", errors="replace", newline="") as f:
        lines = f.read().split("\n")[1:]
    if lines and lines[-1] != "":
        note(f"topics/{name}.csv: the last line is partial (no line end: the flight was cut off while writing it): dropped")
    return lines[:-1]


def _read_lenient(rows, ncols, use):
    good = []
    for line in rows:
        parts = line.rstrip("\r").split(",")
        if len(parts) != ncols:
            continue
        try:
            good.append([float(parts[k]) for k in use])
        except ValueError:
            continue
    return np.array(good, dtype=float).reshape(-1, len(use))


# ----------------------------------------------------------------------------------------------
# ----------------------------------------------------------------------------------------------
# What a run directory says besides its topics: summary.json, params.csv, config.yaml
# ----------------------------------------------------------------------------------------------

def read_summary(run_dir):
    """summary.json as a dict ({} when missing or unreadable, with a note)."""
    path = os.path.join(run_dir, "summary.json")
    try:
        with open(path, encoding="utf-8") as f:
            s = json.load(f)
        return s if isinstance(s, dict) else {}
    except OSError:
        note("summary.json missing: no markers, limits by controller or RMSE window")
    except ValueError as e:
        note(f"summary.json not readable ({e}): no markers, limits by controller or RMSE window")
    return {}


def read_definitions(run_dir):
    """definitions.json (core/host/record/log_definitions.hpp: what the log's codes and defaults
    mean) as {"phase": {code: name}, "item_type": {code: name}, "land_item": {name: value}}; a
    part missing or unreadable is {} with a note (a log from before tern wrote the file)."""
    path = os.path.join(run_dir, "definitions.json")
    try:
        with open(path, encoding="utf-8") as f:
            d = json.load(f)
    except OSError:
        d = None
        note("definitions.json missing: phases shown by code, no cruise-only RMSE window, no land-item defaults")
    except ValueError as e:
        d = None
        note(f"definitions.json not readable ({e}): phases shown by code, no cruise-only RMSE window, no land-item defaults")
    d = d if isinstance(d, dict) else {}

    def codes(key):
        try:
            return {int(k): str(v) for k, v in d.get(key, {}).items()}
        except (AttributeError, TypeError, ValueError):
            note(f"definitions.json: {key} is not a table of codes -> names")
            return {}
    land = d.get("land_item")
    return {"phase": codes("phase"), "item_type": codes("item_type"), "land_item": land if isinstance(land, dict) else {}}


def codes_named(names, name):
    """The codes a definitions.json table gives `name` (a list, empty when it has none)."""
    return [c for c, n in names.items() if n == name]


def read_replay_report(run_dir):
    """replay_report.json (`tern replay`'s truth-free report, core/apps/replay/replay_report.hpp) as
    a dict, or None when missing (a note when unreadable)."""
    path = os.path.join(run_dir, "replay_report.json")
    if not os.path.isfile(path):
        return None
    try:
        with open(path, encoding="utf-8") as f:
            r = json.load(f)
        return r if isinstance(r, dict) else None
    except (OSError, ValueError) as e:
        note(f"replay_report.json not readable ({e}): its tables are not shown")
        return None


def read_params(run_dir):
    """params.csv as {qualified name: [(t, text value), ...]} in time order ({} when missing)."""
    path = os.path.join(run_dir, "params.csv")
    out = {}
    if not os.path.isfile(path):
        return out
    with open(path, encoding="utf-8", errors="replace", newline="") as f:
        rows = csv.reader(f)
        next(rows, None)
        for row in rows:
            if len(row) >= 3:
                try:
                    out.setdefault(row[1], []).append((float(row[0]), row[2]))
                except ValueError:
                    continue
    return out


def param_at(params, name, t):
    """Numeric value of parameter `name` at times t (array), NaN where unset or not a number."""
    out = np.full(len(t), np.nan)
    for t0, text in params.get(name, []):
        try:
            v = float(text)
        except ValueError:
            v = math.nan
        out[t >= t0] = v
    return out


def topic_columns(run_dir, name):
    path = os.path.join(topics_dir(run_dir), name + ".csv")
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            return [_HEADER_RE.match(h).group(1) for h in f.readline().rstrip("\r\n").split(",")]
    except OSError:
        return []


def read_config(run_dir):
    """(config.yaml as a dict or {}, the config file it was resolved from or None)."""
    path = os.path.join(run_dir, "config.yaml")
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
    except OSError:
        return {}, None
    m = re.match(r"#\s*resolved from\s+(.+?)\s*$", text.splitlines()[0] if text else "")
    try:
        cfg = yaml_load(text)
    except YamlError:
        cfg = None
    return (cfg if isinstance(cfg, dict) else {}), (m.group(1) if m else None)


# ----------------------------------------------------------------------------------------------
# Estimator instances: every topic with the State layout but the truth
# ----------------------------------------------------------------------------------------------

STATE_FIELDS = ["p_n", "p_e", "p_d", "phi", "theta", "psi", "Va", "chi", "valid",
                "origin_lat", "origin_lon", "origin_alt", "origin_valid"]
P_FIELDS = [f"P_diag_{k}" for k in range(9)]  # position and attitude blocks (estimator_ekf's layout)
OPTIONAL_STATE = P_FIELDS + ["Vg"]  # read when logged, without a note when not


def is_state_topic(columns):
    return all(c in columns for c in ("p_n", "phi", "Va", "valid", "P_diag_0"))


def instance_of_topic(cfg, topic):
    """The config instance publishing `topic` as its `state` output (remap), else the topic."""
    plugins = [p for p in cfg.get("plugins") or [] if isinstance(p, dict)]
    for p in plugins:
        remap = p.get("remap") if isinstance(p.get("remap"), dict) else {}
        if remap.get("state") == topic:
            return str(p.get("name"))
    if topic == "state":
        plain = [p for p in plugins if str(p.get("plugin", "")).startswith("estimator")
                 and not (isinstance(p.get("remap"), dict) and "state" in p["remap"])]
        if len(plain) == 1:
            return str(plain[0].get("name"))
    return topic


def replay_source(run_dir, cfg_source):
    """The flight a replay was run over, when its config is that flight's config.yaml."""
    if not cfg_source or os.path.basename(cfg_source) != "config.yaml":
        return None
    src = os.path.dirname(cfg_source)
    if os.path.realpath(src) == os.path.realpath(run_dir) or not os.path.isfile(os.path.join(topics_dir(src), "state.csv")):
        return None
    return src


def load_estimators(run_dir, cfg, cfg_source):
    """[{name, label, topic}] of every state topic (main `state` first), plus, for a replay of a
    flight, the estimate recorded in that flight."""
    names = sorted(f[:-4] for f in os.listdir(topics_dir(run_dir)) if f.endswith(".csv") and f[:-4] != "truth")
    names.sort(key=lambda n: n != "state")
    out = []
    for name in names:
        cols = topic_columns(run_dir, name)
        if name != "state" and not is_state_topic(cols):
            continue
        topic = read_topic(run_dir, name, STATE_FIELDS, optional=name != "state", extra=OPTIONAL_STATE)
        if topic is not None:
            out.append({"name": instance_of_topic(cfg, name), "topic": topic})
    src = replay_source(run_dir, cfg_source)
    if src is not None:
        topic = read_topic(src, "state", STATE_FIELDS, optional=True, extra=OPTIONAL_STATE)
        if topic is not None:
            src_cfg, _ = read_config(src)
            out.append({"name": instance_of_topic(src_cfg, "state") + " (recorded in flight "
                        + os.path.basename(src.rstrip("/")) + ")", "topic": topic})
        if len(out) > 1:
            for e in out[:-1]:
                e["name"] += " (replayed)"
    return out


# ----------------------------------------------------------------------------------------------
# Markers: phases, controller handovers, fallback and state-loss recovery, failsafes
# ----------------------------------------------------------------------------------------------

MARKER_STYLE = {"phase": ("#555555", ":"), "handover": ("#9467bd", "-."), "fallback": ("#ff7f0e", "--"),
                "failsafe": ("#d62728", "--"), "cleared": ("#2ca02c", "--")}


def flight_markers(summary):
    """[(t, label, kind)] of summary.json, time order; kind: phase, handover, fallback (the
    fallback or the state-loss recovery took over), failsafe (engaged), cleared (a failsafe's
    cause went away). Handovers at a phase change are part of that phase's marker."""
    out = []
    for p in summary.get("phases", []):
        if p.get("phase") != "preflight":
            out.append((float(p["start_s"]), p.get("phase", "?"), "phase"))
    for h in summary.get("controller_handovers", []):
        reason = h.get("reason", "")
        frm, to = h.get("from", ""), h.get("to", "")
        if reason.startswith("fallback") or to == "state_loss_recovery" or "safety monitor" in reason:
            out.append((float(h["t_s"]), f"fallback: {frm} -> {to}", "fallback"))
        elif not reason.startswith("preflight"):
            out.append((float(h["t_s"]), f"{frm} -> {to}", "handover"))
    for e in summary.get("failsafes", []):
        out.append((float(e["t_s"]), "failsafe " + e.get("cause", "?"), "cleared" if e.get("action") == "none" else "failsafe"))
    out.sort(key=lambda m: m[0])
    return merge_markers(out)


def merge_markers(markers, dt=0.05):
    """Markers within dt s of each other become one (labels joined; the severest kind's style)."""
    rank = {"failsafe": 0, "fallback": 1, "cleared": 2, "handover": 3, "phase": 4}
    out = []
    for t, label, kind in markers:
        if out and t - out[-1][0] <= dt:
            t0, l0, k0 = out[-1]
            out[-1] = (t0, f"{l0}; {label}", k0 if rank[k0] <= rank[kind] else kind)
        else:
            out.append((t, label, kind))
    return out


# ----------------------------------------------------------------------------------------------
# Actuator limits: the active controller's (params.csv), the host's max_deflection
# ----------------------------------------------------------------------------------------------

# surface -> (lower limit, upper limit) as functions of the controller's parameters (control_slc,
# control_tecs: control_common/autopilot.cpp saturates the surfaces to +-max, the throttle to
# min_t..max_t); a controller without them is bounded by the host's limits only
SURFACES = [("delta_a", "aileron", ("-max_a", "max_a")), ("delta_e", "elevator", ("-max_e", "max_e")),
            ("delta_r", "rudder", ("-max_r", "max_r")), ("delta_t", "throttle", ("min_t", "max_t"))]


def active_controller(summary, t):
    """Name of the controller writing `actuators` at times t (summary.json's handovers)."""
    hand = sorted((float(h["t_s"]), h.get("to", "")) for h in summary.get("controller_handovers", []))
    names = np.array(["(none)"] + [to for _, to in hand], dtype=object)
    idx = np.searchsorted(np.array([t0 for t0, _ in hand]), t, side="right")
    return names[idx] if len(t) else np.array([], dtype=object)


def host_limits(params, t):
    """The host's hard limits at times t: +-phase_machine.max_deflection (a command beyond it
    hands over to the fallback), throttle 0..1."""
    dmax = param_at(params, "phase_machine.max_deflection", t)
    return {"delta_a": (-dmax, dmax), "delta_e": (-dmax, dmax), "delta_r": (-dmax, dmax),
            "delta_t": (np.zeros(len(t)), np.ones(len(t)))}


def actuator_limits(summary, params, t):
    """{surface: (lower, upper, [source names])} at times t: the active controller's limits from
    params.csv (NaN where the controller has none: no controller, or one without max_a ...)."""
    active = active_controller(summary, t)
    out = {}
    for field, _, (lo_name, hi_name) in SURFACES:
        lo, hi = np.full(len(t), np.nan), np.full(len(t), np.nan)
        sources = []
        for ctl in sorted(set(active)):
            sel = active == ctl
            vals = []
            for name in (lo_name, hi_name):
                sign = -1.0 if name.startswith("-") else 1.0
                vals.append(sign * param_at(params, f"{ctl}.{name.lstrip('-')}", t[sel]))
            if np.isfinite(vals[1]).any():
                lo[sel], hi[sel] = vals
                sources.append(f"{ctl}.{hi_name}")
        out[field] = (lo, hi, sources)
    return out


def saturation_spans(t, v, lo, hi, rel=1e-4):
    """[(t0, t1)] where v sits at (or beyond) a finite limit (within rel of its size)."""
    tol = rel * np.maximum(np.abs(np.nan_to_num(hi)), np.abs(np.nan_to_num(lo))) + 1e-9
    with np.errstate(invalid="ignore"):
        at = (np.isfinite(hi) & (v >= hi - tol)) | (np.isfinite(lo) & (v <= lo + tol))
    if not at.any():
        return []
    edges = np.diff(np.concatenate([[0], at.astype(np.int8), [0]]))
    starts, ends = np.nonzero(edges == 1)[0], np.nonzero(edges == -1)[0]
    # A span ends where the next sample starts (the last one: a median step after it), so that
    # t0 <= t < t1 holds exactly the samples at the limit (t[e - 1] + dt can round past t[e]).
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 0.0
    return [(float(t[s]), float(t[e]) if e < len(t) else float(t[e - 1]) + dt) for s, e in zip(starts, ends)]


# ----------------------------------------------------------------------------------------------
# Waypoints as flown: the waypoint lists the planner published (topics/waypoints_items.csv)
# ----------------------------------------------------------------------------------------------

def flown_waypoints(run_dir):
    """The waypoint lists of the flight, [(t, revision, N x 3 NED, types, radii)] in time order:
    each list topics/waypoints.csv logged, its items from topics/waypoints_items.csv (the flight
    recorder's rows per item; a cleared list has none); None if the items were not logged."""
    items = read_topic(run_dir, "waypoints_items", ["revision", "index", "w_0", "w_1", "w_2", "type", "loiter_radius"],
                       optional=True)
    lists_topic = read_topic(run_dir, "waypoints", ["revision"], optional=True)
    if items is None and lists_topic is None:
        return None
    if items is None:
        items = Topic("waypoints_items", {k: np.zeros(0) for k in ("t", "revision", "index", "w_0", "w_1", "w_2",
                                                                   "type", "loiter_radius")})
    t = items.get("t")
    times = lists_topic.get("t") if lists_topic is not None else np.unique(t)
    revisions = lists_topic.get("revision") if lists_topic is not None else None
    lists = []
    for k, t0 in enumerate(times):
        sel = t == t0
        order = np.argsort(items.get("index")[sel])
        pos = np.column_stack([items.get(c)[sel][order] for c in ("w_0", "w_1", "w_2")]).reshape(-1, 3)
        rev = int(revisions[k]) if revisions is not None else int(items.get("revision")[sel][0])
        lists.append((float(t0), rev, pos, items.get("type")[sel][order].astype(int), items.get("loiter_radius")[sel][order]))
    return lists


def added_waypoints(lists, tol=1.0):
    """[(k, t)] of the last list's items that the first list did not have (within tol m), each
    with the time it first appeared."""
    if not lists or len(lists) < 2:
        return []
    first, last = lists[0][2], lists[-1][2]
    out = []
    for k, w in enumerate(last):
        if len(first) and np.min(np.linalg.norm(first - w, axis=1)) <= tol:
            continue
        t_new = next(t for t, _, pos, _, _ in lists if len(pos) and np.min(np.linalg.norm(pos - w, axis=1)) <= tol)
        out.append((k, t_new))
    return out


# ----------------------------------------------------------------------------------------------
# The RMSE window of summary.json (core/host/record/metrics.hpp: from window_start_s, cruise only)
# ----------------------------------------------------------------------------------------------

def rmse_window(run):
    """(mask function of times, label) of the window summary.json's RMSE figures use."""
    metrics = run["summary"].get("metrics", {})
    w0 = metrics.get("window_start_s")
    t_end = run["t_end"]
    if not isinstance(w0, (int, float)):
        return (lambda t: np.ones(len(t), bool)), "whole flight: summary.json has no RMSE window"
    cruise_only = not (run["params"].get("metrics.cruise_only") and run["params"]["metrics.cruise_only"][-1][1] == "false")
    phase = run["phase"]
    cruise = codes_named(run.get("definitions", {}).get("phase", {}), "cruise")
    if cruise_only and phase is not None and phase.get("phase") is not None and cruise:
        pt, pv = phase.get("t"), phase.get("phase")

        def mask(t):
            idx = np.searchsorted(pt, t, side="right") - 1
            in_cruise = (idx >= 0) & np.isin(pv[np.clip(idx, 0, len(pv) - 1)], cruise)
            return (t >= w0) & in_cruise
        return mask, f"cruise {w0:.4g}-{t_end:.4g} s, as summary.json"
    return (lambda t: t >= w0), f"{w0:.4g}-{t_end:.4g} s, as summary.json"
