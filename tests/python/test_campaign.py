"""tern.campaign and tern.Campaign: a 3-flight campaign flown through `tern campaign`, its table
typed (uint64 seeds, units, text, numbers), checked against each flight's own summary.json,
reproducible from its seed, and errors naming the file, field or directory."""
import numpy as np
import pytest

import tern
from conftest import DEFAULT

CAMPAIGN = f"""name: small
base: {DEFAULT}
seed: 5
flights: 3
duration: 6
log: summary
dispersions:
  sim.wind: {{dist: polar, speed: [0, 4], from_deg: [0, 360]}}
  slc.roll_kp: {{dist: uniform, low: 0.5, high: 1.5}}
criteria:
  - end_reason == duration
  - instances.sim.sim_crashed == 0
"""


@pytest.fixture
def campaign_file(tmp_path):
    f = tmp_path / "small.yaml"
    f.write_text(CAMPAIGN)
    return f


def test_campaign_table(campaign_file, tmp_path):
    c = tern.campaign(campaign_file, workers=2, out=tmp_path / "out")
    t = c.table
    assert len(c) == 3 and t["index"].tolist() == [0, 1, 2]
    assert t.dtype["seed"] == np.uint64 and len(set(t["seed"].tolist())) == 3
    assert t["outcome"].tolist() == ["pass"] * 3 and t["why"].tolist() == [""] * 3
    assert c.units["sim.wind.speed"] == "m/s" and c.units["slc.roll_kp"] == "rad/rad"
    assert np.all((t["slc.roll_kp"] >= 0.5) & (t["slc.roll_kp"] <= 1.5)) and len(set(t["slc.roll_kp"])) == 3
    assert np.all((t["sim.wind.speed"] >= 0) & (t["sim.wind.speed"] <= 4))
    assert t["end_reason"].tolist() == ["duration"] * 3
    for k in range(3):  # the table's figures are each flight's own summary.json
        run = c.run(k)
        assert run.summary["seed"] == int(t["seed"][k]) == int(t["summary.seed"][k])
        assert run.summary["duration_s"] == t["duration_s"][k]
        assert run.summary["metrics"]["max_cross_track_m"] == t["metrics.max_cross_track_m"][k]
        assert run.params["slc.roll_kp"] == t["slc.roll_kp"][k]
    assert c.rows[1]["slc.roll_kp"] == t["slc.roll_kp"][1] and c.rows[1]["outcome"] == "pass"
    s = c.summary
    assert s["flights"] == 3 and s["passed"] == 3 and s["seed"] == 5
    assert c.throughput["flights_flown"] == 3

    again = tern.campaign(campaign_file, workers=1, out=tmp_path / "again")  # the same seed: the same table
    for name in t.dtype.names:
        if name != "command":
            assert again.table[name].tobytes() == t[name].tobytes(), name
    reread = tern.Campaign(tmp_path / "out")
    assert reread.table.tobytes() == t.tobytes()


def test_failing_criterion_is_a_row(tmp_path):
    f = tmp_path / "strict.yaml"
    f.write_text(CAMPAIGN.replace("name: small", "name: strict").replace("flights: 3", "flights: 2")
                 + "  - duration_s > 100\n")
    c = tern.campaign(f, out=tmp_path / "strict")
    assert c.table["outcome"].tolist() == ["fail", "fail"]
    assert all("duration_s = 6 (needs > 100)" in w for w in c.table["why"])
    assert c.summary["failed"] == 2


def test_errors(campaign_file, tmp_path):
    with pytest.raises(tern.Error, match="nowhere.yaml: no such campaign file"):
        tern.campaign(tmp_path / "nowhere.yaml")
    with pytest.raises(tern.Error, match="workers 0"):
        tern.campaign(campaign_file, workers=0)
    bad = tmp_path / "bad.yaml"
    bad.write_text(CAMPAIGN.replace("slc.roll_kp:", "slc.roll_kq:"))
    with pytest.raises(tern.Error, match="slc.roll_kq"):
        tern.campaign(bad, out=tmp_path / "bad")
    tern.campaign(campaign_file, out=tmp_path / "taken")
    other = tmp_path / "other.yaml"
    other.write_text(CAMPAIGN.replace("seed: 5", "seed: 6"))
    with pytest.raises(tern.Error, match="holds the results of a different campaign file"):
        tern.campaign(other, out=tmp_path / "taken")
    with pytest.raises(tern.Error, match="no results.csv"):
        tern.Campaign(tmp_path)
    with pytest.raises(tern.Error, match="flight 7 has no complete run"):
        tern.Campaign(tmp_path / "taken").run(7)
