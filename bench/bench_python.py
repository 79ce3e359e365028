#!/usr/bin/python3
"""bench_python.py [--build BUILD] [--steps N] [--episode S] [--envs N ...] [--flights N] [--cpu K] [--out JSON]: tern from Python (issues 66, 80).

0. The machine's single-thread figure: the default mission at log level summary by `tern fly`,
   its median real-time factor over --flights flights (the figures below are this machine's).
1. The learning environment (tern.env.FlightEnv, its default roll task on learn.yaml, its default
   episodes: 10 s after a 5-s start): steps per second of wall time at 100-Hz control, each step
   4 ticks of the 400-Hz host (simulator, estimator, guidance and controller), with a numpy
   linear policy computing every action; the episodes' resets (a new seed: the host, its
   libraries and port graph kept) counted apart, and split into the 5-s start the reset flies and
   the rest (the last flight's log ended and removed, the next flight begun). Beside it:
   Host.step(4) alone (the action held, no observation), the floor the environment's Python adds to.
2. The vectorised environment (tern.vector_env.VectorFlightEnv of each --envs count, each
   sub-environment its own Host, in this one thread): sub-environment steps per second, the same
   task and policy (one batched matrix product a step); without resets (episodes longer than the
   run) and with the autoresets of --episode-long episodes.
3. The default flight (configs/missions/default.yaml, seed 1, to its landing) flown by
   `tern fly -q` (a process) and by tern.fly in this process followed by reading its state,
   truth and actuators as arrays, --flights times each, alternating (which goes first too); the
   medians of wall time, tern.fly's two parts (the flight, the reading) apart, and of CPU time
   (every thread: the CLI's process as a child's rusage, tern.fly's as this process's), which the
   machine's other load changes less than the wall time.

Prints a table, writes JSON (default bench/results/bench_python.json). Run with Debian's python3
(python3-numpy) after building (make build): /usr/bin/python3 bench/bench_python.py.
"""
import argparse
import json
import os
import platform
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def env_rate(steps, episode_s, start_s=5.0):
    import numpy as np
    import tern.env
    env = tern.env.FlightEnv(episode_s=episode_s, start_s=start_s)
    gains = np.array([1.5, -0.1])
    stepping = resetting = 0.0
    done = episodes = 0
    while done < steps:
        t0 = time.perf_counter()
        obs, _ = env.reset(seed=episodes + 1)
        t1 = time.perf_counter()
        resetting += t1 - t0
        episodes += 1
        while done < steps:
            obs, reward, terminated, truncated, _ = env.step(np.array([gains @ obs[:2]]))
            done += 1
            if terminated or truncated:
                break
        stepping += time.perf_counter() - t1
    env.close()
    # the reset alone: the last flight ended (its log removed), the next begun, nothing flown
    bare = tern.env.FlightEnv(episode_s=episode_s, start_s=0.0)
    bare.reset(seed=1)
    bare_reset, n = 0.0, 30
    for k in range(n):
        bare.host.step(int(round(episode_s * 400)))  # an episode's flight (untimed) before each reset
        t0 = time.perf_counter()
        bare.reset(seed=k + 2)
        bare_reset += time.perf_counter() - t0
    bare_reset /= n
    host = bare.host
    host_reset = 0.0  # Host.reset(seed) alone, after an episode's flight (untimed), as FlightEnv calls it
    for k in range(n):
        host.step(int(round(episode_s * 400)))
        t0 = time.perf_counter()
        host.reset(k + 100)
        host_reset += time.perf_counter() - t0
    host_reset /= n
    host.reset(1)  # Host.step(4) alone, the action held still (the floor the Python adds to)
    host.write("actuators", {"delta_a": 0.0})
    t0 = time.perf_counter()
    for _ in range(steps):
        if not host.step(4):
            break
    raw = (_ + 1) / (time.perf_counter() - t0)
    bare.close()
    return {"steps": steps, "episodes": episodes, "episode_s": episode_s, "start_s": start_s, "steps_per_s": steps / stepping,
            "steps_per_s_with_resets": steps / (stepping + resetting), "reset_s": resetting / episodes,
            "reset_without_start_flight_s": bare_reset, "start_flight_s": resetting / episodes - bare_reset, "host_reset_s": host_reset,
            "host_step4_per_s": raw, "real_time_factor": steps / stepping * 0.01}


