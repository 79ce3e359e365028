"""tern.Host: the CLI's Host stepped from Python: ticks and time, reading outputs, holding fields
on a module's output, parameters, swaps, seeds, the same flight as tern.fly, and bad input."""
import math

import numpy as np
import pytest

import tern
from conftest import BUILD, LEARN, SOURCE


@pytest.fixture
def host(logs):
    h = tern.Host(LEARN, log_dir=logs, log_level="full")
    yield h
    h.end()


def test_step_and_read(host):
    with pytest.raises(tern.Error, match="reset"):
        host.step(1)
    host.reset(1)
    assert host.flying and host.base_period == pytest.approx(0.0025)
    assert host.step(400)  # ticks at 0, 2.5 ms, ...: the time is the last tick's
    assert host.time == pytest.approx(0.9975)
    assert host.step_until(2.5) and host.time == pytest.approx(2.5)
    state = host.read("state")
    assert {"phi", "theta", "p_d", "Va"} <= set(state)
    assert host.read("truth")["p_d"] < -90.0  # released at 100 m, climbing
    assert isinstance(host.read("truth")["valid"], bool)
    assert "actuators" in host.topics


def test_write_holds_fields_until_released(host):
    host.reset(1)
    host.step_until(1.0)
    host.write("actuators", {"delta_a": 0.1, "delta_r": -0.05})
    host.step(4)
    act = host.read("actuators")
    assert act["delta_a"] == 0.1 and act["delta_r"] == -0.05
    assert act["delta_e"] != 0.0  # the controller's own elevator
    p0 = host.read("truth")["p"]
    host.step_until(2.0)
    assert host.read("truth")["p"] > p0 + 0.05  # the held aileron rolls it right
    assert host.release("actuators")
    host.step(4)
    assert host.read("actuators")["delta_a"] != 0.1
    run = host.end()
    logged = run["actuators"]
    held = (logged["t"] > 1.0) & (logged["t"] <= 2.0)
    assert np.all(logged["delta_a"][held] == 0.1)


def test_bad_input_raises_naming_it(host):
    host.reset(1)
    host.step(4)
    with pytest.raises(tern.Error, match="'actuatorz'"):
        host.read("actuatorz")
    with pytest.raises(tern.Error, match="'actuatorz'"):
        host.write("actuatorz", {"delta_a": 0.0})
    with pytest.raises(tern.Error, match="no field 'delta_q'.*delta_a"):
        host.write("actuators", {"delta_q": 0.0})
    with pytest.raises(tern.Error, match="field 'delta_a': 'left' is not a number"):
        host.write("actuators", {"delta_a": "left"})
    with pytest.raises(tern.Error, match="delta_a.*not a finite number"):
        host.write("actuators", {"delta_a": math.nan})
    with pytest.raises(tern.Error, match="slc.roll_kq"):
        host.get_param("slc.roll_kq")
    with pytest.raises(tern.Error, match="slc.roll_kp"):
        host.set_param("slc.roll_kp", "high")
    with pytest.raises(tern.Error, match="running"):
        host.swap("slc", BUILD / "plugins" / "libtern_control_slc.so")
    assert host.step(4)  # the flight goes on


def test_control_is_write_step_and_read_in_one_call(logs):
    """tern.Control flies what write(), step() and read() fly, bit for bit, and names bad input."""
    pairs = [("state", "phi"), ("controller_internals", "phi_c"), ("state", "p")]
    by_call, by_hand = tern.Host(LEARN, log_dir=logs), tern.Host(LEARN, log_dir=logs)
    control = by_call.control("actuators", ["delta_a", "delta_r"], pairs)
    assert len(control) == 3
    for h in (by_call, by_hand):
        h.reset(3)
    assert np.array_equal(control.read(), np.zeros(3))  # nothing published yet: 0, as read(topic, fields)
    for k in range(60):
        action = None if k % 20 == 5 else np.array([0.01 * (k % 7), -0.02])
        going, obs = control(action, 4)
        if action is None:
            by_hand.release("actuators")
        else:
            by_hand.write("actuators", {"delta_a": action[0], "delta_r": action[1]})
        assert going == by_hand.step(4)
        assert obs.tolist() == [by_hand.read(t, [f])[0] for t, f in pairs]
    assert by_call.read("actuators") == by_hand.read("actuators")
    with pytest.raises(tern.Error, match="2 fields of 'actuators'"):
        control(np.zeros(3), 1)
    with pytest.raises(tern.Error, match="not a finite number"):
        control(np.array([math.nan, 0.0]), 1)
    with pytest.raises(tern.Error, match="no field 'phy'"):
        by_call.control("actuators", ["delta_a"], [("state", "phy")]).read()
    with pytest.raises(tern.Error, match="no action fields"):
        by_call.control("actuators", [], pairs)
    assert by_call.handover_count == len(by_call.handovers)
    for h in (by_call, by_hand):
        h.end()


