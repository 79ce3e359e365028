#!/bin/sh
# core/dds/interop/run_gcs.sh TERN GCS MISSION DOMAIN DIR: the stand-in ground station test (issue 24).
# Flies MISSION (the default mission: sim_aero, estimator, path planner ...) with `tern fly --dds
# --realtime` on DDS domain DOMAIN (loopback only), runs the Cyclone DDS stand-in for rosplane_gcs
# and ROSplane's estimator (cyclone_gcs.c) against it with a loopback-only, unicast-only Cyclone
# configuration, prints its transcript and returns its exit status.
set -u
tern=$1 gcs=$2 mission=$3 domain=$4 dir=$5
rm -rf "$dir" && mkdir -p "$dir" || exit 1
cat > "$dir/cyclone.xml" <<XML
<CycloneDDS><Domain Id="any"><General><Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>
<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>
<MaxAutoParticipantIndex>31</MaxAutoParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers></Discovery></Domain></CycloneDDS>
XML
"$tern" fly "$mission" --dds --dds-domain "$domain" --realtime --duration 60 --log-dir "$dir/runs" > "$dir/vehicle.log" 2>&1 &
vehicle=$!
CYCLONEDDS_URI="file://$dir/cyclone.xml" "$gcs" "$domain"
rc=$?
kill "$vehicle" 2>/dev/null
wait "$vehicle" 2>/dev/null
[ $rc -eq 0 ] || { echo "--- vehicle log"; tail -20 "$dir/vehicle.log"; }
exit $rc
