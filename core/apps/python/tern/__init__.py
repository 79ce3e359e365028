"""tern from Python (docs/python.md).

    import tern
    run = tern.fly("configs/missions/default.yaml", seed=1, duration=60, set={"slc.roll_kp": 0.6})
    run["state"]["p_d"]          # numpy structured array of a topic: one field per log column
    host = tern.Host()            # the Host `tern fly` flies, stepped tick by tick
    host.reset(seed=1); host.step(400); host.read("state")["phi"]
    c = tern.campaign("configs/campaigns/landing_dispersion.yaml", workers=2)   # c.table, c.summary

tern.fly flies through the same code as `tern fly` (core/apps/commands/fly_mission.hpp); tern.Host is
that Host (core/host/flight/host.hpp); tern.Run reads what a flight wrote. Errors about the
outside world (a wrong topic, field, parameter, type or file) raise tern.Error (a ValueError)
naming it. tern.env is the learning environment, tern.vector_env several at once; tern.campaign
flies a Monte Carlo campaign (tern/campaigns.py).
"""

from tern._tern import Error, default_config
from tern._tern import fly as _fly
from tern._tern import Host as _Host
from tern.run import Run
from tern.campaigns import Campaign, campaign

__all__ = ["Campaign", "Error", "Host", "Run", "campaign", "default_config", "fly"]
Error.__module__ = "tern"  # raised as tern.Error


def fly(config=None, seed=None, duration=None, set=None, log_dir=None, log_level=None, log_format=None, quiet=True):
    """Flies `config` (default: the default mission) once, in this process, as `tern fly CONFIG
    --seed SEED --duration DURATION --set K=V ... --log-dir LOG_DIR` does, and returns its Run.

    set: {"instance.param": value}; log_level: "summary", "decimated" or "full"; log_format:
    "csv", "mcap" or "both". Raises tern.Error for a bad config, override or mission."""
    r = _fly(None if config is None else str(config), seed=seed, duration=duration, set=set or {},
             log_dir=None if log_dir is None else str(log_dir), log_level=log_level, log_format=log_format, quiet=quiet)
    run = Run(r["run_dir"])
    run.ok, run.end_reason, run.end_detail, run.wall_s = r["ok"], r["end_reason"], r["end_detail"], r["wall_s"]
    return run


class Host(_Host):
    """A mission's Host stepped from Python (core/apps/python/python_host.hpp).

    Host(config=None, *, seed=None, duration=None, set={}, log_dir=None, log_level=None,
    log_format=None, quiet=True) builds it; reset(seed=None) starts a flight (ending the running
    one); step(ticks=1) and step_until(t) fly it, False once it has ended; time (s), topics,
    read(topic) -> dict or None, write(topic, {field: value}) held until release(topic),
    get_param(name) / set_param(name, value), swap(instance, so) between flights, handovers,
    end_reason; add_waypoint(w, Va_d, chi_d=, use_chi=, lla=, set_current=), clear_waypoints(),
    load_mission(file): mission edits for the path planner (ROSplane's services); end() ends the
    flight and returns its Run."""

    def __init__(self, config=None, *, seed=None, duration=None, set=None, log_dir=None, log_level=None, log_format=None, quiet=True):
        super().__init__(None if config is None else str(config), seed=seed, duration=duration, set=set or {},
                         log_dir=None if log_dir is None else str(log_dir), log_level=log_level, log_format=log_format, quiet=quiet)

    def end(self):
        """Ends the running flight (its log complete) and returns its Run (None before any flight)."""
        run_dir = super().end()
        return Run(run_dir) if run_dir else None

    def swap(self, instance, so):
        super().swap(instance, str(so))

    def load_mission(self, file):
        """Queues the replacement of the mission by a waypoint file (tern's or ROSplane's format)."""
        return super().load_mission(str(file))

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        super().end()
