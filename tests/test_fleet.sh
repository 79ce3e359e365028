#!/usr/bin/env bash
# Multi-vehicle missions (issue 42), as a user flies them:
#   1. configs/missions/crossing.yaml twice with one seed: every table and summary.json of every
#      vehicle, of the coordination and of the fleet byte-identical;
#   2. its separation report: the head-on pair's closest approach (truth) below min_distance, at
#      least one conflict, and the `hold` response flown: uav2 ends the flight higher than it began;
#   3. a crash contained: uav2's isolated filter dies (SIGSEGV) at t = 5 s; uav2's flight ends
#      "plugin_failed", uav1 flies to the end, the fleet's exit status is 1 and its summary says so;
#   4. bad input: two vehicles with one name, a vehicle without a mission, two vehicles with one
#      MAVLink system id, one out of 1-255, a coordination port on an unknown vehicle: one line
#      naming the file and the field.
# and 2b: the shipped coordination examples (rendezvous: three arrivals within 1 s; formation).
# usage: test_fleet.sh TERN REPO_DIR PYTHON3 TEST_PLUGIN_DIR
set -euo pipefail
tern=$1 repo=$2 python=$3 test_plugins=$4
work=$(mktemp -d "${TMPDIR:-/tmp}/tern-fleet-XXXXXX")
trap 'rm -rf "$work"' EXIT

# 1. determinism
for run in a b; do
  "$tern" fly "$repo/configs/missions/crossing.yaml" --duration 45 --log-dir "$work/$run" > "$work/$run.out" 2> "$work/$run.err"
done
ra=$(ls -1d "$work"/a/*/) rb=$(ls -1d "$work"/b/*/)
tables() { (cd "$1" && find . \( -name '*.csv' -o -name 'summary.json' -o -name 'flight.mcap' \) | sort); }
mapfile -t files < <(tables "$ra")
[ "${#files[@]}" -gt 10 ] || { echo "FAIL: the fleet wrote only ${#files[@]} tables"; exit 1; }
[ "$(tables "$rb")" = "$(printf '%s\n' "${files[@]}")" ] || { echo "FAIL: the second flight wrote other files"; exit 1; }
for f in "${files[@]}"; do
  cmp -s "$ra/$f" "$rb/$f" || { echo "FAIL: $f differs between two flights with one seed"; diff "$ra/$f" "$rb/$f" | head -4; exit 1; }
done
echo "determinism: ${#files[@]} files byte-identical over two flights"

# 2. separation
"$python" - "$ra" <<'PY'
import csv, json, sys
run = sys.argv[1]
s = json.load(open(run + "summary.json"))
sep = s["separation"]
print("separation:", json.dumps({k: sep[k] for k in ("closest_approach_m", "pair", "t_s", "conflicts", "from")}))
assert sep["from"] == "truth", sep
assert sep["pair"] == ["uav1", "uav2"], sep
assert 0 < sep["closest_approach_m"] < sep["min_distance_m"], sep
assert sep["conflicts"] >= 1, sep
assert json.load(open(run + "fleet.json"))["vehicles"] == ["uav1", "uav2"]
for v in ("uav1", "uav2"):
    assert s["vehicles"][v]["end_reason"] == "duration", s["vehicles"][v]
rows = list(csv.DictReader(open(run + "uav2/topics/truth.csv")))
climb = float(rows[0]["p_d [m]"]) - float(rows[-1]["p_d [m]"])
print(f"uav2 held: {climb:.1f} m higher at the end")
assert climb > 10.0, climb
PY
grep -q "uav2 holds over" "$work/a.err" || { echo "FAIL: no hold in the fleet's log"; exit 1; }

# 2b. the coordination examples: the timed rendezvous (three vehicles pass the point within 1 s)
# and the formation on one orbit, as shipped
"$tern" fly "$repo/configs/missions/rendezvous.yaml" --log-level summary --log-dir "$work/rdv" -q > /dev/null 2>&1
"$tern" fly "$repo/configs/missions/formation.yaml" --log-level summary --log-dir "$work/formation" -q > /dev/null 2>&1
"$python" - "$(ls -1d "$work"/rdv/*/)" "$(ls -1d "$work"/formation/*/)" <<'PY'
import json, math, sys
r = json.load(open(sys.argv[1] + "summary.json"))
f = r["coordination"]["instances"]["rendezvous"]
print(f"rendezvous: T {f['rendezvous_T']:.1f} s, spread {f['arrival_spread']:.2f} s, closest {r['separation']['closest_approach_m']:.1f} m")
assert f["vehicles_arrived"] == 3 and f["arrival_spread"] <= 1.0, f
assert all(abs(f["arrival_" + v] - f["rendezvous_T"]) < 1.5 for v in ("uav1", "uav2", "uav3")), f
assert r["coordination"]["end_reason"] == "vehicles_ended"
m = json.load(open(sys.argv[2] + "summary.json"))
g = m["coordination"]["instances"]["formation"]
print(f"formation: spacing rms {g['spacing_rms']:.1f} m over {g['spacing_samples']:.0f} samples")
assert g["spacing_samples"] > 0 and math.isfinite(g["spacing_rms"]) and g["spacing_rms"] < 60.0, g  # seed 1: ~33 m
PY

