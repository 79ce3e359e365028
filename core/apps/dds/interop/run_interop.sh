#!/bin/sh
# core/apps/dds/interop/run_interop.sh TERN CLIENT DOMAIN DIR: the Cyclone DDS interop test (issue 20).
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
. "$(dirname "$0")/vehicle_and_client.sh"
fly_with_client "$tern" "$dir/interop.yaml" "$domain" "$dir" "$client" "$domain"
