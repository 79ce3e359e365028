"""tern.env.FlightEnv: Gymnasium's API contract (reset, step, spaces), the action held on the
module's output, determinism, the end of an episode (truncated, terminated) and bad actions."""
import numpy as np
import pytest

import tern
import tern.env


@pytest.fixture
def env():
    e = tern.env.FlightEnv(episode_s=2.0, start_s=1.0)
    yield e
    e.close()


def test_contract(env):
    assert env.action_space.shape == (1,) and env.action_space.low[0] == -0.6 and env.action_space.high[0] == 0.6
    assert env.observation_space.shape == (3,)
    obs, info = env.reset(seed=1)
    assert obs.shape == env.observation_space.shape and obs.dtype == np.float64
    assert info["t"] == pytest.approx(1.0) and info["seed"] == 1
    obs, reward, terminated, truncated, info = env.step(np.array([0.05]))
    assert obs.shape == (3,) and isinstance(reward, float) and reward <= 0.0
    assert terminated is False and truncated is False
    assert info["t"] == pytest.approx(1.01)  # 100-Hz control: 4 ticks of the 400-Hz host
    assert env.host.read("actuators")["delta_a"] == 0.05
    steps = 1
    while not truncated:
        obs, reward, terminated, truncated, info = env.step(env.action_space.sample())
        steps += 1
        assert not terminated
    assert steps == 200 and info["t"] == pytest.approx(3.0)


def rollout(env, seed, gains):
    obs, _ = env.reset(seed=seed)
    out = [obs]
    for _ in range(100):
        obs, *_ = env.step(np.array([gains @ obs[:2]]))
        out.append(obs)
    return np.array(out)


def test_same_seed_same_episode(env):
    gains = np.array([0.4, -0.05])
    a = rollout(env, 3, gains)
    b = rollout(env, 3, gains)
    c = rollout(env, 4, gains)
    assert a.tobytes() == b.tobytes()
    assert a.tobytes() != c.tobytes()


def test_safety_net_or_crash_terminates():
    env = tern.env.FlightEnv(action_fields=("delta_e",), action_low=(-0.6,), action_high=(0.6,), episode_s=30.0, start_s=1.0)
    env.reset(seed=1)
    for _ in range(3000):
        obs, reward, terminated, truncated, info = env.step(np.array([0.6]))  # full nose-down elevator
        if terminated or truncated:
            break
    env.close()
    assert terminated and not truncated
    assert "end_reason" in info or "handover" in info


def test_per_episode_options_and_bad_actions(env):
    env.reset(seed=2, options={"set": {"sim.wind": [0.0, 4.0, 0.0]}})
    assert env.host.get_param("sim.wind") == [0.0, 4.0, 0.0]
    with pytest.raises(tern.Error, match="shape"):
        env.step(np.zeros(2))
    with pytest.raises(tern.Error, match="no topic 'stat'"):
        tern.env.FlightEnv(observation=(("stat", "phi"),))
    with pytest.raises(tern.Error, match="no field 'delta_x'"):
        env2 = tern.env.FlightEnv(action_fields=("delta_x",), episode_s=0.1, start_s=0.1)
        env2.reset(seed=1)
        env2.step(np.zeros(1))


def test_new_parameter_values_keep_the_host_and_fly_as_a_fresh_one(env):
    """options={"set": ...} between episodes: the host stays (no rebuild), its parameters change
    between flights, and each episode is the one a host built with those values flies, a live
    parameter read at start() included (sim_aero's wind sets its trim); dropping a value goes back
    to the config's."""
    gains = np.array([0.4, -0.05])

    def episode(e, seed, sets):
        obs, _ = e.reset(seed=seed, options={"set": sets})
        out = [obs]
        for _ in range(100):
            obs, *_ = e.step(np.array([gains @ obs[:2]]))
            out.append(obs)
        return np.array(out)

    host = env.host
    cases = [{"slc.roll_kp": 0.7}, {"sim.wind": [3.0, -2.0, 0.0]}, {}, {"sim.sensor_profile": "ideal"}]
    reused = [episode(env, 20 + i, sets) for i, sets in enumerate(cases)]
    assert env.host is host
    assert env.host.get_param("sim.sensor_profile") == "ideal"
    for i, sets in enumerate(cases):
        fresh = tern.env.FlightEnv(episode_s=2.0, start_s=1.0, set=sets)
        assert episode(fresh, 20 + i, {}).tobytes() == reused[i].tobytes(), sets
        fresh.close()
    episode(env, 30, {})
    plain = tern.env.FlightEnv(episode_s=0.1, start_s=0.1)
    for name in ("sim.wind", "sim.sensor_profile", "slc.roll_kp"):
        assert env.host.get_param(name) == plain.host.get_param(name), name
    plain.close()
