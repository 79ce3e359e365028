#!/bin/bash
# tests/test_book_sim_replay.sh TERN SOURCE PYTHON3: a 90-s flight of bench/book_sim.py (a simulator
# written from the uavbook alone, not tern's: its own autopilot and sensors, the log starting in the
# air, commands one 5-ms sample late, no excitation table) read by `tern replay` as any other
# simulator's sensor log: every table accepted, the estimate valid from its start with no
# divergence, roll and pitch within 2 deg RMS of the simulator's own attitude (its reference.csv),
# the horizontal velocity within 0.5 m/s (issue 76: the flights users bring).
set -euo pipefail
tern=$1 src=$2 python3=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python3" "$src/bench/book_sim.py" --aircraft "$src/configs/aircraft/aerosonde.yaml" --out "$work/log" --duration 90 > /dev/null
"$tern" replay "$work/log" --log-dir "$work/runs" -q > "$work/replay.txt"
report=$(ls "$work"/runs/*/replay_report.json)
"$python3" - "$report" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
val = r["validity"]
ref = {k: r["reference"][k]["rms"] for k in ("roll", "pitch", "velocity_horizontal")}
checks = [("share_valid", val["share_valid"], val["share_valid"] >= 0.99), ("divergences", val["divergences"], val["divergences"] == 0),
          ("roll RMS deg", ref["roll"], ref["roll"] <= 2.0), ("pitch RMS deg", ref["pitch"], ref["pitch"] <= 2.0),
          ("horizontal velocity RMS m/s", ref["velocity_horizontal"], ref["velocity_horizontal"] <= 0.5)]
bad = [f"{name} {value:.3g}" for name, value, ok in checks if not ok]
print("book_sim replay: " + ", ".join(f"{name} {value:.3g}" for name, value, _ in checks))
sys.exit("book_sim replay: out of bounds: " + ", ".join(bad) if bad else 0)
PY
