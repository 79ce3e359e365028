"""tern plot: how a figure is laid out so that no text hides another or the data. Time figures
(one panel per quantity over the flight time): the title on its own line at the top; each
panel's legend in a strip above the panel, outside the data; the flight phases as shaded bands,
their legend below the time axis; the markers (phase changes, handovers, fallbacks, failsafes)
as vertical lines, labelled along the top panel's top edge, the labels of markers closer than a
label's width drawn as one. Figures seen from above: the legend below the axes. Matplotlib's
constrained layout places it all (margins from the texts' sizes)."""

from matplotlib.legend import Legend
from matplotlib.patches import Patch

from tern_plot_log import MARKER_STYLE

# a phase's band colour, by the name definitions.json gives its code (a phase not here: grey)
PHASE_COLOURS = {"takeoff": "#ff7f0e", "climb": "#2ca02c", "cruise": "#1f77b4", "landing": "#9467bd",
                 "loiter": "#7f7f7f", "preflight": "#8c564b", "approach": "#e377c2", "flare": "#17becf",
                 "rollout": "#bcbd22", "stopped": "#393b79"}
NO_COLOUR = "#bbbbbb"
WIDTH_IN = 11.0                  # a time figure's width
LEGEND_CHARS_PER_ROW = 140       # legend text that fits one row of a time figure's width (small font)
MARKER_LABEL_PX = 13             # markers closer than this (pixels) share one label
DPI = 110                        # tern plot's PNGs (save)
MARKER_CHAR_PX = 6.0             # a marker label's character (x-small) along the line, pixels
LEGEND_ROW_IN = 0.22             # a legend row above a panel (small), inches


# ----------------------------------------------------------------------------------------------
# Phases
# ----------------------------------------------------------------------------------------------

def phase_bands(phase, t_end, names):
    """[(t0, t1, name)] from flight_phase rows; names: definitions.json's phase codes -> names
    (a code it lacks: "phase N")."""
    if phase is None or phase.get("phase") is None:
        return []
    t = phase.get("t")
    p = [names.get(int(c), f"phase {int(c)}") for c in phase.get("phase")]
    bands = []
    for k in range(len(t)):
        t1 = t[k + 1] if k + 1 < len(t) else max(t_end, t[k])
        if bands and bands[-1][2] == p[k]:
            bands[-1] = (bands[-1][0], t1, p[k])
        elif t1 > t[k] or k + 1 == len(t):
            bands.append((t[k], t1, p[k]))
    return bands


def phase_label(name, bands):
    if name == "preflight":  # how long the calibration, alignment and arming checks took
        return name + " ({:.1f} s)".format(sum(t1 - t0 for t0, t1, q in bands if q == name))
    return name


def draw_bands(axes, bands):
    """Each phase's band on every panel; the phases' legend in one row below the time axis."""
    if not bands:
        return
    for ax in axes:
        for t0, t1, p in bands:
            ax.axvspan(t0, t1, color=PHASE_COLOURS.get(p, NO_COLOUR), alpha=0.10, lw=0, zorder=0)
    seen = []
    for _, _, p in bands:
        if p not in seen:
            seen.append(p)
    handles = [Patch(color=PHASE_COLOURS.get(p, NO_COLOUR), alpha=0.25, label=phase_label(p, bands)) for p in seen]
    # below the tick labels and the axis label of the bottom panel (borderaxespad: in font sizes)
    # a Legend of its own (ax.legend() is the panel's, made later), not clipped: in the layout
    legend = Legend(axes[-1], handles, [h.get_label() for h in handles], loc="upper center", bbox_to_anchor=(0.5, 0.0),
                    ncol=len(handles), fontsize="small", frameon=False, title="phase", title_fontsize="small",
                    borderaxespad=3.6, handlelength=1.5, columnspacing=1.2)
    legend.set_clip_on(False)
    axes[-1].add_artist(legend)


# ----------------------------------------------------------------------------------------------
# Time figures
# ----------------------------------------------------------------------------------------------

def new_time_figure(plt, rows, title, runs, row_height=2.6):
    """A figure of `rows` panels over time (shared t axis), its title at the top left."""
    fig, axes = plt.subplots(rows, 1, figsize=(WIDTH_IN, 1.9 + row_height * rows), sharex=True, squeeze=False,
                             layout="constrained")
    axes = list(axes[:, 0])
    fig.suptitle(f"{title} - {' vs '.join(r['label'] for r in runs)}", x=0.01, ha="left", fontsize="medium")
    axes[-1].set_xlabel("t [s]")
    for ax in axes:
        ax.grid(True, lw=0.4, alpha=0.6)
        ax.ticklabel_format(axis="y", useOffset=False)  # no "1e-9+3e1" above the panel, where its legend goes
    return fig, axes


def marker_groups(markers, xlim, width_px):
    """[[marker ...] ...]: markers (t first) in time order, those closer to the group's first than
    MARKER_LABEL_PX pixels of an axis width_px wide over xlim in one group (one label)."""
    gap = MARKER_LABEL_PX * (xlim[1] - xlim[0]) / max(width_px, 1.0)
    groups = []
    for m in sorted(markers, key=lambda m: m[0]):
        if groups and m[0] - groups[-1][0][0] < gap:
            groups[-1].append(m)
        else:
            groups.append([m])
    return groups


