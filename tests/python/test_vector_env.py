"""tern.vector_env.VectorFlightEnv: Gymnasium's vector API contract (batched spaces, arrays of
num_envs rows, vector infos), seeds (different per sub-environment, reproducible bit for bit, the
same episodes as FlightEnv alone), both autoreset modes, and wrong actions."""
import numpy as np
import pytest

import tern
import tern.env
from tern.vector_env import VectorFlightEnv

GAINS = np.array([1.5, -0.1])


def policy(obs):
    return (obs[:, :2] @ GAINS)[:, None]


def rollout(venv, seed, steps):
    obs, _ = venv.reset(seed=seed)
    out = [obs]
    for _ in range(steps):
        obs, rewards, terminated, truncated, _ = venv.step(policy(obs))
        out += [obs, rewards[:, None]]
    return np.concatenate(out, axis=1)


def test_contract_and_seeds():
    with VectorFlightEnv(3, episode_s=1.0, start_s=0.5) as venv:
        assert venv.num_envs == 3 and tern.env.VectorFlightEnv is VectorFlightEnv
        assert venv.single_observation_space.shape == (3,) and venv.single_action_space.shape == (1,)
        assert venv.observation_space.shape == (3, 3) and venv.action_space.shape == (3, 1)
        assert np.all(venv.action_space.low == -0.6) and np.all(venv.action_space.high == 0.6)
        obs, infos = venv.reset(seed=7)
        assert obs.shape == (3, 3) and obs.dtype == np.float64
        assert infos["seed"].tolist() == [7, 8, 9] and infos["_seed"].all()
        obs, rewards, terminated, truncated, infos = venv.step(policy(obs))
        assert rewards.shape == (3,) and terminated.dtype == bool and not truncated.any()
        assert infos["t"] == pytest.approx([0.51] * 3) and infos["_t"].all()
        a = rollout(venv, 7, 40)
        b = rollout(venv, 7, 40)
        c = rollout(venv, 11, 40)
    assert a.tobytes() == b.tobytes()  # the same seeds: bit for bit
    assert a.tobytes() != c.tobytes()
    assert not np.array_equal(a[0], a[1]) and not np.array_equal(a[1], a[2])  # seeds 7, 8, 9: three episodes
    single = tern.env.FlightEnv(episode_s=1.0, start_s=0.5)  # sub-environment 1 is FlightEnv seeded 8, alone
    obs, _ = single.reset(seed=8)
    row = [obs]
    for _ in range(40):
        obs, reward, *_ = single.step(policy(obs[None])[0])
        row += [obs, [reward]]
    single.close()
    assert np.concatenate(row).tobytes() == a[1].tobytes()


def test_autoreset_next_step():
    with VectorFlightEnv(2, episode_s=0.1, start_s=0.5) as venv:  # 10 steps an episode
        obs, infos = venv.reset(seed=[3, 4])
        first = obs.copy()
        for k in range(10):
            obs, rewards, terminated, truncated, infos = venv.step(np.zeros((2, 1)))
            assert truncated.all() == (k == 9) and not terminated.any()
        assert infos["t"] == pytest.approx([0.6, 0.6])
        obs, rewards, terminated, truncated, infos = venv.step(np.full((2, 1), 0.6))  # ignored: both reset
        assert rewards.tolist() == [0.0, 0.0] and not terminated.any() and not truncated.any()
        assert infos["t"] == pytest.approx([0.5, 0.5]) and infos["_seed"].all()
        assert infos["seed"][0] not in (3, 4) and infos["seed"][0] != infos["seed"][1]  # drawn from each one's generator
        assert not np.array_equal(obs, first)
        again = VectorFlightEnv(2, episode_s=0.1, start_s=0.5)
        again.reset(seed=[3, 4])
        for _ in range(11):
            *_, infos2 = again.step(np.zeros((2, 1)))
        again.close()
        assert infos2["seed"].tolist() == infos["seed"].tolist()  # the same seeds, the same next episodes
        obs, rewards, terminated, truncated, infos = venv.step(np.zeros((2, 1)))  # the new episodes go on
        assert infos["t"] == pytest.approx([0.51, 0.51]) and np.all(rewards < 0) and not truncated.any()


def test_autoreset_same_step():
    with VectorFlightEnv(2, episode_s=0.05, start_s=0.5, autoreset_mode="same_step") as venv:
        venv.reset(seed=5)
        for k in range(5):
            obs, rewards, terminated, truncated, infos = venv.step(np.zeros((2, 1)))
        assert truncated.all()
        assert infos["_final_obs"].all() and infos["final_obs"][0].shape == (3,)
        assert infos["final_info"]["t"] == pytest.approx([0.55, 0.55])
        assert infos["t"] == pytest.approx([0.5, 0.5])  # obs: the next episode's first
        assert not np.array_equal(infos["final_obs"][0], obs[0])


def test_bad_input():
    with pytest.raises(tern.Error, match="num_envs 0"):
        VectorFlightEnv(0)
    with pytest.raises(tern.Error, match="autoreset_mode 'always'"):
        VectorFlightEnv(2, autoreset_mode="always")
    with VectorFlightEnv(2, episode_s=0.1, start_s=0.1) as venv:
        with pytest.raises(tern.Error, match="reset"):
            venv.step(np.zeros((2, 1)))
        venv.reset(seed=1)
        with pytest.raises(tern.Error, match=r"actions of shape \(2,\), the action space's is \(2, 1\)"):
            venv.step(np.zeros(2))
        with pytest.raises(tern.Error, match=r"actions of shape \(3, 1\)"):
            venv.step(np.zeros((3, 1)))
        with pytest.raises(tern.Error, match="3 seeds for 2"):
            venv.reset(seed=[1, 2, 3])
    with pytest.raises(tern.Error, match="observation_space"):
        VectorFlightEnv(env_fns=[lambda: tern.env.FlightEnv(), lambda: tern.env.FlightEnv(observation=(("state", "phi"),))])
