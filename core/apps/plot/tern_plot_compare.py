"""tern plot A/B: what differs between two runs drawn over each other. From each run directory's
summary.json, config.yaml and params.csv: the mission (name, file, waypoints), the sensor profile
(sim.sensor_profile), the duration flown, the seed, the aircraft, the plugin instances and the
phase table, and every parameter whose value differs (the values the flight started with;
params.csv, else config.yaml's plugin params). Printed as one block on the terminal and shown at
the top of the overlay's index.html, with a warning when the missions differ: then the figures
compare different flights, not one flight flown two ways."""

import html
import os

PARAMS_SHOWN = 8  # parameters named in the one-line block; index.html's table has them all

# ----------------------------------------------------------------------------------------------
# What one run is: the facts the block compares
# ----------------------------------------------------------------------------------------------


def _cfg_source(run):
    """The config file the run was flown from (config.yaml's "# resolved from <path>"), or None."""
    path = os.path.join(run["run_dir"], "config.yaml")
    try:
        with open(path, encoding="utf-8", errors="replace") as f:
            first = f.readline()
    except OSError:
        return None
    return first.split("resolved from", 1)[1].strip() if "resolved from" in first else None


def sensor_profile(run):
    """summary.json's sensor_profile, else the first plugin's sensor_profile parameter, else None."""
    profile = run["summary"].get("sensor_profile")
    if profile:
        return str(profile)
    for name, values in sorted(run.get("params", {}).items()):
        if name.endswith(".sensor_profile") and values:
            return values[0][1]
    for inst in run["config"].get("plugins") or []:
        if isinstance(inst, dict) and isinstance(inst.get("params"), dict) and "sensor_profile" in inst["params"]:
            return str(inst["params"]["sensor_profile"])
    return None


def run_facts(run):
    """{mission, mission_file, sensor_profile, duration_s, seed, aircraft} of one loaded run
    (tern_plot_load.py's load_run); None where the run does not say."""
    s, cfg = run["summary"], run["config"]
    mission_cfg = cfg.get("mission") if isinstance(cfg.get("mission"), dict) else {}
    duration = s.get("duration_s")
    return {"mission": s.get("mission") or cfg.get("name"),
            "mission_file": mission_cfg.get("file") or _cfg_source(run),
            "sensor_profile": sensor_profile(run),
            "duration_s": float(duration) if isinstance(duration, (int, float)) else run.get("t_end"),
            "seed": s.get("seed", cfg.get("seed")),
            "aircraft": cfg.get("aircraft") or None}


def instances(run):
    """{instance name: plugin} of config.yaml's plugins."""
    return {p["name"]: p.get("plugin") for p in run["config"].get("plugins") or []
            if isinstance(p, dict) and "name" in p}


def start_params(run):
    """{qualified parameter name: text value the flight started with}: params.csv's first value
    of each, else config.yaml's plugin params (<instance>.<param>)."""
    if run.get("params"):
        return {name: values[0][1] for name, values in run["params"].items() if values}
    out = {}
    for p in run["config"].get("plugins") or []:
        if isinstance(p, dict) and isinstance(p.get("params"), dict):
            out.update({f"{p.get('name')}.{k}": _text(v) for k, v in p["params"].items()})
    return out


def _text(v):
    if isinstance(v, float) and v == int(v) and abs(v) < 1e12:
        return str(int(v))
    if isinstance(v, list):
        return "[" + ", ".join(_text(x) for x in v) + "]"
    return "-" if v is None else str(v)


def _same_value(a, b):
    """Two parameter texts equal, as numbers where both are numbers (0.15 and 1.5e-1)."""
    try:
        return float(a) == float(b)
    except (TypeError, ValueError):
        return a == b


# ----------------------------------------------------------------------------------------------
# The differences
# ----------------------------------------------------------------------------------------------

def _waypoints_differ(a, b):
    """Whether the two runs fly different waypoints (the configured mission, else the first
    list the planner published); False when either run does not say."""
    wa, wb = a["waypoints"][0], b["waypoints"][0]
    if wa is None and a.get("flown"):
        wa = a["flown"][0][2]
    if wb is None and b.get("flown"):
        wb = b["flown"][0][2]
    if wa is None or wb is None:
        return False
    return wa.shape != wb.shape or bool(abs(wa - wb).max(initial=0.0) > 0.5)


