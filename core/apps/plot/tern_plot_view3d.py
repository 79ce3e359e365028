"""tern plot: the 3-D replay on index.html (issue 65). What the page's scene needs, taken from the
loaded runs (tern_plot_load.load_run: CSV and MCAP runs alike) and downsampled to RATE_HZ, is
written as view3d_data.js (`window.TERN_VIEW3D = {...}`) beside index.html. The scene, view3d.js
(core/apps/console/view3d*.js bundled with three.js at build time, ~0.6 MB), is not copied into
every run (issue 80): one copy, tern-view3d-<its sha256's first 12 hex digits>.js, sits in the
directory that holds the run directories (runs/), written by the first run that needs it; the page
loads it from there, else (a run moved away from its siblings) from tern plot's install, else it
says how to get it back. All of it from disk, without a server. Plots written anywhere but a run's
plots/ directory get their own copy. A topic the run lacks (a killed flight, a
hardware log without truth) leaves its part out and one line on the page names what is missing.

Per vehicle: the truth's and the estimate's positions (NED, m) and 3-2-1 Euler angles (rad), the
wind (truth's w_n, w_e, else the estimate's), the commanded attitude (controller_internals:
phi_c, theta_c) for the ghost, the commanded path (current_path: line r, q or orbit c, rho,
lambda) at each change; and the aircraft's size from its aircraft file (wing b, c; the gear's
structure nose and tail points). For the run: the mission's waypoints, home and the land item's
runway. Positions in the main estimator's NED (the figures' frame); a fleet's in the world NED
(tern_plot_fleet.py's frame)."""

import hashlib
import html
import json
import math
import os
import pathlib
import shutil

import numpy as np

from tern_plot_landing import home_altitude, land_item, phase_spans
from tern_plot_log import read_topic
from tern_plot_yaml import YamlError, yaml_load

RATE_HZ = 10.0     # samples per second kept for the page (the scene interpolates between them)
WIND_GAIN = 1.0    # the wind arrow's length: the model's drawn spans per m/s of wind
BUNDLE = "view3d.js"
DATA = "view3d_data.js"
PATH_FIELDS = ["path_type", "r_n", "r_e", "r_d", "q_n", "q_e", "q_d", "c_n", "c_e", "c_d", "rho", "lambda"]


def bundle_path():
    """view3d.js in tern plot's share directory (<build or prefix>/share/tern/plot), or None."""
    here = os.path.dirname(os.path.abspath(__file__))
    for d in (here, os.path.join(os.path.dirname(here), "share", "tern", "plot")):
        if os.path.isfile(os.path.join(d, BUNDLE)):
            return os.path.join(d, BUNDLE)
    return None


# ----------------------------------------------------------------------------------------------
# The aircraft's size
# ----------------------------------------------------------------------------------------------

def _find(doc, key):
    """The first value of `key` anywhere in a nested YAML document (ROSflight files nest theirs)."""
    if isinstance(doc, dict):
        if key in doc:
            return doc[key]
        for v in doc.values():
            found = _find(v, key)
            if found is not None:
                return found
    return None


def aircraft_dims(run):
    """({b, c, nose, tail} in m, None) from the run's aircraft file, or (None, why not). nose and
    tail: the gear structure's "nose" and "tail" points (x ahead of / behind the CG); without
    them sdk/src/aircraft.cpp's default_structure, 0.3 b and 0.5 b."""
    rel = run.get("config", {}).get("aircraft")
    if not isinstance(rel, str) or not rel:
        return None, "config.yaml names no aircraft file"
    cfg_path = os.path.join(run["run_dir"], "config.yaml")
    with open(cfg_path, encoding="utf-8", errors="replace") as f:
        first = f.readline()
    src = first.split("resolved from", 1)[1].strip() if "resolved from" in first else cfg_path
    path = rel if os.path.isabs(rel) else os.path.join(os.path.dirname(src), rel)
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            doc = yaml_load(f.read())
    except (OSError, YamlError) as e:
        return None, f"aircraft file {path} not readable ({getattr(e, 'strerror', None) or e})"
    wing = doc.get("wing") if isinstance(doc, dict) and isinstance(doc.get("wing"), dict) else {}
    b, c = wing.get("b", _find(doc, "wing_b")), wing.get("c", _find(doc, "wing_c"))
    if not all(isinstance(x, (int, float)) and math.isfinite(x) and x > 0 for x in (b, c)):
        return None, f"aircraft file {path}: no positive wing span b and chord c"
    structure = _find(doc, "structure")
    structure = structure if isinstance(structure, dict) else {}
    nose, tail = structure.get("nose"), structure.get("tail")
    fwd = float(nose[0]) if isinstance(nose, list) and nose else 0.3 * b
    aft = -float(tail[0]) if isinstance(tail, list) and tail else 0.5 * b
    return {"b": float(b), "c": float(c), "nose": fwd, "tail": aft}, None


