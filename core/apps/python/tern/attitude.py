"""tern.attitude: an estimate's attitude against the truth, from a run's arrays (numpy only).

    yaw, tilt = tern.attitude.errors(run["state"], run["truth"])
    roll, pitch = tern.attitude.roll_pitch_errors(run["state"], run["truth"])

The error rotation between the estimated and the true attitude, R_est R_true^T (earth frame, NED),
split into its rotation about the vertical (yaw, deg, signed: the estimate's heading minus the
truth's) and the angle it tilts the vertical (tilt, deg, >= 0). Both stay defined through a loop's
vertical, where Euler angles do not (the yaw of a loop's top is not the heading's). The roll and
pitch errors are that error's rotation about the true body's x and y axes (the rotation vector of
R_true^T R_est, small-angle), defined through a loop as the tilt is.
"""
import numpy as np


def rotation(w, x, y, z):
    """Body-to-NED rotation matrices of unit quaternions (arrays of n), shape (n, 3, 3)."""
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


def _paired(state, truth, airborne_m, after_s):
    """(R_est, R_true), body-to-NED, of the ticks both logged (same stamp), airborne, after after_s."""
    idx = np.searchsorted(truth["stamp"], state["stamp"]).clip(0, len(truth) - 1)
    same = truth["stamp"][idx] == state["stamp"]
    s, t = state[same], truth[idx[same]]
    keep = (-t["p_d"] > airborne_m) & (t["t"] > after_s)
    s, t = s[keep], t[keep]
    return (rotation(s["quat_w"], s["quat_x"], s["quat_y"], s["quat_z"]),
            rotation(t["quat_w"], t["quat_x"], t["quat_y"], t["quat_z"]))


def roll_pitch_errors(state, truth, airborne_m=5.0, after_s=30.0):
    """(roll, pitch) errors in deg, signed, on the ticks errors() takes: the rotation from the true
    to the estimated attitude about the true body's x and y axes."""
    R_est, R_true = _paired(state, truth, airborne_m, after_s)
    B = np.transpose(R_true, (0, 2, 1)) @ R_est
    return np.degrees(0.5 * (B[:, 2, 1] - B[:, 1, 2])), np.degrees(0.5 * (B[:, 0, 2] - B[:, 2, 0]))


def errors(state, truth, airborne_m=5.0, after_s=30.0):
    """(yaw, tilt) errors in deg, one per tick that both `state` and `truth` logged (same stamp),
    where the truth is more than `airborne_m` up and the flight time is past `after_s`."""
    R_est, R_true = _paired(state, truth, airborne_m, after_s)
    E = R_est @ np.transpose(R_true, (0, 2, 1))
    yaw = np.degrees(np.arctan2(E[:, 1, 0] - E[:, 0, 1], E[:, 0, 0] + E[:, 1, 1]))
    tilt = np.degrees(np.arccos(np.clip(E[:, 2, 2], -1.0, 1.0)))
    return yaw, tilt
