"""tern.vector_env: several tern.env.FlightEnv stepped together in one process, after Gymnasium's
vector API contract (gymnasium.vector.SyncVectorEnv), without needing Gymnasium.

    venv = tern.vector_env.VectorFlightEnv(4, episode_s=5.0)    # 4 FlightEnv, 4 Hosts
    obs, infos = venv.reset(seed=1)                              # obs[4, 3]; sub-env i seeded 1 + i
    obs, rewards, terminated, truncated, infos = venv.step(actions)   # actions[4, 1]

Each sub-environment is a FlightEnv with its own tern.Host (its own plugins, simulator and log),
stepped one after another in this thread: the same episodes as num_envs FlightEnv stepped alone,
bit for bit. The observations, rewards, terminated and truncated flags are numpy arrays of
num_envs rows; `infos` is Gymnasium's vector form: for every key a sub-environment's info had,
an array of num_envs values and a boolean mask `"_" + key` saying which sub-environments set it.

A sub-environment whose episode ended (terminated or truncated) is reset by the vector env, as
Gymnasium's vector API does, in one of its autoreset modes:
    "next_step" (Gymnasium 1.x's default): the step after the one that ended it resets it instead
                of stepping it (its action is ignored; its reward 0, terminated and truncated
                False, its obs the new episode's first);
    "same_step": the step that ended it resets it at once; its obs is the new episode's first and
                infos["final_obs"], infos["final_info"] (masked) hold the ended episode's last.
An autoreset draws the sub-environment's next flight seed from its own generator (seeded by the
first reset's seed), without options: the same seeds give the same sequence of episodes.
"""

import numpy as np

from tern._tern import Error
from tern.flight_env import FlightEnv
from tern.spaces import batch

AUTORESET_MODES = ("next_step", "same_step")