# 3. a crashed vehicle contained
cat > "$work/crash.yaml" <<YAML
name: crash
seed: 3
duration: 20
aircraft: $repo/configs/aircraft/anaconda.yaml
phases: {takeoff: ctl, climb: ctl, cruise: ctl}
phase_machine: {preflight: false}
mission: {waypoints: [[100, 0, -50]]}
plugins:
  - {name: sensor, plugin: test_sensor, rate: 400}
  - {name: filter, plugin: test_filter, trigger: imu, isolate: true}
  - {name: ctl, plugin: test_controller, rate: 100}
vehicles:
  - {name: uav1}
  - {name: uav2, params: {filter.fail_mode: segv, filter.fail_at: 5.0}}
YAML
status=0
TERN_PLUGIN_PATH=$test_plugins "$tern" fly "$work/crash.yaml" --log-dir "$work/crash" > "$work/crash.out" 2>&1 || status=$?
[ "$status" -eq 1 ] || { cat "$work/crash.out"; echo "FAIL: exit status $status, 1 expected"; exit 1; }
"$python" - "$(ls -1d "$work"/crash/*/)" <<'PY'
import json, sys
s = json.load(open(sys.argv[1] + "summary.json"))
v1, v2 = s["vehicles"]["uav1"], s["vehicles"]["uav2"]
print("crash: uav1", v1["end_reason"], v1["flown_s"], "s; uav2", v2["end_reason"], v2["flown_s"], "s")
assert v2["end_reason"] == "plugin_failed" and 4.9 < v2["flown_s"] < 5.2, v2
assert v1["end_reason"] == "duration" and v1["ok"] and v1["flown_s"] >= 19.99, v1
assert s["ok"] is False
PY

# 4. bad input: one line, the file and the field
sed 's/name: uav2/name: uav1/' "$work/crash.yaml" > "$work/twice.yaml"
if TERN_PLUGIN_PATH=$test_plugins "$tern" check "$work/twice.yaml" > "$work/twice.out" 2>&1; then echo "FAIL: two vehicles named uav1 accepted"; exit 1; fi
grep -q "twice.yaml:.*vehicles\[1\].name: vehicle name 'uav1' is used twice" "$work/twice.out" || { cat "$work/twice.out"; echo "FAIL: error line"; exit 1; }
grep -v '^mission:' "$work/crash.yaml" > "$work/nomission.yaml"
if TERN_PLUGIN_PATH=$test_plugins "$tern" check "$work/nomission.yaml" > "$work/nomission.out" 2>&1; then echo "FAIL: a vehicle without a mission accepted"; exit 1; fi
grep -q "nomission.yaml:.*vehicles\[0\] (uav1): no mission" "$work/nomission.out" || { cat "$work/nomission.out"; echo "FAIL: error line"; exit 1; }
[ "$(wc -l < "$work/nomission.out")" -eq 1 ] || { cat "$work/nomission.out"; echo "FAIL: more than one line"; exit 1; }
# MAVLink system ids (--gcs): one another vehicle has already, one out of 1-255; a free one taken
sed 's/{name: uav2,/{name: uav2, system_id: 1,/' "$work/crash.yaml" > "$work/sysid.yaml"
if TERN_PLUGIN_PATH=$test_plugins "$tern" check "$work/sysid.yaml" > "$work/sysid.out" 2>&1; then echo "FAIL: two vehicles with system id 1 accepted"; exit 1; fi
grep -q "sysid.yaml:.*vehicles\[1\].system_id: MAVLink system id 1 of uav2 is uav1's already" "$work/sysid.out" ||
  { cat "$work/sysid.out"; echo "FAIL: error line"; exit 1; }
sed 's/{name: uav2,/{name: uav2, system_id: 256,/' "$work/crash.yaml" > "$work/sysid.yaml"
if TERN_PLUGIN_PATH=$test_plugins "$tern" check "$work/sysid.yaml" > "$work/sysid.out" 2>&1; then echo "FAIL: system id 256 accepted"; exit 1; fi
grep -q "sysid.yaml:.*vehicles\[1\].system_id: expected a MAVLink system id, an integer 1-255, got '256'" "$work/sysid.out" ||
  { cat "$work/sysid.out"; echo "FAIL: error line"; exit 1; }
[ "$(wc -l < "$work/sysid.out")" -eq 1 ] || { cat "$work/sysid.out"; echo "FAIL: more than one line"; exit 1; }
sed 's/{name: uav2,/{name: uav2, system_id: 7,/' "$work/crash.yaml" > "$work/sysid.yaml"
TERN_PLUGIN_PATH=$test_plugins "$tern" check "$work/sysid.yaml" > "$work/sysid.out" 2>&1 || { cat "$work/sysid.out"; echo "FAIL: system id 7 refused"; exit 1; }
# a coordination port that names an unknown vehicle
sed 's|      start_phase: cruise|      start_phase: cruise\n    remap: {uav2/state: uav9/state}|' "$repo/configs/missions/rendezvous.yaml" |
  sed "s|\.\./|$repo/configs/|g" > "$work/unknown.yaml"
if "$tern" check "$work/unknown.yaml" > "$work/unknown.out" 2>&1; then echo "FAIL: a port on vehicle uav9 accepted"; exit 1; fi
grep -q "unknown.yaml: coordination\[0\] (rendezvous): port 'uav2/state' (topic 'uav9/state') names an unknown vehicle 'uav9'" "$work/unknown.out" ||
  { cat "$work/unknown.out"; echo "FAIL: error line"; exit 1; }
echo "PASS"
