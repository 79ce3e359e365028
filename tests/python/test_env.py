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
