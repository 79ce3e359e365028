"""tern plot: angles drawn wrapped. A heading, course or yaw is drawn in [-180, 180) deg, the line
broken (a NaN inserted) where it wraps, so that no vertical line crosses the axes at +-180 deg;
the differences of angles (an estimate minus the truth) are wrapped the same way."""

import math

import numpy as np

DEG = 180.0 / math.pi
CIRCLE_TICKS = (-180, -90, 0, 90, 180)
MIN_COURSE_VG = 1.0  # m/s: the course is drawn from this ground speed (at rest it is noise)


def wrap_pi(a):
    """An angle (rad) in [-pi, pi)."""
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def wrap_deg(a):
    """An angle (rad) in deg in [-180, 180)."""
    return wrap_pi(np.asarray(a, dtype=float)) * DEG


def break_wraps(t, deg, jump=180.0):
    """(t, deg) with a NaN inserted between two samples more than `jump` deg apart (a wrap at
    +-180 deg): a line drawn through them is broken there instead of crossing the axes."""
    t, deg = np.asarray(t, dtype=float), np.asarray(deg, dtype=float)
    with np.errstate(invalid="ignore"):
        at = np.nonzero(np.abs(np.diff(deg)) > jump)[0] + 1
    return np.insert(t, at, np.nan), np.insert(deg, at, np.nan)


def wrapped_deg(a):
    """An angle (rad) in deg in [-180, 180) with a NaN at each wrap, and the indices where the NaNs
    went in (to insert them into the times too)."""
    d = wrap_deg(a)
    with np.errstate(invalid="ignore"):
        at = np.nonzero(np.abs(np.diff(d)) > 180.0)[0] + 1
    return np.insert(d, at, np.nan), at


def circle_axis(ax):
    """A y axis of the whole circle: -180 to 180 deg, a tick every 90 deg."""
    ax.set_ylim(-185.0, 185.0)
    ax.set_yticks(CIRCLE_TICKS)


def course_where_moving(chi, vg, min_vg=MIN_COURSE_VG):
    """The course chi with NaN where the ground speed vg is below min_vg (vg None: chi as is)."""
    if vg is None:
        return chi
    with np.errstate(invalid="ignore"):
        return np.where(vg >= min_vg, chi, np.nan)