# ----------------------------------------------------------------------------------------------
# Series, downsampled
# ----------------------------------------------------------------------------------------------

def downsample(t):
    """The indices of the first sample in each 1/RATE_HZ-s bin of times t, and the last sample."""
    _, idx = np.unique(np.floor(np.asarray(t) * RATE_HZ), return_index=True)
    return np.union1d(idx, [len(t) - 1]) if len(t) else idx


def _flat(cols, digits):
    """Rows of the columns interleaved (flat), rounded; NaN as null (JSON has no NaN)."""
    a = np.round(np.column_stack(cols), digits).ravel()
    return [None if not math.isfinite(x) else float(x) for x in a]


def series(topic, to_world):
    """{t, ned, euler} of a State-shaped topic (positions moved by to_world), or None."""
    if topic is None or any(topic.get(f) is None for f in ("p_n", "p_e", "p_d", "phi", "theta", "psi")):
        return None
    k = downsample(topic.get("t"))
    ned = to_world(np.column_stack([topic.get(f)[k] for f in ("p_n", "p_e", "p_d")]))
    return {"t": _flat([topic.get("t")[k]], 3), "ned": _flat(ned.T, 2),
            "euler": _flat([topic.get(f)[k] for f in ("phi", "theta", "psi")], 4)}


def wind_series(run):
    """{t, w} (NED, m/s) from the truth's wind, else the estimate's; None when neither has it."""
    for name in ("truth", "state"):
        tp = read_topic(run["run_dir"], name, [], optional=True, extra=["w_n", "w_e", "w_d"])
        if tp is not None and tp.get("w_n") is not None and tp.get("w_e") is not None:
            k = downsample(tp.get("t"))
            w_d = tp.get("w_d")[k] if tp.get("w_d") is not None else np.zeros(len(k))
            return {"t": _flat([tp.get("t")[k]], 3), "w": _flat([tp.get("w_n")[k], tp.get("w_e")[k], w_d], 2)}
    return None


def ghost_series(run):
    """{t, a: [phi_c, theta_c]} of controller_internals, or None."""
    ci = run.get("controller_internals")
    if ci is None or ci.get("phi_c") is None or ci.get("theta_c") is None:
        return None
    k = downsample(ci.get("t"))
    return {"t": _flat([ci.get("t")[k]], 3), "a": _flat([ci.get("phi_c")[k], ci.get("theta_c")[k]], 4)}


def path_series(run, to_world):
    """{t, items, k}: the commanded paths (each distinct one once) and which is flown from t on
    (path_type as msg/path.hpp's CurrentPath::Type: 0 orbit, 1 line)."""
    p = read_topic(run["run_dir"], "current_path", [], optional=True, extra=PATH_FIELDS)
    if p is None or any(p.get(f) is None for f in ("path_type", "r_n", "r_e", "q_n", "q_e", "c_n", "c_e", "rho")):
        return None
    col = {f: np.nan_to_num(p.get(f)) if p.get(f) is not None else np.zeros(len(p)) for f in PATH_FIELDS}
    params = np.column_stack([col[f] for f in PATH_FIELDS])
    rows = np.concatenate([[0], np.nonzero(np.any(params[1:] != params[:-1], axis=1))[0] + 1])
    r = to_world(np.column_stack([col["r_n"], col["r_e"], col["r_d"]])[rows])
    c = to_world(np.column_stack([col["c_n"], col["c_e"], col["c_d"]])[rows])
    out = {"t": [], "items": [], "k": []}
    seen = {}
    for j, row in enumerate(rows):
        item = {"type": "orbit" if int(col["path_type"][row]) == 0 else "line", "r": _flat([r[j]], 2),
                "q": _flat([[col[f][row]] for f in ("q_n", "q_e", "q_d")], 4), "c": _flat([c[j]], 2),
                "rho": round(float(col["rho"][row]), 2), "lambda": int(col["lambda"][row])}
        key = json.dumps(item)
        if key not in seen:
            seen[key] = len(out["items"])
            out["items"].append(item)
        if not out["k"] or out["k"][-1] != seen[key]:
            out["t"].append(round(float(p.get("t")[row]), 3))
            out["k"].append(seen[key])
    return out


# ----------------------------------------------------------------------------------------------
# A vehicle, the run's fixed things, the page's data
# ----------------------------------------------------------------------------------------------

