"""tern.flight_env: FlightEnv, the learning environment on tern's Host, and its default task (the
roll loop). Its contract is tern.env's docstring; use it as tern.env.FlightEnv."""

import os
from pathlib import Path
import shutil
import tempfile

import numpy as np

from tern import Host, default_config
from tern._tern import Error
from tern.spaces import box

LEARN_CONFIG = Path(default_config()).parent / "learn.yaml"
ROLL_OBSERVATION = (("state", "phi"), ("state", "p"), ("controller_internals", "phi_c"))


def roll_reward(obs, action):
    """The default task's reward: -(phi_c - phi)^2 - 0.05 p^2."""
    return -float(obs[0] ** 2 + 0.05 * obs[1] ** 2)


class FlightEnv:
    """See tern.env's docstring. Arguments:

    config              mission config (default learn.yaml)
    action_topic        the module output the action replaces ("actuators", "controller_command")
    action_fields       its fields, in the action vector's order; action_low/high their bounds
    observation         (topic, field) pairs: [("state", "phi"), ("truth", "phi"), ...]; a pair
                        ("controller_internals", "phi_c") reads another module's output
    observe             optional: f(values) -> obs vector, values the observation pairs' numbers
                        (with ROLL_OBSERVATION, the default task's [phi_c - phi, p, phi_c])
    reward              f(obs, action) -> float
    terminate           optional: f(obs) -> bool (the episode ends terminated)
    control_rate_hz     steps per second of flight time (100: 4 ticks of a 400-Hz host)
    episode_s, start_s  episode length after the start, and the modules' own flight before it (s)
    set                 {"instance.param": value} for every episode (reset's options add to it)
    log_level           the episodes' flight logs ("summary": summary.json only); keep_logs keeps them
    """

    metadata = {"render_modes": []}
    render_mode = None

    def __init__(self, config=None, *, action_topic="actuators", action_fields=("delta_a",), action_low=(-0.6,), action_high=(0.6,),
                 observation=ROLL_OBSERVATION, observe=None,
                 reward=roll_reward, terminate=None, control_rate_hz=100.0, episode_s=10.0, start_s=5.0, set=None,
                 log_level="summary", log_dir=None, keep_logs=False):
        self.config = str(config or LEARN_CONFIG)
        self.action_topic = action_topic
        self.action_fields = tuple(action_fields)
        self.observation = tuple((t, f) for t, f in observation)
        if observe is None and self.observation == ROLL_OBSERVATION:
            observe = _roll_observation  # the default task's [phi_c - phi, p, phi_c]
        self._observe_fn = observe
        self._reward = reward
        self._terminate = terminate
        self.control_rate_hz = float(control_rate_hz)
        self.episode_s = float(episode_s)
        self.start_s = float(start_s)
        self._set = dict(set or {})
        self._log_level = log_level
        self._keep_logs = keep_logs
        self._log_dir = Path(log_dir) if log_dir else Path(tempfile.mkdtemp(prefix="tern-env-", dir=_scratch_parent(keep_logs)))
        self._own_log_dir = log_dir is None
        if len(action_low) != len(self.action_fields) or len(action_high) != len(self.action_fields):
            raise Error(f"FlightEnv: {len(self.action_fields)} action fields, {len(action_low)} low and {len(action_high)} high bounds")
        self.action_space = box(action_low, action_high)
        self._host = None
        self._host_config = None
        self._flying = False  # an episode's flight is open (its log not yet discarded)
        self._rng = np.random.default_rng()
        self._build(self.config, self._set, None)
        n = len(self._observe(self._zero_values()))
        self.observation_space = box(np.full(n, -np.inf), np.full(n, np.inf))

    # ---- Gymnasium's contract ---------------------------------------------------------------

    def reset(self, *, seed=None, options=None):
        """Starts an episode: (obs, info). seed: the flight's seed (else one drawn from the
        environment's generator, seeded by the first seed given); options: {"set": {...},
        "config": FILE} for this episode."""
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        flight_seed = int(seed) if seed is not None else int(self._rng.integers(1, 2**63 - 1))
        options = options or {}
        self._build(str(options.get("config", self.config)), {**self._set, **options.get("set", {})}, flight_seed)
        self._discard_log()
        self._host.release(self.action_topic)
        self._host.reset(flight_seed)
        self._flying = True
        self._host.step_until(self.start_s)
        self._handovers = self._host.handover_count
        self._end_t = self._host.time + self.episode_s
        obs = self._observe(self._values())
        return obs, {"t": self._host.time, "seed": flight_seed}

    def step(self, action):
        """Holds `action` on the action topic and flies one control period: (obs, reward,
        terminated, truncated, info). action None: the module's own output flies this step."""
        if self._host is None or not hasattr(self, "_end_t"):
            raise Error("FlightEnv.step: call reset() first")
        a = None
        if action is not None:
            a = np.asarray(action, dtype=np.float64)
            if a.shape != self.action_space.shape:
                raise Error(f"FlightEnv.step: action of shape {a.shape}, the action space's is {self.action_space.shape} "
                            f"({', '.join(self.action_fields)} of '{self.action_topic}')")
            a = np.minimum(np.maximum(a, self.action_space.low), self.action_space.high)  # np.clip costs more
        # write (None: release), step and read in one call (tern.Control)
        going, values = self._control(a, self._ticks)
        obs = self._observe(values)
        reward = self._reward(obs, a if a is not None else np.zeros(self.action_space.shape))
        safety = self._host.handover_count > self._handovers
        ended = not going and self._host.end_reason not in ("duration", "aborted")
        terminated = bool(ended or safety or (self._terminate is not None and self._terminate(obs)))
        truncated = bool(not terminated and (self._host.time >= self._end_t - 1e-9 or not going))
        info = {"t": self._host.time}
        if ended:
            info["end_reason"] = self._host.end_reason
        if safety:
            info["handover"] = self._host.handovers[-1]
        return obs, reward, terminated, truncated, info

    def close(self):
        if self._host is not None:
            self._discard_log()
            self._host = None
        if self._own_log_dir and not self._keep_logs:
            shutil.rmtree(self._log_dir, ignore_errors=True)

    @property
    def host(self):
        """The tern.Host flying the episodes (read other topics, change parameters)."""
        return self._host

    # ---- inside ----------------------------------------------------------------------------

    def _build(self, config, sets, seed):
        """The host for an episode of `config` with the parameter values `sets`: the one flying
        when only values differ (changed between flights, Host.set_param), else a new one."""
        if self._host is not None and config == self._host_config and self._retune(sets):
            return
        if self._host is not None:
            self._discard_log()
        self._host = Host(config, seed=seed, set=sets, log_dir=self._log_dir, log_level=self._log_level)
        self._host_config = config
        self._control = self._host.control(self.action_topic, list(self.action_fields), list(self.observation))
        self._built_sets = dict(sets)  # their values without the set are not known here
        self._host_sets = dict(sets)   # the values in force
        self._config_values = {}       # a parameter's value before the first set that changed it
        ticks = 1.0 / (self.control_rate_hz * self._host.base_period)
        if abs(ticks - round(ticks)) > 1e-9 or round(ticks) < 1:
            raise Error(f"FlightEnv: control_rate_hz {self.control_rate_hz} is not the host's base rate "
                        f"({1.0 / self._host.base_period:g} Hz) divided by a whole number")
        self._ticks = int(round(ticks))

    def _retune(self, sets):
        """Moves the flying host's parameters from the values in force to `sets`, between flights
        (a plugin reads a parameter live or at start(): tern/param.hpp); False, nothing changed,
        when one set at the build would go back to the config's value, which only a new host knows."""
        if any(n not in sets and n in self._built_sets for n in self._host_sets):
            return False
        changes = {n: self._config_values[n] for n in self._host_sets if n not in sets}
        changes.update({n: v for n, v in sets.items() if n not in self._host_sets or repr(self._host_sets[n]) != repr(v)})
        if not changes:
            return True
        self._discard_log()  # the last episode's flight ends first
        try:
            for name, value in changes.items():
                if name not in self._built_sets and name not in self._config_values:
                    self._config_values[name] = self._host.get_param(name)
                self._host.set_param(name, value)
        except Error:
            self._host_config = None  # half changed: the next episode builds anew
            raise
        self._host_sets = dict(sets)
        return True

    def _discard_log(self):
        """Ends the episode's flight, if one is open, and removes its log (unless keep_logs)."""
        if not self._flying:
            return
        self._flying = False
        run = self._host.end()
        if run is not None and not self._keep_logs:
            shutil.rmtree(run.dir, ignore_errors=True)

    def _values(self):
        return self._control.read()  # tern.Error names a topic or field it lacks

    def _zero_values(self):
        self._values()
        return np.zeros(len(self.observation))

    def _observe(self, values):
        return np.asarray(self._observe_fn(values) if self._observe_fn else values, dtype=np.float64)


def _scratch_parent(keep_logs):
    """Where the environment's own log directory goes: Linux's shared memory (/dev/shm, a tmpfs)
    when each episode's log is removed at its end (keep_logs False), so that the episodes' files
    cost no disk writes (a reset 0.5 ms quicker on ext4); else the system's temporary directory."""
    shm = "/dev/shm"
    return shm if not keep_logs and os.path.isdir(shm) and os.access(shm, os.W_OK) else None


def _roll_observation(values):
    values[0] = values[2] - values[0]  # [phi, p, phi_c] -> [phi_c - phi, p, phi_c]
    return values
