#!/usr/bin/env python3
"""Clone the controller's roll loop into a small PyTorch MLP (behaviour cloning), then fly it.

    PYTHONPATH=build/python python3 core/apps/python/examples/clone_roll_policy.py [--epochs 300]

PyTorch is optional: Debian's python3-torch (apt-get install python3-torch) when it is there. The
demonstrations are the controller's own aileron: FlightEnv's default roll task (tern.env, learn.yaml)
flown with the action released (env.step(None)), each step's observation [phi_c - phi, p, phi_c]
paired with the aileron the controller commanded from it (the `actuators` output read after the
step). A 3-16-16-1 tanh MLP learns delta_a from the observation by mean squared error (Adam). Then
the cloned policy flies held-out seeds in a tern.vector_env.VectorFlightEnv (one batched forward
pass for every sub-environment a step) beside the controller's own roll loop.

Without PyTorch it says so on one line ("torch is absent ..."), fits the numpy fallback instead (a
linear policy by least squares on the same demonstrations), flies that, and exits 0. --numpy
takes the fallback even with PyTorch there.
"""
import argparse
import json
import sys

import numpy as np

import tern.env
from tern.vector_env import VectorFlightEnv


def demonstrations(episodes, episode_s, seed):
    """(observations [N, 3], the controller's aileron [N]) over `episodes` episodes."""
    env = tern.env.FlightEnv(episode_s=episode_s, start_s=25.0)  # from 25 s: in the hourglass's first turn
    xs, ys = [], []
    for k in range(episodes):
        env.reset(seed=seed + k)
        while True:
            obs, _, terminated, truncated, _ = env.step(None)  # the controller's own aileron flies
            xs.append(obs)
            ys.append(env.host.read("actuators", ["delta_a"])[0])
            if terminated or truncated:
                break
    env.close()
    return np.array(xs), np.array(ys)


def train_torch(torch, x, y, epochs, hidden, seed):
    """A tanh MLP fitted by Adam on the whole batch; returns f(obs[n, 3]) -> actions[n, 1]."""
    torch.manual_seed(seed)
    net = torch.nn.Sequential(torch.nn.Linear(x.shape[1], hidden), torch.nn.Tanh(), torch.nn.Linear(hidden, hidden),
                              torch.nn.Tanh(), torch.nn.Linear(hidden, 1)).double()
    opt = torch.optim.Adam(net.parameters(), lr=3e-3)
    xt, yt = torch.from_numpy(x), torch.from_numpy(y[:, None])
    for epoch in range(epochs):
        opt.zero_grad()
        loss = torch.nn.functional.mse_loss(net(xt), yt)
        loss.backward()
        opt.step()
        if epoch % max(1, epochs // 5) == 0 or epoch == epochs - 1:
            print(f"  epoch {epoch:4d}: mean squared aileron error {loss.item():.3e} rad^2")

    def policy(obs):
        with torch.no_grad():
            return net(torch.from_numpy(obs)).numpy()
    return policy


def train_numpy(x, y):
    """The fallback: delta_a = w . [obs, 1] by least squares."""
    a = np.hstack([x, np.ones((len(x), 1))])
    w, *_ = np.linalg.lstsq(a, y, rcond=None)
    print(f"  linear fallback: delta_a = {w[0]:.3f} (phi_c - phi) {w[1]:+.3f} p {w[2]:+.3f} phi_c {w[3]:+.4f};"
          f" mean squared aileron error {np.mean((a @ w - y) ** 2):.3e} rad^2")
    return lambda obs: (np.hstack([obs, np.ones((len(obs), 1))]) @ w)[:, None]


def fly_policy(policy, seeds, episode_s):
    """Return and RMS roll error (deg) per seed, the policy flying every seed at once."""
    venv = VectorFlightEnv(len(seeds), episode_s=episode_s, start_s=25.0)
    obs, _ = venv.reset(seed=seeds)
    returns, errors = np.zeros(len(seeds)), [[] for _ in seeds]
    live = np.ones(len(seeds), dtype=bool)
    while live.any():
        obs, rewards, terminated, truncated, _ = venv.step(np.clip(policy(obs), -0.6, 0.6))
        returns += np.where(live, rewards, 0.0)
        for i in np.flatnonzero(live):
            errors[i].append(obs[i, 0])
        returns[live & terminated] -= 1000.0  # the safety net took over: the worst return
        live &= ~(terminated | truncated)  # the next step would reset it: its episode is over
    venv.close()
    return [(float(r), float(np.degrees(np.sqrt(np.mean(np.square(e)))))) for r, e in zip(returns, errors)]


def fly_controller(seeds, episode_s):
    env = tern.env.FlightEnv(episode_s=episode_s, start_s=25.0)
    out = []
    for s in seeds:
        env.reset(seed=s)
        total, errors = 0.0, []
        while True:
            obs, reward, terminated, truncated, _ = env.step(None)
            total += reward
            errors.append(obs[0])
            if terminated or truncated:
                break
        out.append((total, float(np.degrees(np.sqrt(np.mean(np.square(errors)))))))
    env.close()
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--episodes", type=int, default=4, help="demonstration episodes")
    ap.add_argument("--episode", type=float, default=8.0, help="episode length, s")
    ap.add_argument("--epochs", type=int, default=300)
    ap.add_argument("--hidden", type=int, default=16, help="units in each hidden layer")
    ap.add_argument("--evaluate", type=int, default=3, help="held-out seeds the cloned policy flies")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--numpy", action="store_true", help="the numpy fallback even with PyTorch there")
    ap.add_argument("--out", help="JSON file for the figures")
    a = ap.parse_args()

    torch = None
    if not a.numpy:
        try:
            import torch
        except ImportError:
            print("torch is absent (Debian: apt-get install python3-torch): the MLP is not trained; "
                  "the numpy fallback (a linear least-squares policy) flies instead")
    x, y = demonstrations(a.episodes, a.episode, a.seed * 1000)
    print(f"{len(x)} demonstrations from {a.episodes} episodes of the controller's roll loop")
    if torch is not None:
        print(f"PyTorch {torch.__version__}: a 3-{a.hidden}-{a.hidden}-1 tanh MLP")
        policy, kind = train_torch(torch, x, y, a.epochs, a.hidden, a.seed), "mlp (torch)"
    else:
        policy, kind = train_numpy(x, y), "linear (numpy fallback)"

    seeds = [a.seed * 1000 + 500 + i for i in range(a.evaluate)]
    cloned = fly_policy(policy, seeds, a.episode)
    own = fly_controller(seeds, a.episode)
    print(f"\n{'seed':>6} {'cloned return':>14} {'RMS roll error':>15} {'controller return':>18} {'RMS roll error':>15}")
    for s, (r1, e1), (r2, e2) in zip(seeds, cloned, own):
        print(f"{s:>6} {r1:14.3f} {e1:11.2f} deg {r2:18.3f} {e2:11.2f} deg")
    if a.out:
        with open(a.out, "w") as f:
            json.dump({"policy": kind, "demonstrations": len(x), "seeds": seeds, "cloned": cloned, "controller": own}, f, indent=2)
    return 0 if all(np.isfinite(e) for _, e in cloned) else 1


if __name__ == "__main__":
    sys.exit(main())