class VectorFlightEnv:
    """See the module's docstring. Arguments:

    num_envs        how many FlightEnv (each its own Host)
    env_fns         instead: a list of functions each returning an environment (FlightEnv or any
                    with its contract and equal spaces), as SyncVectorEnv takes
    autoreset_mode  "next_step" (default) or "same_step"
    **kwargs        FlightEnv's arguments, the same for every sub-environment
    """

    metadata = {"render_modes": [], "autoreset_mode": "next_step"}
    render_mode = None

    def __init__(self, num_envs=None, env_fns=None, *, autoreset_mode="next_step", **kwargs):
        if autoreset_mode not in AUTORESET_MODES:
            raise Error(f"VectorFlightEnv: autoreset_mode '{autoreset_mode}': one of {', '.join(AUTORESET_MODES)}")
        if env_fns is not None:
            if kwargs:
                raise Error(f"VectorFlightEnv: env_fns builds the environments; FlightEnv arguments {sorted(kwargs)} too")
            env_fns = list(env_fns)
            if num_envs is not None and num_envs != len(env_fns):
                raise Error(f"VectorFlightEnv: num_envs {num_envs} and {len(env_fns)} env_fns")
            num_envs = len(env_fns)
        elif num_envs is None:
            raise Error("VectorFlightEnv: give num_envs (with FlightEnv's arguments) or env_fns")
        if not isinstance(num_envs, (int, np.integer)) or num_envs < 1:
            raise Error(f"VectorFlightEnv: num_envs {num_envs!r}: a whole number of at least 1")
        self.autoreset_mode = autoreset_mode
        self.metadata = {**self.metadata, "autoreset_mode": autoreset_mode}
        self.envs = []
        try:
            for i in range(num_envs):
                self.envs.append(env_fns[i]() if env_fns is not None else FlightEnv(**kwargs))
        except BaseException:
            self.close()
            raise
        self.num_envs = len(self.envs)
        first = self.envs[0]
        for i, e in enumerate(self.envs[1:], 1):
            for name in ("observation_space", "action_space"):
                a, b = getattr(first, name), getattr(e, name)
                if a.shape != b.shape or not (np.array_equal(a.low, b.low) and np.array_equal(a.high, b.high)):
                    self.close()
                    raise Error(f"VectorFlightEnv: sub-environment {i}'s {name} {b} differs from sub-environment 0's {a}")
        self.single_observation_space = first.observation_space
        self.single_action_space = first.action_space
        self.observation_space = batch(first.observation_space, self.num_envs)
        self.action_space = batch(first.action_space, self.num_envs)
        self._obs = np.zeros(self.observation_space.shape, dtype=np.float64)
        self._autoreset = np.zeros(self.num_envs, dtype=bool)
        self._started = False

    # ---- Gymnasium's vector contract -------------------------------------------------------

    def reset(self, *, seed=None, options=None):
        """Resets every sub-environment: (obs[num_envs, ...], infos). seed: an int (sub-environment
        i gets seed + i, as Gymnasium's), a list of num_envs ints or Nones, or None; options:
        FlightEnv.reset's, given to every sub-environment."""
        if seed is None or isinstance(seed, (int, np.integer)):
            seeds = [None if seed is None else int(seed) + i for i in range(self.num_envs)]
        else:
            seeds = list(seed)
            if len(seeds) != self.num_envs:
                raise Error(f"VectorFlightEnv.reset: {len(seeds)} seeds for {self.num_envs} sub-environments")
        infos = {}
        for i, (env, s) in enumerate(zip(self.envs, seeds)):
            self._obs[i], info = env.reset(seed=s, options=options)
            _add_info(infos, info, i, self.num_envs)
        self._autoreset[:] = False
        self._started = True
        return self._obs.copy(), infos

    def step(self, actions):
        """Steps every sub-environment with its row of `actions` (shape (num_envs,) + the single
        action space's): (obs, rewards, terminated, truncated, infos), each with num_envs rows;
        finished sub-environments are reset as the autoreset mode says (module docstring)."""
        if not self._started:
            raise Error("VectorFlightEnv.step: call reset() first")
        a = np.asarray(actions, dtype=np.float64)
        if a.shape != self.action_space.shape:
            raise Error(f"VectorFlightEnv.step: actions of shape {a.shape}, the action space's is {self.action_space.shape} "
                        f"({self.num_envs} sub-environments x {self.single_action_space.shape})")
        n = self.num_envs
        rewards = np.zeros(n, dtype=np.float64)
        terminated = np.zeros(n, dtype=bool)
        truncated = np.zeros(n, dtype=bool)
        infos = {}
        for i, env in enumerate(self.envs):
            if self._autoreset[i]:  # next_step: this step starts its next episode
                self._obs[i], info = env.reset()
            else:
                self._obs[i], rewards[i], terminated[i], truncated[i], info = env.step(a[i])
                if self.autoreset_mode == "same_step" and (terminated[i] or truncated[i]):
                    _add_info(infos, {"final_obs": self._obs[i].copy(), "final_info": info}, i, n)
                    self._obs[i], info = env.reset()
            _add_info(infos, info, i, n)
        if self.autoreset_mode == "next_step":
            self._autoreset = terminated | truncated
        return self._obs.copy(), rewards, terminated, truncated, infos

    def close(self):
        for env in getattr(self, "envs", []):
            env.close()
        self.envs = []

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def __repr__(self):
        return f"VectorFlightEnv({self.num_envs}, autoreset_mode='{self.autoreset_mode}')"


def _add_info(infos, info, i, n):
    """Sub-environment i's info into the vector form (Gymnasium's VectorEnv._add_info): per key an
    array of n values (float, int, bool; object for anything else; a dict nests) and its mask."""
    for key, value in info.items():
        if isinstance(value, dict):
            inner = infos.get(key, {})
            _add_info(inner, value, i, n)
            infos[key] = inner
        else:
            if key not in infos:
                if isinstance(value, (bool, np.bool_)):
                    infos[key] = np.zeros(n, dtype=bool)
                elif isinstance(value, (int, np.integer)):
                    infos[key] = np.zeros(n, dtype=np.int64)
                elif isinstance(value, (float, np.floating)):
                    infos[key] = np.zeros(n, dtype=np.float64)
                else:
                    infos[key] = np.full(n, None, dtype=object)
            infos[key][i] = value
        mask = "_" + key
        if mask not in infos:
            infos[mask] = np.zeros(n, dtype=bool)
        infos[mask][i] = True