def group_text(texts, max_chars):
    """One label of a group's texts ("a / b", each once), cut to max_chars ("..." at the end)."""
    text = " / ".join(dict.fromkeys(texts))
    return text if len(text) <= max_chars else text[:max(1, max_chars - 3)].rstrip() + "..."


def run_markers(runs, xlim):
    """[(t, label, text, colour, ls)] of every run's markers within xlim: label as recorded (an
    overlay's names its run), text as drawn (the run shown by the colour); a marker every run has
    at the same time once, in its kind's style."""
    shared = set.intersection(*[{(round(t, 2), label) for t, label, _ in r["markers"]} for r in runs])
    out = []
    for k_run, run in enumerate(runs):
        for t, label, kind in run["markers"]:
            if not xlim[0] <= t <= xlim[1]:
                continue
            colour, ls = MARKER_STYLE[kind]
            text = label
            if run["overlay"] and (round(t, 2), label) in shared:
                if k_run > 0:
                    continue
            elif run["overlay"]:
                colour, label = run["colour"], f"{run['label']}: {label}"
            out.append((t, label, text, colour, ls))
    return out


def draw_markers(axes, runs, xlim):
    """Every run's markers (flight_markers, within xlim) on every panel: a vertical line styled by
    kind (several runs: in the run's colour). Labelled along the top panel's top edge: markers
    nearer than a label's width under one label ("a / b"), cut to the panel's height, left out
    of the layout. Returns the markers' labels (an overlay's with the run's name)."""
    shown = run_markers(runs, xlim)
    for ax in axes:
        for t, _, _, colour, ls in shown:
            ax.axvline(t, color=colour, ls=ls, lw=0.9, zorder=5)
    fig = axes[0].figure
    pos = axes[0].get_position()
    max_chars = int(pos.height * fig.get_figheight() * DPI / MARKER_CHAR_PX)
    for group in marker_groups(shown, xlim, pos.width * fig.get_figwidth() * DPI):
        colours = {m[3] for m in group}
        text = group_text([m[2] for m in group], max_chars)
        note = axes[0].annotate(text, (group[0][0], 1.0), xycoords=("data", "axes fraction"), xytext=(2, -3),
                                textcoords="offset points", rotation=90, va="top", fontsize="x-small",
                                color=colours.pop() if len(colours) == 1 else "#333333", zorder=7, clip_on=True,
                                bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.55))
        note.set_in_layout(False)
    return [m[1] for m in shown]


def legend_columns(lengths, limit=LEGEND_CHARS_PER_ROW):
    """The most columns whose widths add up to at most `limit` characters (at least 1): matplotlib
    fills a legend column by column, the first len % ncol columns one entry longer, each column
    as wide as its longest text plus its handle."""
    for ncol in range(len(lengths), 1, -1):
        rows, longer = divmod(len(lengths), ncol)
        sizes = [rows + 1] * longer + [rows] * (ncol - longer)
        starts = [sum(sizes[:c]) for c in range(ncol)]
        if sum(max(lengths[a:a + n]) + 6 for a, n in zip(starts, sizes)) <= limit:
            return ncol
    return 1


def legend_above(ax):
    """The panel's legend in a strip above it (outside the data), as many columns as fit the
    width; returns
    (its texts, its rows) (([], 0) without one)."""
    handles, labels = ax.get_legend_handles_labels()
    if not handles:
        return [], 0
    ncol = legend_columns([len(s) for s in labels])
    ax.legend(handles, labels, loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=ncol, fontsize="small", frameon=False,
              borderaxespad=0.2, handlelength=1.8, columnspacing=1.5)
    return labels, -(-len(labels) // ncol)


def lay_out_time_figure(fig, axes, runs, xlim):
    """Bands (one run), markers, legends of a time figure over xlim; the figure taller by its
    legends' rows (the panels keep their height). Returns (marker labels, legend texts)."""
    axes[-1].set_xlim(*xlim)
    if len(runs) == 1:
        draw_bands(axes, runs[0]["bands"])
    markers = draw_markers(axes, runs, xlim)
    legend, rows = [], 0
    for ax in axes:
        texts, n = legend_above(ax)
        legend += texts
        rows += n
    fig.set_figheight(fig.get_figheight() + LEGEND_ROW_IN * rows)
    return markers, legend


# ----------------------------------------------------------------------------------------------
# Figures seen from above
# ----------------------------------------------------------------------------------------------

def top_view(fig, ax):
    """A figure seen from above (north up, east on x, equal axes): axis labels, grid, the legend
    below the axes (outside the tracks), constrained layout."""
    ax.set_xlabel("east [m]")
    ax.set_ylabel("north [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.grid(True, lw=0.4, alpha=0.6)
    handles, labels = ax.get_legend_handles_labels()
    if handles:
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.055), ncol=2, fontsize="small", frameon=False)
    fig.set_layout_engine("constrained")
