#!/bin/sh
# core/apps/dds/interop/run_gcs.sh TERN GCS MISSION DOMAIN DIR: the stand-in ground station test (issue 24).
# Flies MISSION (the default mission: sim_aero, estimator, path planner ...) with `tern fly --dds
# --realtime` on DDS domain DOMAIN (loopback only), runs the Cyclone DDS stand-in for rosplane_gcs
# and ROSplane's estimator (cyclone_gcs.c) against it, prints its transcript and returns its exit status.
set -u
tern=$1 gcs=$2 mission=$3 domain=$4 dir=$5
rm -rf "$dir" && mkdir -p "$dir" || exit 1
. "$(dirname "$0")/vehicle_and_client.sh"
fly_with_client "$tern" "$mission" "$domain" "$dir" "$gcs" "$domain"
