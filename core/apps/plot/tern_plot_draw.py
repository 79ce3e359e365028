"""tern plot: what every figure is drawn with: the colours (truth, estimate, command, instances,
runs), an estimate drawn only where its state is valid, a time figure made and finished (phase
bands, markers, legends: tern_plot_layout.py), a figure saved and recorded for index.html and
figures.json, and long time series decimated to what the figure's pixels show."""

import math
import os
import warnings

import numpy as np
import matplotlib.pyplot as plt

from tern_plot_angles import break_wraps
from tern_plot_layout import lay_out_time_figure, new_time_figure, top_view
from tern_plot_usage import fail

C_TRUE, C_EST, C_CMD, C_GNSS = "black", "#1f77b4", "#d62728", "#7f7f7f"
INSTANCE_COLOURS = [C_EST, "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#e377c2", "#17becf"]
GNSS_COLOURS = ["#7f7f7f", "#bcbd22", "#17becf"]  # raw fix n, e, h: apart from the instances' colours
RUN_COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b", "#17becf"]


def estimate_mask(state):
    """Estimate columns with NaN where the state is not valid."""
    valid = state.get("valid")
    return (valid < 0.5) if valid is not None else np.zeros(len(state), dtype=bool)


def est(state, field):
    v = state.get(field)
    if v is None:
        return None
    v = v.copy()
    v[estimate_mask(state)] = np.nan
    return v


def new_figure(rows, title, runs, row_height=2.6):
    """A figure of `rows` panels over the flight time (tern_plot_layout.py)."""
    return new_time_figure(plt, rows, title, runs, row_height)


def finish(fig, axes, runs, out, fname, caption, xlim=None):
    """Bands (one run), markers (those within xlim, default the whole flight), legends
    (tern_plot_layout.py); saves out["dir"]/fname and records the figure (file, caption, markers
    drawn, legend texts) for index.html and figures.json."""
    xlim = xlim or (0.0, max(r["t_end"] for r in runs))
    markers, legend = lay_out_time_figure(fig, axes, runs, xlim)
    save(fig, out, fname, caption, markers, legend)


def save(fig, out, fname, caption, markers=(), legend=()):
    path = os.path.join(out["dir"], fname)
    try:
        fig.savefig(path, dpi=110)
    except OSError as e:
        fail(f"{path}: cannot write ({e.strerror})")
    plt.close(fig)
    out["written"].append(path)
    out["figures"].append({"file": fname, "caption": caption, "markers": list(markers), "legend": list(legend)})


MAX_POINTS = 4000  # per time-series line: ~3 per pixel column of an 11 in, 110 dpi figure


def decimate(t, v, max_points=MAX_POINTS):
    """Keeps each bin's minimum and maximum (in time order): the drawn envelope, spikes
    included, is that of the full series. NaN gaps survive where a whole bin is NaN."""
    n = len(v)
    if n <= max_points:
        return t, v
    k = int(math.ceil(n / (max_points // 2)))
    m = n // k * k
    vb = v[:m].reshape(-1, k)
    nan = np.isnan(vb)
    imin = np.where(nan, np.inf, vb).argmin(axis=1)
    imax = np.where(nan, -np.inf, vb).argmax(axis=1)
    base = np.arange(vb.shape[0]) * k
    idx = np.column_stack([base + np.minimum(imin, imax), base + np.maximum(imin, imax)]).ravel()
    idx = np.unique(np.concatenate([idx, np.arange(m, n)]))  # sorted; a bin's min = max once
    return t[idx], v[idx]


def decimate_max(t, v, max_points=MAX_POINTS // 2):
    """Each bin's largest value at the bin's first time (a band's outline, never narrower)."""
    n = len(v)
    if n <= max_points:
        return t, v
    k = int(math.ceil(n / max_points))
    m = n // k * k
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        vb = np.nanmax(v[:m].reshape(-1, k), axis=1)
    return np.concatenate([t[:m:k], t[m:]]), np.concatenate([vb, v[m:]])


def steps(t, v):
    """The samples of a piecewise-constant series where it changes (and its ends): drawn with
    drawstyle steps-post, the same line from a few points (NaN runs stay gaps)."""
    if len(v) < 3:
        return t, v
    same = (v[1:] == v[:-1]) | (np.isnan(v[1:]) & np.isnan(v[:-1]))
    keep = np.concatenate([[True], ~same]) | (np.arange(len(v)) == len(v) - 1)
    return t[keep], v[keep]


def plot_ts(ax, t, v, **kw):
    td, vd = decimate(t, v)
    return ax.plot(td, vd, **kw)


def plot_angle(ax, t, deg, **kw):
    """An angle wrapped into [-180, 180) deg: decimated, then the line broken at each wrap."""
    return ax.plot(*break_wraps(*decimate(t, deg)), **kw)


def figure_helpers():
    """The drawing functions the figure classes of tern_plot_landing.py, tern_plot_reference.py and
    tern_plot_fleet.py are given (each adds what else it needs)."""
    return {"new_figure": new_figure, "finish": finish, "save": save, "plot_ts": plot_ts, "plt": plt, "top_view": top_view}
