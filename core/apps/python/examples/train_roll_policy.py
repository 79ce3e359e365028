#!/usr/bin/env python3
"""Train a roll policy in tern's learning environment with numpy alone, then fly it.

    PYTHONPATH=build/python python3 core/apps/python/examples/train_roll_policy.py [--iterations 6]

The policy is linear in the default task's observation (tern.env: [phi_c - phi, p, phi_c]):
    delta_a = k_phi (phi_c - phi) - k_p p        (rad; the roll loop's PD law, uavbook 6.1)
and replaces the controller's aileron on `actuators` while its course loop commands phi_c and its
other loops fly pitch, speed and rudder. The cross-entropy method (Rubinstein & Kroese) draws
`population` gain pairs from a normal distribution, flies one episode each (the same seed for
every candidate of an iteration: common random numbers, a new seed each iteration), and refits
the distribution to the best `elite`. Then the mean gains fly episodes of held-out seeds beside
the controller's own roll loop (the action released: env.step(None)); the table shows both, and
--out writes the gains and figures as JSON.
"""
import argparse
import json
import sys

import numpy as np

import tern.env


def episode(env, seed, gains):
    """Return and RMS roll error (deg) of one episode; gains None: the controller's own aileron."""
    obs, _ = env.reset(seed=seed)
    total, errors = 0.0, []
    while True:
        action = None if gains is None else np.array([gains[0] * obs[0] - gains[1] * obs[1]])
        obs, reward, terminated, truncated, _ = env.step(action)
        total += reward
        errors.append(obs[0])
        if terminated:
            return total - 1000.0, float("nan")  # the safety net took over: the worst return
        if truncated:
            return total, float(np.degrees(np.sqrt(np.mean(np.square(errors)))))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--iterations", type=int, default=6)
    ap.add_argument("--population", type=int, default=12)
    ap.add_argument("--elite", type=int, default=3)
    ap.add_argument("--episode", type=float, default=8.0, help="episode length, s")
    ap.add_argument("--evaluate", type=int, default=3, help="held-out seeds the result flies")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--out", help="JSON file for the gains and figures")
    a = ap.parse_args()

    env = tern.env.FlightEnv(episode_s=a.episode, start_s=25.0)  # from 25 s: in the hourglass's first turn
    rng = np.random.default_rng(a.seed)
    mean, std = np.array([0.5, 0.0]), np.array([0.5, 0.1])
    print(f"{'iter':>4} {'k_phi':>7} {'k_p':>7} {'best return':>12} {'mean return':>12}")
    for it in range(a.iterations):
        gains = mean + std * rng.standard_normal((a.population, 2))
        returns = np.array([episode(env, a.seed * 1000 + it, g)[0] for g in gains])
        elite = gains[np.argsort(returns)[-a.elite:]]
        mean, std = elite.mean(axis=0), elite.std(axis=0) + 0.01
        print(f"{it:>4} {mean[0]:7.3f} {mean[1]:7.3f} {returns.max():12.3f} {returns.mean():12.3f}")

    seeds = [a.seed * 1000 + 500 + i for i in range(a.evaluate)]
    learnt = [episode(env, s, mean) for s in seeds]
    own = [episode(env, s, None) for s in seeds]
    env.close()
    print(f"\n{'seed':>6} {'policy return':>14} {'RMS roll error':>15} {'controller return':>18} {'RMS roll error':>15}")
    for s, (r1, e1), (r2, e2) in zip(seeds, learnt, own):
        print(f"{s:>6} {r1:14.3f} {e1:13.2f} deg {r2:18.3f} {e2:13.2f} deg")
    result = {"k_phi": mean[0], "k_p": mean[1], "seeds": seeds, "policy": learnt, "controller": own}
    if a.out:
        with open(a.out, "w") as f:
            json.dump(result, f, indent=2)
    return 0 if all(np.isfinite(e) for _, e in learnt) else 1


if __name__ == "__main__":
    sys.exit(main())
