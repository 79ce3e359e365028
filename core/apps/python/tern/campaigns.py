"""tern.campaign: a Monte Carlo campaign (docs/campaigns.md) flown from Python, and its table
(this module is tern.campaigns, named apart from the function).

    c = tern.campaign("configs/campaigns/landing_dispersion.yaml", workers=2, out="campaigns/mine")
    c.table                      # numpy structured array: one row per flight (results.csv)
    c.table["metrics.landing.sink_rate_mps"][c.table["outcome"] == "pass"]
    c.rows                       # the same as a list of dicts; c.units["sim.wind.speed"] == "m/s"
    c.summary                    # summary.json: pass rate and its 95 % interval, percentiles, worst
    c.run(k)                     # flight k's tern.Run
    tern.Campaign("campaigns/mine")   # a campaign's output directory, read back

How it flies: tern.campaign runs the program `tern campaign FILE --workers N --out D` runs (the
build's bin/tern, its extension command tern-campaign: core/apps/campaign/campaign_main.cpp) as a
child process, then reads its output directory. Not a binding of that code, because the campaign
flies every flight as a child process `tern fly` anyway (by design: the row's re-fly command is
exactly what ran, and a plugin that aborts ends one flight, not the campaign), and it installs
SIGINT/SIGTERM handlers to stop its children and resume later: in this process they would take
over Python's Ctrl-C. A binding would fly nothing faster; the program is the CLI's code path as it
is, with the same resume (run it again into the same `out`: only flights without a summary fly).

The table: `index` int64, `seed` uint64 (a flight seed is 0 .. 2^64-1), `outcome` ("pass", "fail",
"error"), `why`, `command`, then every drawn value (its unit in `units`) and every summary.json
figure flattened (`metrics.max_cross_track_m`, `instances.sim.sim_crashed` ...). A column of
whole numbers is int64 (uint64 beyond it), of true/false bool, of other numbers float64 (an empty
cell NaN), else text. A figure named like an earlier column (summary.json's `seed`) is
`summary.<name>`.
"""

import csv
import re
import subprocess
from pathlib import Path

import numpy as np

from tern._tern import Error, bin_dir
from tern.run import read_json

_HEADER_CELL = re.compile(r"^(.*?)(?: \[(.*)\])?$")
_INT = re.compile(r"^-?[0-9]+$")


def campaign(file, *, workers=None, out=None, plots=False, quiet=True):
    """Flies the campaign `file` as `tern campaign FILE --workers N --out D` does (see the module's
    docstring) and returns its Campaign. workers: flights at once (default: every core); out: its
    output directory (default campaigns/<name>, as the CLI's); plots: also tern-campaign-plot's
    plots (the CLI's default; off here: the table is the Python user's); quiet: the campaign's
    progress and report lines captured (False: printed as it flies). Raises tern.Error with the
    campaign's own error line (a bad file, field or value; another campaign's output directory)."""
    file = Path(file)
    if not file.is_file():
        raise Error(f"tern.campaign: {file}: no such campaign file")
    if workers is not None and (not isinstance(workers, (int, np.integer)) or workers < 1):
        raise Error(f"tern.campaign: workers {workers!r}: a whole number of at least 1")
    cmd = [str(Path(bin_dir()) / "tern"), "campaign", str(file)]
    if workers is not None:
        cmd += ["--workers", str(int(workers))]
    if out is not None:
        cmd += ["--out", str(out)]
    if not plots:
        cmd.append("--no-plots")
    r = subprocess.run(cmd, capture_output=quiet, text=True)
    if r.returncode != 0:
        if quiet:
            lines = [line for line in r.stderr.splitlines() if "error" in line] or r.stderr.strip().splitlines()[-3:]
            raise Error("; ".join(lines) or f"tern campaign {file}: exit status {r.returncode}")
        raise Error(f"tern campaign {file}: exit status {r.returncode} (its errors are printed above)")
    text = r.stdout if quiet else ""
    where = re.search(r"^results: (.*)/summary\.md$", text, re.M)
    out_dir = Path(where.group(1)) if where else Path(out) if out is not None else None
    if out_dir is None:  # not quiet: the default directory, as the CLI makes it
        out_dir = Path("campaigns") / _campaign_name(file)
    return Campaign(out_dir)


