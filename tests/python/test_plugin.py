"""Plugins written in Python (plugins/python, docs/python.md "A plugin in Python"): the shipped
examples fly the default mission from the command line and from Python, bit-identically from run
to run; a Python exception is one line naming the script's file and line, and the safety net
handles it as any plugin's (a routed controller: the fallback flies on; anything else: the flight
ends, its log kept); a hang in an isolated instance is killed; bad declarations are one line;
parameters change in flight; the plugin's library reloads between flights (a hot swap) with the
interpreter alive, and makes nothing that points into it (no pybind11 internals); the Python path follower commands what the C++ one does; the templates fly."""
import json
import re
import subprocess

import pytest

import tern
from conftest import BUILD, SOURCE

MISSIONS = SOURCE / "configs" / "missions"
FOLLOWER = MISSIONS / "python_follower.yaml"
CONTROLLER = MISSIONS / "python_controller.yaml"
TERN = BUILD / "bin" / "tern"


def cli(*args, check=True):
    r = subprocess.run([str(TERN), *map(str, args)], capture_output=True, text=True, timeout=240)
    if check:
        assert r.returncode == 0, r.stdout + r.stderr
    return r


def run_dir(out):
    return re.search(r"log: (\S+)", out).group(1)


def script(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return path


def test_follower_flies_the_default_mission_and_repeats_bit_for_bit(tmp_path):
    a = run_dir(cli("fly", FOLLOWER, "--duration", "60", "--log-dir", tmp_path / "a", "--log-level", "full", "-q").stdout)
    b = run_dir(cli("fly", FOLLOWER, "--duration", "60", "--log-dir", tmp_path / "b", "--log-level", "full", "-q").stdout)
    for topic in ("controller_command.csv", "actuators.csv", "truth.csv"):
        assert open(f"{a}/topics/{topic}", "rb").read() == open(f"{b}/topics/{topic}", "rb").read()
    summary = json.load(open(f"{a}/summary.json"))
    follower = summary["instances"]["follower"]
    assert follower["plugin"] == "python_path_follower" and follower["commands"] == follower["steps"] > 5000
    assert summary["instances"]["metrics"]["max_cross_track_m"] < 10.0


def test_in_process_flight_is_the_command_lines(tmp_path):
    """tern.fly loads the plugin into the interpreter it runs in: the same flight as `tern fly`."""
    run = tern.fly(FOLLOWER, duration=30, log_dir=tmp_path / "py", log_level="full")
    assert run.ok, run.end_detail
    d = run_dir(cli("fly", FOLLOWER, "--duration", "30", "--log-dir", tmp_path / "cli", "--log-level", "full", "-q").stdout)
    assert open(f"{d}/topics/controller_command.csv", "rb").read() == (run.dir / "topics" / "controller_command.csv").read_bytes()


def test_controller_exception_hands_over_to_the_fallback(tmp_path):
    bad = script(tmp_path, "bad_controller.py", "class Bad:\n    inputs = {'state': 'State'}\n    outputs = {'actuators': 'Actuators'}\n"
                 "    def step(self, now, inputs):\n        return {'actuators': {'delta_t': 1 / 0}}\n")
    run = tern.fly(CONTROLLER, duration=60, set={"pyslc.script": str(bad)}, log_dir=tmp_path)
    assert run.ok and run.summary["fallback_engaged"] and run.wall_s > 0
    assert run.summary["controller_handovers"][-1]["to"] == "slc"
    assert re.search(r"bad_controller\.py:5 in step: ZeroDivisionError: division by zero", (run.dir / "tern.log").read_text())


def test_follower_exception_ends_the_flight_in_one_line_with_its_log(tmp_path):
    bad = script(tmp_path, "bad_follower.py", "class Bad:\n    inputs = {'state': 'State'}\n    outputs = {'controller_command': 'ControllerCommand'}\n"
                 "    def step(self, now, inputs):\n        if now > 20e9:\n            raise RuntimeError('lost the path')\n")
    r = cli("fly", FOLLOWER, "--duration", "60", "--set", f"follower.script={bad}", "--log-dir", tmp_path, "-q", check=False)
    assert r.returncode != 0
    summary = json.load(open(f"{run_dir(r.stdout)}/summary.json"))
    assert "follower.step threw at t=20.0" in summary["end_reason"] and "bad_follower.py:6 in step: RuntimeError: lost the path" in summary["end_reason"]
    assert summary["duration_s"] == pytest.approx(20.0, abs=0.02)


def test_isolated_hang_is_killed_and_the_fallback_flies(tmp_path):
    hang = script(tmp_path, "hang.py", "import time\nclass Hang:\n    inputs = {'state': 'State'}\n    outputs = {'actuators': 'Actuators'}\n"
                  "    def step(self, now, inputs):\n        time.sleep(3600)\n")
    config = CONTROLLER.read_text().replace("    plugin: python_controller\n", "    plugin: python_controller\n    isolate: true\n")
    config = config.replace("../../plugins/python/examples/cruise_controller.py", str(hang)).replace("../", str(MISSIONS.parent) + "/")
    path = tmp_path / "isolated.yaml"
    path.write_text(config.replace("file: fixedwing_mission.yaml", f"file: {MISSIONS / 'fixedwing_mission.yaml'}"))
    d = run_dir(cli("fly", path, "--duration", "40", "--log-dir", tmp_path, "-q").stdout)
    summary = json.load(open(f"{d}/summary.json"))
    assert summary["end_reason"] == "duration" and summary["fallback_engaged"]
    assert "hung" in open(f"{d}/tern.log").read()


@pytest.mark.parametrize("text,line", [
    ("class A:\n    inputs = {'state': 'Stat'}\n    def step(self, now, inputs): pass\n", "port 'state': no message type 'Stat'"),
    ("class A:\n    outputs = {'controller_command': 'ControllerCommand'}\n", "defines 0 classes with a step method"),
    ("class A:\n    params = {'k': object()}\n    def step(self, now, inputs): pass\n", "parameter 'k': a default of bool"),
    ("class A:\n    params = {'step': 1.0}\n    def step(self, now, inputs): pass\n", "parameter 'step' would hide"),
    ("import nosuchmodule\n", "ModuleNotFoundError: No module named 'nosuchmodule'"),
])
def test_bad_declarations_are_one_line(tmp_path, text, line):
    bad = script(tmp_path, "bad.py", text)
    r = cli("check", FOLLOWER, "--set", f"follower.script={bad}", check=False)
    assert r.returncode != 0 and line in r.stderr, r.stderr


def test_wrong_output_column_is_one_line(tmp_path):
    bad = script(tmp_path, "typo.py", "class Typo:\n    outputs = {'controller_command': 'ControllerCommand'}\n"
                 "    def step(self, now, inputs):\n        return {'controller_command': {'Va_cc': 17.0}}\n")
    run = tern.fly(FOLLOWER, duration=5, set={"follower.script": str(bad)}, log_dir=tmp_path)
    assert not run.ok and "output 'controller_command': tern/ControllerCommand has no column 'Va_cc'" in run.end_reason


@pytest.mark.parametrize("value,wanted", [("0.5", "a bool"), ("'yes'", "a bool")])
def test_wrong_output_value_is_one_line(tmp_path, value, wanted):
    bad = script(tmp_path, "flag.py", "class Flag:\n    outputs = {'controller_command': 'ControllerCommand'}\n"
                 f"    def step(self, now, inputs):\n        return {{'controller_command': {{'Va_c': 17.0, 'landing': {value}}}}}\n")
    run = tern.fly(FOLLOWER, duration=5, set={"follower.script": str(bad)}, log_dir=tmp_path)
    assert not run.ok and f"column 'landing' of tern/ControllerCommand takes {wanted}" in run.end_reason


def test_parameters_change_in_flight(tmp_path):
    hold = script(tmp_path, "hold.py", "class Hold:\n    inputs = {'state': 'State'}\n    outputs = {'controller_command': 'ControllerCommand'}\n"
                  "    params = {'Va': (17.0, 'm/s', 10.0, 30.0, 'airspeed to hold'), 'h': 70.0}\n"
                  "    def step(self, now, inputs):\n        return {'controller_command': {'Va_c': self.Va, 'h_c': self.h, 'chi_c': inputs['state'].chi}}\n")
    with tern.Host(FOLLOWER, set={"follower.script": str(hold)}, log_dir=tmp_path) as host:
        host.reset(seed=1)
        host.step_until(30.0)
        assert host.read("controller_command")["Va_c"] == 17.0
        host.set_param("follower.Va", 15.5)  # applied at the next tick, before the plugin's next step
        host.step(8)
        assert host.get_param("follower.Va") == 15.5 and host.read("controller_command")["Va_c"] == 15.5
        with pytest.raises(tern.Error, match="Va"):
            host.set_param("follower.Va", 50.0)
            host.step(8)


def test_python_follower_reloads_between_flights_and_matches_the_cpp_one(tmp_path):
    """A hot-swap unloads the plugin's library with the interpreter alive: the next flight loads
    it anew (a private copy) and flies as the first did."""
    commands = []
    with tern.Host(FOLLOWER, log_dir=tmp_path) as host:
        for flight in range(3):
            host.reset(seed=1)
            assert host.step_until(41.0)
            commands.append(host.read("controller_command"))
            host.end()
            host.swap("follower", BUILD / "plugins" / "libtern_python_path_follower.so")
    assert commands[0] == commands[1] == commands[2] and commands[0]["Va_c"] > 10.0
    with tern.Host(MISSIONS / "default.yaml", log_dir=tmp_path) as host:
        host.reset(seed=1)
        assert host.step_until(41.0)
        assert abs(host.read("controller_command")["chi_c"] - commands[0]["chi_c"]) < 0.05  # one law in two languages


def test_the_plugin_makes_no_pybind11_internals(tmp_path):
    """The plugin's library is unloaded with the interpreter alive (a hot swap), so nothing it makes
    may point into it. Its messages and parameters go through pybind11's object wrappers
    (sdk/python), which must never make pybind11's internals (kept in builtins, with pointers into
    the library that made them): a flight from the command line, where no other pybind11 module is
    loaded, steps and re-reads its parameters without them."""
    probe = script(tmp_path, "probe.py", "import builtins\nclass Probe:\n    inputs = {'state': 'State'}\n"
                   "    outputs = {'controller_command': 'ControllerCommand'}\n"
                   "    params = {'Va': (17.0, 'm/s'), 'h': [70.0], 'tag': 'probe', 'on': True, 'n': 3}\n"
                   "    def step(self, now, inputs):\n"
                   "        made = [k for k in vars(builtins) if k.startswith('__pybind11_internals')]\n"
                   "        assert not made and self.tag == 'probe' and self.on and self.n == 3, made\n"
                   "        return {'controller_command': {'Va_c': self.Va, 'h_c': self.h[0], 'chi_c': inputs['state'].chi}}\n")
    r = cli("fly", FOLLOWER, "--duration", "5", "--set", f"follower.script={probe}", "--set", "follower.Va=16.5",
            "--log-dir", tmp_path, "--log-level", "full", "-q", check=False)
    assert r.returncode == 0, r.stdout + r.stderr
    header, *rows = open(f"{run_dir(r.stdout)}/topics/controller_command.csv").read().splitlines()
    column = [name.split(" [")[0] for name in header.split(",")].index("Va_c")  # "Va_c [m/s]"
    assert len(rows) > 100 and {float(row.split(",")[column]) for row in rows} == {16.5}


@pytest.mark.parametrize("kind,end", [("path_follower", "duration"), ("controller", "landed")])
def test_new_plugin_python_template_flies(tmp_path, kind, end):
    out = cli("new-plugin", "my_module", "--python", "--kind", kind, "--dir", tmp_path / "p").stdout
    assert "class MyModule in my_module.py" in out
    assert "class MyModule:" in (tmp_path / "p" / "my_module.py").read_text()
    d = run_dir(cli("fly", tmp_path / "p" / "mission.yaml", "--duration", "1000", "--log-dir", tmp_path, "-q").stdout)
    summary = json.load(open(f"{d}/summary.json"))
    assert summary["end_reason"] == end and not summary["fallback_engaged"]
    r = cli("new-plugin", "other", "--python", "--kind", "estimator", "--dir", tmp_path / "q", check=False)
    assert r.returncode == 2 and "kind 'estimator' has no Python template" in r.stderr


def test_failing_summary_loses_only_its_figures(tmp_path):
    bad = script(tmp_path, "bad_summary.py", "class F:\n    inputs = {'state': 'State'}\n    outputs = {'controller_command': 'ControllerCommand'}\n"
                 "    def step(self, now, inputs):\n        return {'controller_command': {'Va_c': 17.0, 'h_c': 70.0, 'chi_c': inputs['state'].chi}}\n"
                 "    def summary(self):\n        return {'x': 'not a number'}\n")
    run = tern.fly(FOLLOWER, duration=20, set={"follower.script": str(bad)}, log_dir=tmp_path)
    assert run.ok and run.summary["instances"]["follower"]["steps"] > 1000 and "x" not in run.summary["instances"]["follower"]
    assert "summary() failed, its figures are left out" in (run.dir / "tern.log").read_text()
