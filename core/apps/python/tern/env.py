"""tern.env: a learning environment on tern's Host, after Gymnasium's API contract, without
needing Gymnasium (registered with it as "tern/Flight-v0" when it is importable).

    env = tern.env.FlightEnv()                 # the roll loop's task, below
    obs, info = env.reset(seed=1)
    obs, reward, terminated, truncated, info = env.step(env.action_space.sample())

Every step holds the action on a module's output (Host.write: fields of `action_topic` replaced
after each step of the module that publishes it, e.g. the controller's `actuators`, or a loop's
command on `controller_command`) and flies `ticks_per_step` ticks of the host's base rate (100-Hz
control on a 400-Hz host: 4 simulator and estimator ticks). The observation is a vector of
(topic, field) pairs read after the step: the estimator's `state` by default, or the simulator's
`truth` by choice. An episode ends `terminated` when the flight ends for a reason other than its
duration (a crash, a plugin's failure, a failsafe's termination), when the safety net hands the
controls over (a controller handover after the start), or when `terminate(obs)` says so; it ends
`truncated` after `episode_s`. Before the first observation the mission's own modules fly for
`start_s` (the action is not held): the episode starts from the flight as it is then.

tern.env.VectorFlightEnv (tern.vector_env) steps several of them at once, after Gymnasium's
vector API. FlightEnv is written in tern/flight_env.py, its spaces in tern/spaces.py; this module
gathers them (and registers them with Gymnasium).

Per episode, reset(seed=, options={"set": {...}, "config": FILE}) chooses the seed (sensor
noise, turbulence), parameter overrides (wind: {"sim.wind": [vn, ve, vd]}, sensors:
{"sim.sensor_profile": "ideal"}, gains) and the mission. A new config builds the host anew; a new
seed or new override values reset it as `tern serve`'s flights are (its libraries, instances and
port graph stay; the values are set between flights as Host.set_param sets them: a flight the
same as a fresh host's with those values), unless an override given at construction is dropped
(its value without it is the config's, which only a new host knows).

The default task (learn.yaml: the Anaconda released at trim at 100 m, flying the hourglass) is
the roll loop: the action is the aileron (delta_a, rad), the observation [phi_c - phi, p, phi_c]
(rad, rad/s, rad) with phi_c the controller's own roll command from its course loop
(controller_internals), the reward -(phi_c - phi)^2 - 0.05 p^2 per step.
"""

from tern.flight_env import LEARN_CONFIG, ROLL_OBSERVATION, FlightEnv, roll_reward
from tern.spaces import Box, gymnasium as _gymnasium
from tern.vector_env import VectorFlightEnv

__all__ = ["Box", "FlightEnv", "LEARN_CONFIG", "ROLL_OBSERVATION", "VectorFlightEnv", "roll_reward"]

if _gymnasium is not None:
    try:  # gymnasium.make_vec("tern/Flight-v0", num_envs=4, vectorization_mode="vector_entry_point"): VectorFlightEnv
        _gymnasium.register(id="tern/Flight-v0", entry_point="tern.env:FlightEnv", vector_entry_point="tern.vector_env:VectorFlightEnv")
    except TypeError:  # a Gymnasium without vector entry points
        _gymnasium.register(id="tern/Flight-v0", entry_point="tern.env:FlightEnv")
    except _gymnasium.error.Error:  # registered already (a reload)
        pass
