#!/bin/sh
# core/dds/interop/run_interop.sh TERN CLIENT DOMAIN DIR: the Cyclone DDS interop test (issue 20).
# Flies the host's test plugins with `tern fly --dds` on DDS domain DOMAIN (loopback only), runs the
# Cyclone DDS client against it (cyclone_client.c) with a loopback-only, unicast-only Cyclone
# configuration, prints the client's transcript and returns its exit status.
set -u
tern=$1 client=$2 domain=$3 dir=$4
rm -rf "$dir" && mkdir -p "$dir" || exit 1
cat > "$dir/interop.yaml" <<YAML
name: interop
seed: 7
duration: 60
phases: {takeoff: ctl, climb: ctl, cruise: ctl}
phase_machine: {preflight: false}
plugins:
  - {name: sensor, plugin: test_sensor, rate: 400}
  - {name: filter, plugin: test_filter, trigger: imu}
  - {name: ctl, plugin: test_controller, rate: 100}
YAML
# Cyclone: 127.0.0.1 only, no multicast; unicast discovery to the participant indices tern uses
cat > "$dir/cyclone.xml" <<XML
<CycloneDDS><Domain Id="any"><General><Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>
<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>
<MaxAutoParticipantIndex>31</MaxAutoParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers></Discovery></Domain></CycloneDDS>
XML
"$tern" fly "$dir/interop.yaml" --dds --dds-domain "$domain" --realtime --duration 60 --log-dir "$dir/runs" > "$dir/vehicle.log" 2>&1 &
vehicle=$!
CYCLONEDDS_URI="file://$dir/cyclone.xml" "$client" "$domain"
rc=$?
kill "$vehicle" 2>/dev/null
wait "$vehicle" 2>/dev/null
[ $rc -eq 0 ] || { echo "--- vehicle log"; tail -20 "$dir/vehicle.log"; }
exit $rc
