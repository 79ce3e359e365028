"""tern.spaces: the spaces of tern's learning environments (tern.env, tern.vector_env), after
Gymnasium's spaces.Box contract: Gymnasium's own Box when Gymnasium is importable, else Box below,
which needs only numpy."""

import numpy as np

from tern._tern import Error

try:  # the environments need only numpy; Gymnasium's spaces when it is there
    import gymnasium
except ImportError:
    gymnasium = None


class Box:
    """A box in R^n: shape, low, high, dtype (Gymnasium's spaces.Box contract, as plain attributes)."""

    def __init__(self, low, high, dtype=np.float64):
        self.low = np.asarray(low, dtype=dtype)
        self.high = np.asarray(high, dtype=dtype)
        if self.low.shape != self.high.shape:
            raise Error(f"Box: low {self.low.shape} and high {self.high.shape} differ in shape")
        self.shape = self.low.shape
        self.dtype = np.dtype(dtype)
        self._rng = np.random.default_rng()

    def seed(self, seed=None):
        self._rng = np.random.default_rng(seed)

    def sample(self):
        lo = np.where(np.isfinite(self.low), self.low, -1.0)
        hi = np.where(np.isfinite(self.high), self.high, 1.0)
        return self._rng.uniform(lo, hi).astype(self.dtype)

    def contains(self, x):
        x = np.asarray(x)
        return x.shape == self.shape and bool(np.all(x >= self.low) and np.all(x <= self.high))

    def __repr__(self):
        return f"Box({self.low.tolist()}, {self.high.tolist()}, {self.shape}, {self.dtype})"


def box(low, high):
    """A float64 box: Gymnasium's spaces.Box when Gymnasium is there, else a Box."""
    if gymnasium is not None:
        return gymnasium.spaces.Box(np.asarray(low, np.float64), np.asarray(high, np.float64), dtype=np.float64)
    return Box(low, high)


def batch(space, n):
    """The space of num_envs rows of `space` (Gymnasium's batch_space for a Box)."""
    low = np.broadcast_to(space.low, (n,) + space.shape)
    high = np.broadcast_to(space.high, (n,) + space.shape)
    return box(np.array(low), np.array(high))