def vehicle_data(run, name, colour, to_world):
    """(the vehicle's part of the page's data, [what its run lacks])."""
    missing = []
    dims, why = aircraft_dims(run)
    if dims is None:
        span = 1.0  # m: the model drawn 1 m across, said on the page
        dims = {"b": span, "c": span / 8, "nose": 0.3 * span, "tail": 0.5 * span}
        missing.append(f"{why}: the model drawn {span:g} m across")
    truth, state = series(run["truth"], to_world), series(run["state"], to_world)
    if truth is None:
        missing.append("truth (the aircraft drawn at its estimate)" if state is not None else "truth")
    if state is None:
        missing.append("state (no estimated track)")
    d = {"name": name, "colour": colour, "dims": dims, "truth": truth, "state": state,
         "wind": wind_series(run), "ghost": ghost_series(run), "path": path_series(run, to_world)}
    for key, what in (("wind", "wind (truth's and state's w_n, w_e)"),
                      ("ghost", "controller_internals (no commanded-attitude ghost)"),
                      ("path", "current_path (no commanded path)")):
        if d[key] is None:
            missing.append(what)
    return d, missing


def statics(run, to_world):
    """(waypoints [NED], home NED or None, runway or None) of a run."""
    wps = run.get("waypoints", (None, True))[0]
    waypoints = [list(map(float, p)) for p in to_world(np.asarray(wps, float))] if wps is not None and len(wps) else []
    spans = phase_spans(run) if run.get("summary") is not None else []
    home = to_world(np.array([[0.0, 0.0, -home_altitude(run, spans)]]))[0].tolist() if run["state"] is not None else None
    spec = land_item(run, spans)
    runway = None
    if spec is not None:
        td = to_world(np.asarray([spec["td"]], float))[0]
        pose = run["truth"] if run["truth"] is not None else run["state"]
        along = 0.0
        if pose is not None and pose.get("p_n") is not None:  # the runway to where the aircraft ended
            last = to_world(np.array([[pose.get("p_n")[-1], pose.get("p_e")[-1], pose.get("p_d")[-1]]]))[0]
            along = (last[0] - td[0]) * math.cos(spec["heading"]) + (last[1] - td[1]) * math.sin(spec["heading"])
        b = aircraft_dims(run)[0]
        width = 4.0 * (b["b"] if b else 1.0)  # drawn four spans wide
        runway = {"td": [float(x) for x in td], "heading": float(spec["heading"]),
                  "length": float(max(along, width)), "width": width}
    return waypoints, home, runway


def scene_box(vehicles, waypoints):
    """(extent m, centre NED) of everything drawn."""
    pts = [np.asarray([x for x in s["ned"] if x is not None], float).reshape(-1, 3)
           for v in vehicles for s in (v["truth"], v["state"]) if s is not None and s["ned"]]
    if waypoints:
        pts.append(np.asarray(waypoints, float))
    if not pts:
        return 200.0, [0.0, 0.0, 0.0]
    p = np.vstack(pts)
    p = p[np.all(np.isfinite(p), axis=1)]
    lo, hi = p.min(axis=0), p.max(axis=0)
    return round(float(max(hi[0] - lo[0], hi[1] - lo[1], 100.0) * 1.2), 1), [round(float(x), 1) for x in (lo + hi) / 2]


def shared_bundle(src, out_dir):
    """view3d.js where the page finds it (module docstring): its path relative to out_dir."""
    with open(src, "rb") as f:
        name = f"tern-view3d-{hashlib.sha256(f.read()).hexdigest()[:12]}.js"
    out_dir = os.path.abspath(out_dir)
    if os.path.basename(out_dir) == "plots":  # <runs>/<run>/plots: one copy in <runs>
        target = os.path.join(os.path.dirname(os.path.dirname(out_dir)), name)
        try:
            if not os.path.isfile(target):
                tmp = f"{target}.{os.getpid()}.tmp"  # whole or absent, whoever writes it first
                shutil.copyfile(src, tmp)
                os.replace(tmp, target)
            return os.path.relpath(target, out_dir)
        except OSError:
            pass  # a read-only parent: the run keeps its own copy
    shutil.copyfile(src, os.path.join(out_dir, BUNDLE))
    return BUNDLE


def bundle_loader(candidates):
    """A script that loads the first of `candidates` (URLs) that exists, else says where it looked."""
    urls = json.dumps(candidates).replace("</", "<\\/")  # never a closing tag inside the script
    return ("<script>(function (urls) {\n"
            "  function next(i) {\n"
            "    if (i >= urls.length) {\n"
            "      document.getElementById('view3d').textContent = '3-D replay: view3d.js not found (' + urls.join(', ') +\n"
            "        '): run tern-plot on this run again to write it';\n"
            "      return;\n"
            "    }\n"
            "    var s = document.createElement('script');\n"
            "    s.src = urls[i];\n"
            "    s.onerror = function () { next(i + 1); };\n"
            "    document.body.appendChild(s);\n"
            "  }\n"
            f"  next(0);\n}})({urls});</script>\n")


