"""tern.Run: what a flight wrote (core/host/record/flight_log.hpp), as Python objects.

    run = tern.Run("runs/20261125T231634Z-default")     # a run directory
    run = tern.Run("runs/.../flight.mcap")               # or an MCAP log
    run.topics                  # ["actuators", "state", ...]
    s = run["state"]            # numpy structured array: s["t"], s["p_d"], s["phi"] ...
    run.units("state")["p_d"]   # "m"; also s.dtype.metadata["units"]
    run.summary, run.params, run.param_changes, run.events, run.config

A topic's table is read once and kept. Its columns are the log's ("t" is the flight time in s,
"stamp" the message's time in ns); a column's unit is the header's "[unit]". A column whose unit is
"ns" is int64, "bool" is bool, every other float64. An MCAP log is read through `tern export csv`'s
code (tern._tern.export_csv, byte for byte the CSV log's tables) into a temporary directory.
"""

import csv
import json
import math
import re
import shutil
import tempfile
from pathlib import Path

import numpy as np

from tern._tern import Error, export_csv
from tern._tern import read_table as _read_rows

_HEADER_CELL = re.compile(r"^(.*?)(?: \[(.*)\])?$")


def _cell(text):
    """A params.csv value: a number when it reads as one, a list for "[a, b]", else the text."""
    try:
        return float(text)
    except ValueError:
        pass
    if text.startswith("[") and text.endswith("]"):
        try:
            return [float(x) for x in text[1:-1].split(",") if x.strip()]
        except ValueError:
            return text
    return {"true": True, "false": False}.get(text, text)


def read_table(path):
    """A topic CSV (header "name [unit]", then rows) as a numpy structured array with the units
    in its dtype's metadata. The header makes the dtype; the rows are parsed into it in C++
    (tern._tern.read_table: std::from_chars, the exact inverse of the log's std::to_chars, on two
    threads, without a copy). Raises tern.Error naming the file and line for a malformed table (a
    cell that is not a number, a row of another length than the header)."""
    path = Path(path)
    with open(path, newline="") as f:
        header = f.readline().rstrip("\r\n")
    if not header:
        raise Error(f"{path}: empty file, not a topic table")
    names, units = [], {}
    for cell in header.split(","):
        name, unit = _HEADER_CELL.match(cell).groups()
        names.append(name)
        units[name] = unit or ""
    kinds = [np.int64 if units[n] == "ns" else bool if units[n] == "bool" else np.float64 for n in names]
    dtype = np.dtype({"names": names, "formats": kinds}, metadata={"units": units})
    return _read_rows(str(path), dtype)


def read_json(directory, name, missing):
    """directory/name parsed; tern.Error "<directory>: no <name> (<missing>)" when it is not there."""
    f = directory / name
    if not f.is_file():
        raise Error(f"{directory}: no {name} ({missing})")
    with open(f) as fh:
        return json.load(fh)


class Run:
    """A run directory (or an MCAP log) read as Python objects; see the module's docstring."""

    def __init__(self, path):
        path = Path(path)
        self.path = path
        self._tables = {}
        self._tmp = None
        if path.is_file() and path.suffix == ".mcap":
            self.dir = path.parent
            self._tmp = tempfile.mkdtemp(prefix="tern-run-")
            export_csv(str(path), self._tmp)
            self._topic_dir = Path(self._tmp)
        elif path.is_dir():
            self.dir = path
            self._topic_dir = path / "topics"
            mcap = path / "flight.mcap"
            if not self._topic_dir.is_dir() and mcap.is_file():  # log.format mcap: the tables from the MCAP
                self._tmp = tempfile.mkdtemp(prefix="tern-run-")
                export_csv(str(mcap), self._tmp)
                self._topic_dir = Path(self._tmp)
        else:
            raise Error(f"{path}: not a run directory or an MCAP file (.mcap)")

    def __del__(self):
        if getattr(self, "_tmp", None):
            shutil.rmtree(self._tmp, ignore_errors=True)

    def __repr__(self):
        return f"tern.Run('{self.path}')"

    @property
    def topics(self):
        """The logged topics' names, sorted."""
        if not self._topic_dir.is_dir():
            return []
        return sorted(p.stem for p in self._topic_dir.glob("*.csv"))

    def __contains__(self, topic):
        return (self._topic_dir / f"{topic}.csv").is_file()

    def __getitem__(self, topic):
        """The topic's table as a numpy structured array (see the module's docstring)."""
        if topic not in self._tables:
            f = self._topic_dir / f"{topic}.csv"
            if not f.is_file():
                raise Error(f"{self.path}: no topic '{topic}' logged; its topics: {', '.join(self.topics) or '(none)'}")
            self._tables[topic] = read_table(f)
        return self._tables[topic]

    def units(self, topic):
        """{column: unit} of a topic's table."""
        return dict(self[topic].dtype.metadata["units"])

    def _json(self, name):
        return read_json(self.dir, name, "a flight that did not finish, or not a run directory")

    @property
    def summary(self):
        """summary.json: what the flight did (same config and seed: the same bytes)."""
        return self._json("summary.json")

    @property
    def timing(self):
        """timing.json: how long it took on the wall clock."""
        return self._json("timing.json")

    @property
    def param_changes(self):
        """params.csv's rows: [{"t", "parameter", "value", "source"}], the values at the start first."""
        f = self.dir / "params.csv"
        if not f.is_file():
            raise Error(f"{self.dir}: no params.csv")
        with open(f, newline="") as fh:
            return [{"t": float(r["t [s]"]), "parameter": r["parameter"], "value": _cell(r["value"]), "source": r["source"]}
                    for r in csv.DictReader(fh)]

    @property
    def params(self):
        """{"instance.param": value} as the flight started."""
        out = {}
        for row in self.param_changes:
            out.setdefault(row["parameter"], row["value"])
        return out

    @property
    def events(self):
        """What happened, in time order: [{"t" (s), "kind", "what"}] of kinds "phase",
        "handover", "failsafe", "waypoint" (summary.json) and "param" (a change in flight)."""
        s = self.summary
        ev = [{"t": p["start_s"], "kind": "phase", "what": f"{p['phase']}: {p.get('reason', '')}"} for p in s.get("phases", [])]
        ev += [{"t": h["t_s"], "kind": "handover", "what": f"{h['from']} -> {h['to']}: {h['reason']}"}
               for h in s.get("controller_handovers", [])]
        ev += [{"t": f.get("t_s", math.nan), "kind": "failsafe", "what": json.dumps(f)} for f in s.get("failsafes", [])]
        ev += [{"t": w["t_s"], "kind": "waypoint", "what": f"waypoint {w['waypoint']} passed"}
               for w in s.get("metrics", {}).get("waypoint_passages", [])]
        ev += [{"t": r["t"], "kind": "param", "what": f"{r['parameter']} = {r['value']} ({r['source']})"}
               for r in self.param_changes if r["t"] > 0]
        return sorted(ev, key=lambda e: (e["t"], e["kind"]))

    @property
    def config(self):
        """config.yaml as flown (every parameter's effective value), read with PyYAML."""
        import yaml
        f = self.dir / "config.yaml"
        if not f.is_file():
            raise Error(f"{self.dir}: no config.yaml")
        with open(f) as fh:
            return yaml.safe_load(fh)
