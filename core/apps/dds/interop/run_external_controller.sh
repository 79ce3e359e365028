#!/bin/sh
# core/apps/dds/interop/run_external_controller.sh TERN STANDIN DOMAIN DIR SOURCE_DIR: the external-module
# test (issue 24). The stand-in controller (standin_controller.c, Cyclone DDS, loopback only) flies
# the default mission's cruise through `plugin: external` (configs/missions/external_controller.yaml,
# DDS domain DOMAIN), twice; then control_slc flies configs/missions/default.yaml on the same seed.
# Passes when both external flights reach every waypoint of the mission with the external module in
# control (no fallback), their line cross-track RMS is within twice control_slc's, and their state
# logs are bit-identical (cmp); and when, with no node running, the silent module is replaced by
# the fallback (slc) through the safety monitor. Prints the figures.
set -u
tern=$1 standin=$2 domain=$3 dir=$4 src=$5
seed=1 duration=180
rm -rf "$dir" && mkdir -p "$dir" || exit 1
cat > "$dir/cyclone.xml" <<XML
<CycloneDDS><Domain Id="any"><General><Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>
<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>
<MaxAutoParticipantIndex>31</MaxAutoParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers></Discovery></Domain></CycloneDDS>
XML
fly_external() {  # $1: run name
  CYCLONEDDS_URI="file://$dir/cyclone.xml" "$standin" "$domain" "$src/configs/gains/anaconda.yaml" 5 > "$dir/standin_$1.log" 2>&1 &
  sp=$!
  start=$(date +%s.%N)
  "$tern" fly "$src/configs/missions/external_controller.yaml" --dds-domain "$domain" --seed $seed --duration $duration \
    --log-dir "$dir/$1" --quiet > "$dir/tern_$1.log" 2>&1
  rc=$?
  echo "$1: tern exit $rc, wall $(awk "BEGIN{printf \"%.1f\", $(date +%s.%N) - $start}") s"
  kill "$sp" 2>/dev/null
  wait "$sp" 2>/dev/null
  cat "$dir/standin_$1.log"
  [ $rc -eq 0 ] || { tail -20 "$dir/tern_$1.log"; exit 1; }
}
fly_external a
fly_external b
"$tern" fly "$src/configs/missions/default.yaml" --seed $seed --duration $duration --log-dir "$dir/slc" --quiet > "$dir/tern_slc.log" 2>&1 ||
  { tail -20 "$dir/tern_slc.log"; exit 1; }
# no node on the topics: the module is silent from the first cruise tick, the safety monitor hands
# over to the fallback (slc) and the flight goes on
"$tern" fly "$src/configs/missions/external_controller.yaml" --dds-domain "$domain" --seed $seed --duration 30 \
  --log-dir "$dir/silent" --quiet > "$dir/tern_silent.log" 2>&1 || { tail -20 "$dir/tern_silent.log"; exit 1; }
run() { ls -d "$dir/$1"/*/ | head -1; }
a=$(run a) b=$(run b) slc=$(run slc)
status=0
if cmp "$a/topics/state.csv" "$b/topics/state.csv" && cmp "$a/topics/truth.csv" "$b/topics/truth.csv" &&
   cmp "$a/topics/actuators.csv" "$b/topics/actuators.csv"; then
  echo "deterministic: state, truth and actuators logs of the two external flights are bit-identical"
else
  echo "FAILED: the two external flights differ"; status=1
fi
python3 - "$(run silent)/summary.json" <<'PY' || status=1
import json, sys
j = json.load(open(sys.argv[1]))
back = [h for h in j["controller_handovers"] if h["from"] == "ext" and h["to"] == "slc"]
print(f"silent module: handed back to slc at {[h['t_s'] for h in back]} s ({back[0]['reason'] if back else 'never'}), "
      f"{j['instances']['ext']['timeouts']:.0f} timeouts, end {j['end_reason']}")
ok = j["fallback_engaged"] and back and "silent" in back[0]["reason"] and j["end_reason"] == "duration"
print("PASSED" if ok else "FAILED")
sys.exit(0 if ok else 1)
PY
python3 - "$a/summary.json" "$slc/summary.json" "$src/configs/missions/fixedwing_mission.yaml" <<'PY' || status=1
import json, sys
ext, slc = (json.load(open(f)) for f in sys.argv[1:3])
n_wp = sum(1 for line in open(sys.argv[3]) if line.startswith("wp:"))
def rms(j): return j["instances"]["manager"]["line_cross_track_rms_m"]
reached = sorted({p["waypoint"] for p in ext["metrics"]["waypoint_passages"]})
x = ext["instances"]["ext"]
took = [h for h in ext["controller_handovers"] if h["to"] == "ext"]
print(f"seed {ext['seed']}, {ext['duration_s']} s: waypoints reached {reached} of {n_wp}; line cross-track RMS ext {rms(ext):.3f} m, "
      f"slc {rms(slc):.3f} m (ratio {rms(ext) / rms(slc):.2f}); ext took over at {[h['t_s'] for h in took]} s, "
      f"fallback engaged {ext['fallback_engaged']}; lockstep: {x['exchanges']:.0f} exchanges, {x['timeouts']:.0f} timeouts, "
      f"wait per tick mean {x['wait_us_mean']:.0f} us, max {x['wait_us_max']:.0f} us")
ok = len(reached) == n_wp and rms(ext) <= 2 * rms(slc) and took and not ext["fallback_engaged"] and x["timeouts"] == 0
print("PASSED" if ok else "FAILED")
sys.exit(0 if ok else 1)
PY
exit $status