def _campaign_name(file):
    import yaml
    with open(file) as f:
        doc = yaml.safe_load(f) or {}
    return str(doc.get("name", Path(file).stem))


class Campaign:
    """A campaign's output directory (results.csv, summary.json ...) read back; see the module's
    docstring."""

    def __init__(self, path):
        self.dir = Path(path)
        if not (self.dir / "results.csv").is_file():
            raise Error(f"{self.dir}: no results.csv (not a campaign's output directory, or one never collected)")
        self.table, self.units = read_results(self.dir / "results.csv")

    def __repr__(self):
        return f"tern.Campaign('{self.dir}')"

    def __len__(self):
        return len(self.table)

    @property
    def rows(self):
        """The table as a list of dicts, one per flight (plain Python values)."""
        names = self.table.dtype.names
        return [dict(zip(names, row)) for row in self.table.tolist()]

    def _json(self, name):
        return read_json(self.dir, name, "a campaign that did not finish, or not a campaign directory")

    @property
    def summary(self):
        """summary.json: pass rate (and its 95 % Wilson interval), figure percentiles, the worst flights."""
        return self._json("summary.json")

    @property
    def throughput(self):
        """throughput.json: wall time, flights per minute (of the last time flights were flown)."""
        return self._json("throughput.json")

    def run(self, index):
        """Flight `index`'s tern.Run (its log at the campaign's log level: summary.json at least)."""
        from tern.run import Run
        runs = sorted((self.dir / "flights" / f"{int(index):05d}" / "run").glob("*/summary.json"))
        if not runs:
            raise Error(f"{self.dir}: flight {index} has no complete run (flights 0 .. {len(self) - 1})")
        return Run(runs[-1].parent)


def read_results(path):
    """results.csv as (numpy structured array, {column: unit}); the typing rules are the module's."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        raise Error(f"{path}: empty file, not a campaign's results.csv")
    header, body = rows[0], rows[1:]
    for k, row in enumerate(body):
        if len(row) != len(header):
            raise Error(f"{path}:{k + 2}: {len(row)} cells, the header has {len(header)} columns")
    names, units = [], {}
    for cell in header:
        name, unit = _HEADER_CELL.match(cell).groups()
        if name in units:
            name = "summary." + name
        names.append(name)
        units[name] = unit or ""
    columns = [[row[i] for row in body] for i in range(len(header))]
    typed = [_typed(name, cells) for name, cells in zip(names, columns)]
    dtype = np.dtype({"names": names, "formats": [a.dtype for a in typed]}, metadata={"units": units})
    table = np.empty(len(body), dtype=dtype)
    for name, a in zip(names, typed):
        table[name] = a
    return table, units


def _typed(name, cells):
    if name == "seed":
        return np.array([int(c) for c in cells], dtype=np.uint64)
    if name in ("outcome", "why", "command"):
        return np.array(cells, dtype=str) if cells else np.array([], dtype="U1")
    if cells and all(_INT.match(c) for c in cells):
        values = [int(c) for c in cells]
        if all(-2**63 <= v < 2**63 for v in values):
            return np.array(values, dtype=np.int64)
        if all(0 <= v < 2**64 for v in values):
            return np.array(values, dtype=np.uint64)
    if cells and all(c in ("true", "false") for c in cells):
        return np.array([c == "true" for c in cells], dtype=bool)
    try:
        return np.array([float(c) if c != "" else np.nan for c in cells], dtype=np.float64)
    except ValueError:
        return np.array(cells, dtype=str) if cells else np.array([], dtype="U1")