def fact_differences(fa, fb):
    """[(what, text)] of the facts that differ (mission, sensor profile, duration, seed, aircraft)."""
    out = []
    if fa["mission"] != fb["mission"]:
        out.append(("mission", f"mission {_text(fa['mission'])} vs {_text(fb['mission'])}"))
    if fa["mission_file"] != fb["mission_file"] and fa["mission_file"] and fb["mission_file"]:
        out.append(("mission_file", f"mission file {_short(fa['mission_file'], fb['mission_file'])}"))
    if fa["sensor_profile"] != fb["sensor_profile"]:
        out.append(("sensor_profile", f"sensor profile {_text(fa['sensor_profile'])} vs {_text(fb['sensor_profile'])}"))
    da, db = fa["duration_s"], fb["duration_s"]
    if da is not None and db is not None and abs(da - db) >= 0.05:
        out.append(("duration", f"duration {da:.1f} vs {db:.1f} s"))
    if fa["seed"] != fb["seed"]:
        out.append(("seed", f"seed {_text(fa['seed'])} vs {_text(fb['seed'])}"))
    if fa["aircraft"] != fb["aircraft"]:
        out.append(("aircraft", f"aircraft {_short(fa['aircraft'], fb['aircraft'])}"))
    return out


def _short(a, b):
    """"a vs b" by file name, by the whole path where the file names are the same."""
    na, nb = os.path.basename(str(a)), os.path.basename(str(b))
    return f"{na} vs {nb}" if na != nb else f"{a} vs {b}"


def libraries(run):
    """{instance name: its plugin library's FNV-1a hash} of summary.json's instances."""
    return {name: d.get("library_fnv1a") for name, d in (run["summary"].get("instances") or {}).items()
            if isinstance(d, dict) and d.get("library_fnv1a")}


def setup_differences(a, b):
    """[text] of the plugin instances, their libraries (another build) and the phase table that differ."""
    out = []
    ia, ib = instances(a), instances(b)
    la, lb = libraries(a), libraries(b)
    for name in sorted(set(ia) | set(ib)):
        if name not in ib:
            out.append(f"instance {name} ({ia[name]}) only in {a['label']}")
        elif name not in ia:
            out.append(f"instance {name} ({ib[name]}) only in {b['label']}")
        elif ia[name] != ib[name]:
            out.append(f"plugin of {name} {ia[name]} vs {ib[name]}")
        elif la.get(name) and lb.get(name) and la[name] != lb[name]:
            out.append(f"plugin library of {name} ({ia[name]}): another build (FNV-1a {la[name]} vs {lb[name]})")
    pa, pb = a["config"].get("phases") or {}, b["config"].get("phases") or {}
    if isinstance(pa, dict) and isinstance(pb, dict):
        for phase in [p for p in pa if p in pb] + [p for p in pa if p not in pb] + [p for p in pb if p not in pa]:
            if pa.get(phase) != pb.get(phase):
                out.append(f"phases.{phase} {_text(pa.get(phase))} vs {_text(pb.get(phase))}")
    return out


def param_differences(a, b):
    """[(name, value in a or None, value in b or None)] of the parameters that differ, by name;
    left out: the sensor profile (a fact of its own) and the parameters of an instance only one
    run has (named as such by setup_differences)."""
    pa, pb = start_params(a), start_params(b)
    ia, ib = instances(a), instances(b)
    lone = set(ia) ^ set(ib)
    out = []
    for name in sorted(set(pa) | set(pb)):
        if name.endswith(".sensor_profile") or name.split(".", 1)[0] in lone:
            continue
        va, vb = pa.get(name), pb.get(name)
        if va is None or vb is None or not _same_value(va, vb):
            out.append((name, va, vb))
    return out


