"""core/apps/python/examples/clone_roll_policy.py: PyTorch's behaviour cloning when torch is there,
else one line saying torch is absent and the numpy fallback flown; either way it exits 0 with the
cloned policy flown on held-out seeds beside the controller."""
import importlib.util
import json
import subprocess
import sys

import pytest

from conftest import BUILD, SOURCE, python_env

EXAMPLE = SOURCE / "core" / "apps" / "python" / "examples" / "clone_roll_policy.py"
HAS_TORCH = importlib.util.find_spec("torch") is not None


def run(*args, cwd):
    env = python_env(PYTHONPATH=str(BUILD / "python"))
    return subprocess.run([sys.executable, str(EXAMPLE), *args], capture_output=True, text=True, env=env, cwd=cwd, timeout=240)


def test_help(tmp_path):
    r = run("--help", cwd=tmp_path)
    assert r.returncode == 0 and "PyTorch MLP" in r.stdout and "--numpy" in r.stdout


@pytest.mark.parametrize("forced", [False, True])
def test_clone_and_fly(tmp_path, forced):
    args = ["--episodes", "2", "--episode", "2", "--evaluate", "2", "--epochs", "20", "--out", "out.json"] + (["--numpy"] if forced else [])
    r = run(*args, cwd=tmp_path)
    assert r.returncode == 0, r.stdout + r.stderr
    out = json.loads((tmp_path / "out.json").read_text())
    assert out["demonstrations"] == 400 and out["seeds"] == [1500, 1501]
    if forced or not HAS_TORCH:
        assert out["policy"] == "linear (numpy fallback)" and "linear fallback: delta_a =" in r.stdout
        assert ("torch is absent" in r.stdout) == (not forced)
    else:
        assert out["policy"] == "mlp (torch)" and "PyTorch" in r.stdout
    for (ret, rms), (own_ret, own_rms) in zip(out["cloned"], out["controller"]):
        assert -1000 < ret < 0 and -1000 < own_ret < 0 and 0 < rms < 5 and 0 < own_rms < 5  # flew the episode, no safety net
