"""tern.fly and tern.Run: a short flight of the default mission read as arrays, overrides, the
MCAP log read as the CSV one, determinism, and errors that name what is wrong."""
import numpy as np
import pytest

import tern
from conftest import DEFAULT


def test_fly_reads_arrays(logs):
    run = tern.fly(DEFAULT, seed=1, duration=20, set={"slc.roll_kp": 0.6}, log_dir=logs)
    assert run.ok and run.end_reason == "duration"
    assert {"state", "truth", "actuators", "imu"} <= set(run.topics)
    state = run["state"]
    assert state.dtype.names[:3] == ("t", "stamp", "p_n")
    assert state.dtype["stamp"] == np.int64
    assert run.units("state")["p_d"] == "m" and state.dtype.metadata["units"]["Va"] == "m/s"
    assert len(state) > 100 and state["t"][-1] == pytest.approx(20.0, abs=0.01)
    assert np.all(np.diff(state["t"]) > 0)
    assert run.summary["seed"] == 1 and run.summary["mission"] == "default"
    assert run.params["slc.roll_kp"] == 0.6
    kinds = {e["kind"] for e in run.events}
    assert "phase" in kinds and "handover" in kinds
    assert run.config["name"] == "default"


def test_same_seed_same_arrays(logs):
    a = tern.fly(DEFAULT, seed=3, duration=15, log_dir=logs / "a")
    b = tern.fly(DEFAULT, seed=3, duration=15, log_dir=logs / "b")
    c = tern.fly(DEFAULT, seed=4, duration=15, log_dir=logs / "c")
    for topic in ("state", "truth", "imu", "actuators"):
        assert a[topic].tobytes() == b[topic].tobytes(), topic
    assert a["imu"].tobytes() != c["imu"].tobytes()


def test_mcap_reads_as_csv(logs):
    run = tern.fly(DEFAULT, seed=2, duration=8, log_format="both", log_dir=logs)
    mcap = tern.Run(run.dir / "flight.mcap")
    assert mcap.topics == run.topics
    assert mcap["state"].tobytes() == run["state"].tobytes()


def test_errors_name_what_is_wrong(logs, tmp_path):
    run = tern.fly(DEFAULT, seed=1, duration=2, log_dir=logs)
    with pytest.raises(tern.Error, match="no topic 'stat'"):
        run["stat"]
    with pytest.raises(tern.Error, match="not a run directory"):
        tern.Run(tmp_path / "nowhere")
    with pytest.raises(tern.Error, match="slc.roll_kq"):
        tern.fly(DEFAULT, duration=1, set={"slc.roll_kq": 1.0}, log_dir=logs)
    with pytest.raises(tern.Error, match="nowhere.yaml"):
        tern.fly(tmp_path / "nowhere.yaml", log_dir=logs)


def test_malformed_table_names_file_line_and_column(tmp_path):
    from tern.run import read_table
    good = tmp_path / "good.csv"
    good.write_text("t [s],stamp [ns],x [m],ok [bool]\n0.5,500000000,-1.25e-3,1\n1,1000000000,nan,0\n"
                    "1.5,9007199254740993,+2,1\n2,2e3,-inf,0\n")
    t = read_table(good)
    assert t["stamp"].tolist() == [500000000, 1000000000, 2**53 + 1, 2000] and t["stamp"].dtype == np.int64  # ns exact
    assert t["x"][0] == -1.25e-3 and np.isnan(t["x"][1]) and t["x"][2] == 2.0 and t["x"][3] == -np.inf
    assert t["ok"].tolist() == [True, False, True, False]
    bad = tmp_path / "bad.csv"
    bad.write_text("t [s],x [m]\n0.5,1\n1,zero\n")
    with pytest.raises(tern.Error, match=r"bad.csv:3: column 2 'x': 'zero' is not a number"):
        read_table(bad)
    short = tmp_path / "short.csv"
    short.write_text("t [s],x [m],y [m]\n0.5,1,2\n1,2\n")
    with pytest.raises(tern.Error, match=r"short.csv:3: 2 cells, the header has 3 columns"):
        read_table(short)
    long = tmp_path / "long.csv"
    long.write_text("t [s],x [m]\n0.5,1,2\n")
    with pytest.raises(tern.Error, match=r"long.csv:2: more cells than the header's 2 columns"):
        read_table(long)
    big = tmp_path / "big.csv"  # two threads: an error in the second half names its own line
    big.write_text("t [s],x [m]\n" + "".join(f"{i},{i * 0.5}\n" for i in range(9999)) + "9999,x\n")
    with pytest.raises(tern.Error, match=r"big.csv:10001: column 2 'x': 'x' is not a number"):
        read_table(big)
    assert len(read_table(big.parent / "good.csv")) == 4
