#!/bin/sh
# core/apps/dds/interop/run_fleet_interop.sh TERN CLIENT DOMAIN DIR: the multi-vehicle DDS test (issue 42).
# Flies a two-vehicle mission of the host's test plugins with `tern fly --dds` on DDS domain DOMAIN
# (loopback only) and runs the Cyclone DDS client (cyclone_client.c) against each vehicle's
# namespace in turn: /uav1 and /uav2 each have their node graph, their state topic, their parameter
# services and add_waypoint. Prints the transcripts; exit 0 when both clients succeeded.
set -u
tern=$1 client=$2 domain=$3 dir=$4
rm -rf "$dir" && mkdir -p "$dir" || exit 1
cat > "$dir/fleet.yaml" <<YAML
name: fleet_interop
seed: 7
duration: 60
aircraft: $(dirname "$0")/../../../../configs/aircraft/anaconda.yaml
phases: {takeoff: ctl, climb: ctl, cruise: ctl}
phase_machine: {preflight: false}
mission: {waypoints: [[100, 0, -50]]}
plugins:
  - {name: sensor, plugin: test_sensor, rate: 400}
  - {name: filter, plugin: test_filter, trigger: imu}
  - {name: ctl, plugin: test_controller, rate: 100}
vehicles:
  - {name: uav1}
  - {name: uav2}
YAML
both() {
  "$client" "$domain" uav1 && "$client" "$domain" uav2
}
. "$(dirname "$0")/vehicle_and_client.sh"
fly_with_client "$tern" "$dir/fleet.yaml" "$domain" "$dir" both