def write_view3d(out_dir, vehicles, waypoints, home, runway, missing):
    """view3d_data.js into out_dir, view3d.js where the page finds it (shared_bundle); the
    index.html section (HTML), or a note when view3d.js is not installed."""
    src = bundle_path()
    esc = html.escape
    if src is None:
        return ('<p class="hint">3-D replay not written: view3d.js is not installed (make deps runs npm ci in '
                "core/apps/console, then rebuild)</p>")
    t = [x for v in vehicles for s in (v["truth"], v["state"]) if s for x in (s["t"][0], s["t"][-1])]
    extent, center = scene_box(vehicles, waypoints)
    data = {"t0": min(t) if t else 0.0, "t1": max(t) if t else 0.0, "extent": extent, "center": center,
            "wind_gain": WIND_GAIN, "waypoints": waypoints, "home": home, "runway": runway,
            "missing": [f"missing in this run: {'; '.join(missing)}"] if missing else [], "vehicles": vehicles}
    with open(os.path.join(out_dir, DATA), "w", encoding="utf-8") as f:
        f.write("window.TERN_VIEW3D = " + json.dumps(data, separators=(",", ":"), allow_nan=False) + ";\n")
    page_src = shared_bundle(src, out_dir)
    candidates = [pathlib.PurePath(page_src).as_posix()]
    if page_src != BUNDLE:
        candidates.append(pathlib.Path(src).resolve().as_uri())
    return (f'<h2 id="replay3d">3-D replay</h2>\n<div id="view3d"></div>\n<p class="hint">Drag to turn, wheel to zoom '
            "(free camera: the models drawn larger, their span 1/25 of the scene; follow: at their size); the URL's <code>#t=SECONDS</code> opens the "
            f'replay at that time.</p>\n<script src="{esc(DATA)}"></script>\n' + bundle_loader(candidates))


VIEW3D_STYLE = """
#view3d { position: relative; max-width: 1100px; }
.view3d-stage { width: 100%; height: 520px; border: 1px solid #ccc; }
.view3d-bar { display: flex; gap: 0.6em; align-items: center; margin: 0.3em 0; }
.view3d-bar input[type=range] { flex: 1; }
.view3d-hud { font-size: 0.85em; color: #444; }
.hint { font-size: 0.85em; color: #666; }
"""


def identity(p):
    return p


def runs_view3d(runs, out_dir):
    """The 3-D replay of one run, or of an overlay's runs (each in its colour, each in its own
    estimator's NED), into out_dir: the index.html section."""
    vehicles, missing = [], []
    for run in runs:
        v, lacks = vehicle_data(run, run["label"], run.get("colour", "#c0392b"), identity)
        vehicles.append(v)
        missing += [f"{run['label']}: {m}" if len(runs) > 1 else m for m in lacks]
    waypoints, home, runway = statics(runs[0], identity)
    return write_view3d(out_dir, vehicles, waypoints, home, runway, missing)


def fleet_view3d(vehicles, origin, out_dir):
    """A multi-vehicle run's 3-D replay into out_dir: every vehicle in its fleet colour in the
    world NED about `origin` (tern_plot_fleet.py's), each moved there from its estimator's NED
    exactly through ECEF (tern_plot_mission.ned_to_ned); the index.html section."""
    from tern_plot_load import last_origin
    from tern_plot_mission import ned_to_ned
    out, missing, waypoints, home, runway = [], [], [], None, None
    for v in vehicles:
        run = v["run"]
        o_est = last_origin(run["state"])
        if origin is None or (o_est is None and run["truth_origin"] is None):
            missing.append(f"{v['name']}: no origin to place it in the world frame (not drawn)")
            continue
        if o_est is not None:
            def to_world(p, o=o_est):
                return ned_to_ned(p, o, origin)
        else:  # truth only: load_run's shift into the (absent) estimator frame undone
            def to_world(p, run=run):
                return ned_to_ned(np.asarray(p, float) + run["truth_shift"], run["truth_origin"], origin)
        d, lacks = vehicle_data(run, v["name"], v.get("colour", "#c0392b"), to_world)
        out.append(d)
        missing += [f"{v['name']}: {m}" for m in lacks]
        w, h, r = statics(run, to_world)
        waypoints += w
        home, runway = home or h, runway or r
    return write_view3d(out_dir, out, waypoints, home, runway, missing) if out else ""
