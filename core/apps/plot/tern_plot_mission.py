"""tern plot: the configured mission's waypoints (config.yaml's mission: section, tern waypoint
files, ROSplane mission files), in NED about the estimator's origin."""

import math
import os
import re

import numpy as np

from tern_plot_log import note
from tern_plot_yaml import YamlError, top_level_section, yaml_load

# ----------------------------------------------------------------------------------------------
# Mission waypoints
# ----------------------------------------------------------------------------------------------

WGS84_A = 6378137.0
WGS84_F = 1.0 / 298.257223563


def _ecef(lat_deg, lon_deg, alt):
    e2 = WGS84_F * (2.0 - WGS84_F)
    lat, lon = math.radians(lat_deg), math.radians(lon_deg)
    n = WGS84_A / math.sqrt(1.0 - e2 * math.sin(lat) ** 2)
    return np.array([(n + alt) * math.cos(lat) * math.cos(lon),
                     (n + alt) * math.cos(lat) * math.sin(lon),
                     (n * (1.0 - e2) + alt) * math.sin(lat)])


def ecef_to_ned_rotation(origin):
    """The 3 x 3 rotation from ECEF axes to the NED axes of the local tangent plane at origin
    (deg, deg, m): ned = R @ (ecef - ecef(origin))."""
    lat, lon = math.radians(origin[0]), math.radians(origin[1])
    sl, cl, so, co = math.sin(lat), math.cos(lat), math.sin(lon), math.cos(lon)
    return np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])


def lla_to_ned(lla, origin):
    """Geodetic (deg, deg, m) -> NED (m) about origin (deg, deg, m), WGS84 local tangent plane."""
    return [float(x) for x in ecef_to_ned_rotation(origin) @ (_ecef(*lla) - _ecef(*origin))]


def ned_to_ned(ned, origin, to_origin):
    """Points (N x 3, NED about origin) -> NED about to_origin: exact through ECEF (the two
    tangent planes' tilt included), both origins (deg, deg, m) on WGS84."""
    rot = ecef_to_ned_rotation(to_origin) @ ecef_to_ned_rotation(origin).T
    return np.asarray(ned, dtype=float) @ rot.T + np.array(lla_to_ned(origin, to_origin))


def _triple(v):
    if isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                   for x in v):
        return [float(x) for x in v]
    return None


def _waypoint(entry):
    """One mission entry -> (position triple, is_lla) or None. A return_home item is home
    (n = e = 0) at its altitude (NaN when it keeps the altitude of the item before it)."""
    t = _triple(entry)
    if t is not None:
        return t, False
    if not isinstance(entry, dict):
        return None
    if entry.get("type") == "return_home":
        alt = entry.get("altitude")
        return [0.0, 0.0, -float(alt) if isinstance(alt, (int, float)) else math.nan], False
    for key in ("ned", "w"):
        if key in entry and _triple(entry[key]) is not None:
            return _triple(entry[key]), entry.get("lla") is True
    if "lla" in entry and _triple(entry["lla"]) is not None:
        return _triple(entry["lla"]), True
    return None


def parse_rosplane(text):
    """ROSplane mission file: repeated top-level `wp:` maps. Split at every `wp:` line."""
    chunks = []
    for line in text.splitlines():
        if re.match(r"^wp\s*:", line):
            chunks.append([])
        elif chunks:
            chunks[-1].append(line)
    wps = []
    for chunk in chunks:
        entry = yaml_load("\n".join(chunk))
        wp = _waypoint(entry)
        if wp is None:
            raise YamlError("a wp: entry without w: [n, e, d]")
        wps.append(wp)
    return wps, True


def parse_mission_text(text):
    if re.search(r"^wp\s*:", text, re.M):
        return parse_rosplane(text)
    doc = yaml_load(text)
    if not isinstance(doc, dict):
        raise YamlError("expected a map with waypoints")
    return _entries(doc.get("waypoints")), doc.get("loop", True) is not False