def compare(a, b):
    """What differs between runs a and b (tern_plot_load.py's loaded runs): {a, b, facts (fact_differences),
    setup, params, missions_differ}."""
    fa, fb = run_facts(a), run_facts(b)
    facts = fact_differences(fa, fb)
    differ = any(what in ("mission", "mission_file") for what, _ in facts) or _waypoints_differ(a, b)
    if differ and not any(what.startswith("mission") for what, _ in facts):
        facts.insert(0, ("mission", f"mission waypoints ({_text(fa['mission'])} flies other waypoints)"))
    return {"a": a["label"], "b": b["label"], "facts": facts, "setup": setup_differences(a, b),
            "params": param_differences(a, b), "missions_differ": differ, "mission_a": fa["mission"],
            "mission_b": fb["mission"]}


def compare_runs(runs):
    """compare() of the first run against each other one ([] for one run)."""
    return [compare(runs[0], other) for other in runs[1:]]


# ----------------------------------------------------------------------------------------------
# The block: terminal lines and index.html
# ----------------------------------------------------------------------------------------------

def _cut(texts, limit, where):
    more = f" (+{len(texts) - limit} more: {where})" if len(texts) > limit else ""
    return "; ".join(texts[:limit]) + more


def param_items(d, where="index.html", limit=PARAMS_SHOWN):
    """The parameter differences as texts: those both runs have ("parameters (n): name a vs b; ..."),
    then those only one run has ("parameters only in B (n): name, ...")."""
    both = [f"{name} {_text(va)} vs {_text(vb)}" for name, va, vb in d["params"] if va is not None and vb is not None]
    out = [f"parameters ({len(both)}): {_cut(both, limit, where)}"] if both else []
    for k, label in ((2, d["b"]), (1, d["a"])):
        only = [p[0] for p in d["params"] if p[k] is not None and p[3 - k] is None]
        if only:
            out.append(f"parameters only in {label} ({len(only)}): {_cut(only, limit, where).replace('; ', ', ')}")
    return out


def block_items(d, where="index.html"):
    """The differences as short texts: facts, then plugins and phases, then parameters."""
    return [text for _, text in d["facts"]] + d["setup"] + param_items(d, where)


def headline(d):
    """The block's first line, without the "A/B: " prefix."""
    pair = f"{d['a']} vs {d['b']}: "
    items = block_items(d)
    if not items:
        return pair + ("these runs differ in nothing tern plot compares (mission, sensor profile, duration, seed, "
                       "aircraft, plugins, phases, parameters)")
    if not d["facts"]:
        return pair + ("same mission, sensor profile, duration, seed and aircraft: only the compared plugins/"
                       "parameters differ: " + "; ".join(items))
    return pair + "these runs differ in: " + "; ".join(items)


def warning(d):
    """The warning when the missions differ, else None."""
    if not d["missions_differ"]:
        return None
    return (f"warning: the missions differ ({_text(d['mission_a'])} vs {_text(d['mission_b'])}): the figures compare "
            "different flights, not one flight flown two ways")


def terminal_lines(differences):
    """The block printed on the terminal: per compared pair its headline and, when the missions
    differ, a warning line."""
    out = []
    for d in differences:
        out.append("A/B: " + headline(d))
        if warning(d):
            out.append("A/B: " + warning(d))
    return out


def html_block(differences):
    """The block for the top of the overlay's index.html ("" for one run)."""
    esc = html.escape
    parts = []
    for d in differences:
        items = block_items(d, "the table below the figures")
        pair = f"{d['a']} vs {d['b']}"
        if not items:
            head = headline(d)
        elif not d["facts"]:
            head = f"{pair}: same mission, sensor profile, duration, seed and aircraft; only the compared plugins/parameters differ:"
        else:
            head = f"{pair}: these runs differ in:"
        warn = f'<p class="warning">{esc(warning(d))}</p>' if warning(d) else ""
        lis = "".join(f"<li>{esc(i)}</li>" for i in items)
        parts.append(f'<div class="differences">{warn}<p>{esc(head)}</p>{"<ul>" + lis + "</ul>" if lis else ""}</div>')
    return "\n".join(parts)


def param_rows(differences):
    """[(pair, parameter, value A, value B)] of every pair's parameter differences (index.html's table)."""
    return [[f"{d['a']} vs {d['b']}", name, _text(va), _text(vb)] for d in differences for name, va, vb in d["params"]]