def vector_rate(steps, episode_s, n):
    """Sub-environment steps per second of a VectorFlightEnv of n: (without resets, with autoresets)."""
    import numpy as np
    from tern.vector_env import VectorFlightEnv
    gains = np.array([1.5, -0.1])
    out = []
    for length in (steps / n * 0.01 + 1.0, episode_s):  # longer than the run: no reset; then episode_s
        venv = VectorFlightEnv(n, episode_s=length, start_s=5.0)
        obs, _ = venv.reset(seed=1)
        resets = 0
        t0 = time.perf_counter()
        for _ in range(steps // n):
            obs, rewards, terminated, truncated, _ = venv.step((obs[:, :2] @ gains)[:, None])
            resets += int(np.count_nonzero(terminated | truncated))
        out.append((steps // n * n / (time.perf_counter() - t0), resets))
        venv.close()
    return {"num_envs": n, "steps": steps // n * n, "steps_per_s": out[0][0], "episode_s": episode_s,
            "steps_per_s_with_autoresets": out[1][0], "autoresets": out[1][1]}


def cpu(who):
    import resource
    r = resource.getrusage(who)
    return r.ru_utime + r.ru_stime


def machine_figure(build, flights):
    """The machine's single-thread figure beside the environment's: the default mission's flight
    (seed 1, to its landing) at log level summary by `tern fly`, this process's core(s): the
    median real-time factor of `flights` flights (issue 80 states its targets against it)."""
    import statistics
    rtf = []
    with tempfile.TemporaryDirectory(prefix="bench-python-") as tmp:
        for i in range(flights):
            t0 = time.perf_counter()
            subprocess.run([str(build / "bin" / "tern"), "fly", "-q", "--seed", "1", "--log-level", "summary", "--log-dir", f"{tmp}/m{i}"],
                           check=True, capture_output=True)
            wall = time.perf_counter() - t0
            with open(next(Path(tmp, f"m{i}").glob("*/summary.json"))) as f:
                rtf.append(json.load(f)["duration_s"] / wall)
    return {"command": "tern fly -q --seed 1 --log-level summary (configs/missions/default.yaml)", "flights": flights,
            "median_real_time_factor": statistics.median(rtf), "real_time_factors": rtf}


def default_flight(build, flights):
    import resource
    import statistics
    import tern

    cli, py, fly, read, cli_cpu, py_cpu = [], [], [], [], [], []
    with tempfile.TemporaryDirectory(prefix="bench-python-") as tmp:
        for i in range(flights):
            def by_cli():
                c0, t0 = cpu(resource.RUSAGE_CHILDREN), time.perf_counter()
                subprocess.run([str(build / "bin" / "tern"), "fly", "-q", "--seed", "1", "--log-dir", f"{tmp}/cli{i}"], check=True,
                               capture_output=True)
                cli.append(time.perf_counter() - t0)
                cli_cpu.append(cpu(resource.RUSAGE_CHILDREN) - c0)

            def by_python():
                c0, t0 = cpu(resource.RUSAGE_SELF), time.perf_counter()
                run = tern.fly(seed=1, log_dir=f"{tmp}/py{i}")
                t1 = time.perf_counter()
                rows = sum(len(run[t]) for t in ("state", "truth", "actuators"))
                t2 = time.perf_counter()
                py_cpu.append(cpu(resource.RUSAGE_SELF) - c0)
                py.append(t2 - t0)
                fly.append(t1 - t0)
                read.append(t2 - t1)
                return run, rows

            if i % 2:  # alternate which goes first
                run, rows = by_python()
                by_cli()
            else:
                by_cli()
                run, rows = by_python()
            flown = run.summary["duration_s"]
    m = statistics.median
    return {"flight_s": flown, "cli_wall_s": m(cli), "python_fly_and_read_wall_s": m(py), "python_fly_wall_s": m(fly),
            "python_read_wall_s": m(read), "rows_read": rows, "python_over_cli": m(py) / m(cli),
            "cli_cpu_s": m(cli_cpu), "python_fly_and_read_cpu_s": m(py_cpu), "python_over_cli_cpu": m(py_cpu) / m(cli_cpu),
            "flights": flights, "statistic": "median", "cli_wall_s_all": cli, "python_fly_and_read_wall_s_all": py}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", default=str(ROOT / "build"))
    ap.add_argument("--steps", type=int, default=20000)
    ap.add_argument("--episode", type=float, default=10.0, help="episode length, s (default FlightEnv's: 10 s after a 5-s start)")
    ap.add_argument("--envs", type=int, nargs="+", default=[1, 2, 4], help="sub-environments of the vectorised environment")
    ap.add_argument("--cpu", type=int, help="pin the whole process (and its children) to this core")
    ap.add_argument("--flights", type=int, default=5)
    ap.add_argument("--out", default=str(ROOT / "bench" / "results" / "bench_python.json"))
    a = ap.parse_args()
    build = Path(a.build).resolve()
    sys.path.insert(0, str(build / "python"))
    if a.cpu is not None:
        os.sched_setaffinity(0, {a.cpu})
    machine = machine_figure(build, a.flights)
    env = env_rate(a.steps, a.episode)
    vecs = [vector_rate(a.steps, a.episode, n) for n in a.envs]
    fly = default_flight(build, a.flights)
    print(f"{'environment (100-Hz control, 4 ticks a step)':<52} {'value':>12}  target")
    print(f"{'steps per second (numpy linear policy)':<52} {env['steps_per_s']:12.0f}  >= 20000")
    print(f"{'  the same with the episodes resets':<52} {env['steps_per_s_with_resets']:12.0f}")
    print(f"{'  reset (new seed; host kept), s':<52} {env['reset_s']:12.4f}")
    print(f"{'    of which the 5-s start flown, s':<52} {env['start_flight_s']:12.4f}")
    print(f"{'    the rest: log ended and removed, next begun, s':<52} {env['reset_without_start_flight_s']:12.4f}")
    print(f"{'    Host.reset(seed) alone, s':<52} {env['host_reset_s']:12.4f}")
    print(f"{'Host.step(4) alone per second':<52} {env['host_step4_per_s']:12.0f}")
    print(f"{'real-time factor':<52} {env['real_time_factor']:12.0f}  >= 200")
    for vec in vecs:
        print(f"{'vectorised, %d sub-environments: steps per second' % vec['num_envs']:<52} {vec['steps_per_s']:12.0f}")
        print(f"{'  the same with autoresets (%g-s episodes)' % vec['episode_s']:<52} {vec['steps_per_s_with_autoresets']:12.0f}")
    print(f"{'machine: default mission, summary log, real-time factor':<52} {machine['median_real_time_factor']:12.0f}")
    print(f"{'default flight (%.1f s of flight), median of %d' % (fly['flight_s'], fly['flights']):<52}")
    print(f"{'  tern fly -q, wall s':<52} {fly['cli_wall_s']:12.2f}")
    print(f"{'  tern.fly + state/truth/actuators as arrays, wall s':<52} {fly['python_fly_and_read_wall_s']:12.2f}  <= CLI")
    print(f"{'    the flight (tern.fly), wall s':<52} {fly['python_fly_wall_s']:12.2f}")
    print(f"{'    reading %d rows as arrays, wall s' % fly['rows_read']:<52} {fly['python_read_wall_s']:12.3f}")
    print(f"{'  ratio':<52} {fly['python_over_cli']:12.3f}  <= 1")
    print(f"{'  CPU time (all threads): tern fly, s':<52} {fly['cli_cpu_s']:12.2f}")
    print(f"{'  CPU time: tern.fly + arrays, s':<52} {fly['python_fly_and_read_cpu_s']:12.2f}")
    print(f"{'  ratio of CPU times':<52} {fly['python_over_cli_cpu']:12.3f}")
    result = {"bench": "bench_python", "issues": [66, 80], "machine": platform.node(), "cpus": os.cpu_count(),
              "python": sys.version.split()[0], "cores": sorted(os.sched_getaffinity(0)), "machine_figure": machine,
              "environment": env, "vector_environment": vecs, "default_flight": fly,
              "command": "python3 bench/bench_python.py " + " ".join(sys.argv[1:])}
    Path(a.out).parent.mkdir(parents=True, exist_ok=True)
    with open(a.out, "w") as f:
        json.dump(result, f, indent=2)
    print(f"wrote {a.out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