def _entries(seq):
    wps = []
    for k, entry in enumerate(seq or []):
        wp = _waypoint(entry)
        if wp is None:
            raise YamlError(f"waypoint {k}: expected [n, e, d] or a map with ned, w or lla")
        wps.append(wp)
    return wps


def mission_waypoints(run_dir, state, truth):
    """Returns (N x 3 NED array, loop) of the configured mission, or (None, True)."""
    cfg_path = os.path.join(run_dir, "config.yaml")
    if not os.path.isfile(cfg_path):
        note("config.yaml missing: no waypoints drawn")
        return None, True
    with open(cfg_path, encoding="utf-8", errors="replace") as f:
        text = f.read()
    m = re.match(r"#\s*resolved from\s+(.+?)\s*$", text.splitlines()[0] if text else "")
    config_dir = os.path.dirname(m.group(1)) if m else run_dir
    try:
        cfg = yaml_load(text)
        if not isinstance(cfg, dict):
            raise YamlError("not a map")
    except YamlError:
        try:
            cfg = yaml_load(top_level_section(text, "mission")) or {}
        except YamlError as e:
            note(f"config.yaml: mission section not readable ({e}): no waypoints drawn")
            return None, True

    def resolve(p):
        if os.path.isabs(p):
            return p
        for base in (config_dir, run_dir):
            if os.path.exists(os.path.join(base, p)):
                return os.path.join(base, p)
        return os.path.join(config_dir, p)

    source = None
    for inst in cfg.get("plugins") or []:
        if isinstance(inst, dict) and inst.get("plugin") == "path_planner":
            mf = (inst.get("params") or {}).get("mission_file")
            if isinstance(mf, str) and mf:
                source = resolve(mf)
    mission = cfg.get("mission")
    loop = True
    try:
        if source is None and isinstance(mission, dict) and isinstance(mission.get("file"), str):
            source = resolve(mission["file"])
        if source is not None:
            try:
                with open(source, encoding="utf-8", errors="replace") as f:
                    wps, loop = parse_mission_text(f.read())
            except OSError:
                note(f"mission file {source} not readable: no waypoints drawn")
                return None, True
            if isinstance(mission, dict) and isinstance(mission.get("loop"), bool):
                loop = mission["loop"]
        elif isinstance(mission, dict):
            wps, loop = _entries(mission.get("waypoints")), mission.get("loop", True) is not False
        else:
            note("config.yaml has no mission section: no waypoints drawn")
            return None, True
    except YamlError as e:
        note(f"mission waypoints not readable ({source or 'config.yaml'}: {e}): none drawn")
        return None, True
    if not wps:
        return None, loop
    out = []
    origin = None
    if any(is_lla for _, is_lla in wps):
        origin = geo_origin(state, truth, cfg)
        if origin is None:
            note("lat/lon waypoints but no origin in the log: only NED waypoints drawn")
    for w, is_lla in wps:
        if is_lla:
            if origin is not None:
                out.append(lla_to_ned(w, origin))
        else:
            out.append(w)
    return (np.array(out) if out else None), loop


def geo_origin(state, truth, cfg):
    for topic in (state, truth):
        if topic is None:
            continue
        lat, lon, alt, ok = (topic.get(k) for k in ("origin_lat", "origin_lon", "origin_alt", "origin_valid"))
        if lat is None or lon is None or alt is None:
            continue
        idx = np.nonzero(ok > 0.5)[0] if ok is not None else np.arange(len(lat))
        if len(idx):  # the last origin: the planner converts again when the origin moves
            return float(lat[idx[-1]]), float(lon[idx[-1]]), float(alt[idx[-1]])
    for inst in cfg.get("plugins") or []:
        p = inst.get("params") if isinstance(inst, dict) else None
        if isinstance(p, dict) and all(isinstance(p.get(k), (int, float)) for k in
                                       ("origin_lat", "origin_lon", "origin_alt")):
            return float(p["origin_lat"]), float(p["origin_lon"]), float(p["origin_alt"])
    return None