def test_params_seed_and_swap(host):
    host.reset(1)
    assert host.get_param("slc.roll_kp") != 0.5
    host.set_param("slc.roll_kp", 0.5)
    host.step(1)
    assert host.get_param("slc.roll_kp") == 0.5
    host.end()
    host.swap("slc", BUILD / "plugins" / "libtern_control_slc.so")
    host.reset(7)
    assert host.seed == 7 and host.time == 0.0
    host.step(40)
    assert host.read("state") is not None


def test_host_flies_what_tern_fly_flies(logs):
    flown = tern.fly(LEARN, seed=5, duration=3, log_dir=logs / "fly", log_level="full")
    with tern.Host(LEARN, seed=5, log_dir=logs / "host", log_level="full") as h:
        h.reset()
        h.step_until(3.0)
        stepped = h.end()
    for topic in ("state", "truth", "actuators"):
        a, b = flown[topic], stepped[topic]
        assert len(b) >= len(a) > 100 and a.tobytes() == b[: len(a)].tobytes(), topic


def test_a_new_seed_flies_what_a_host_built_with_it_flies(logs):
    # reset(seed) reseeds the built host (nothing reloaded): its flight is a fresh host's, bit for bit
    with tern.Host(LEARN, seed=5, log_dir=logs / "reseeded", log_level="full") as h:
        h.reset()
        h.step_until(1.0)
        h.reset(9)
        assert h.seed == 9
        h.step_until(3.0)
        reseeded = h.end()
    with tern.Host(LEARN, seed=9, log_dir=logs / "fresh", log_level="full") as h:
        h.reset()
        h.step_until(3.0)
        fresh = h.end()
    for topic in ("state", "truth", "actuators", "imu", "gnss"):
        assert reseeded[topic].tobytes() == fresh[topic].tobytes(), topic


def test_mission_edits_reach_the_planner(logs):
    """add_waypoint / clear_waypoints / load_mission: ROSplane's services, applied at the next tick."""
    with tern.Host(SOURCE / "configs" / "missions" / "default.yaml", log_dir=logs) as host:
        host.reset(1)
        host.step_until(60.0)
        assert host.clear_waypoints() == 1  # (the default mission ends with a land item: nothing follows it)
        host.step(80)  # the planner steps at 10 Hz: 40 ticks
        assert host.read("waypoints")["count"] == 0
        assert host.add_waypoint([400.0, -300.0, -80.0], 18.0) == 2
        host.add_waypoint([-200.0, 300.0, -80.0], 18.0, chi_d=1.0, use_chi=True)
        host.step(80)
        assert host.read("waypoints")["count"] == 2
        host.add_waypoint([0.0, 0.0, -60.0], 16.0, set_current=True)
        host.step(80)
        assert host.read("waypoints")["count"] == 1 and host.read("current_path")["Va_d"] == 16.0
        host.load_mission(SOURCE / "configs" / "missions" / "fixedwing_mission.yaml")
        host.step(80)
        assert host.read("waypoints")["count"] >= 4
        with pytest.raises(tern.Error, match="Va_d"):
            host.add_waypoint([0.0, 0.0, -60.0], 0.0)
        with pytest.raises(tern.Error, match="no such file"):
            host.load_mission("/nonexistent/mission.yaml")
        with pytest.raises(tern.Error, match="must be finite"):
            host.add_waypoint([math.nan, 0.0, -60.0], 16.0)
