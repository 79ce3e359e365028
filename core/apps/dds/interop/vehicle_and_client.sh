# core/apps/dds/interop/vehicle_and_client.sh (sourced by run_interop.sh and run_gcs.sh):
# fly_with_client TERN MISSION DOMAIN DIR CLIENT [ARGS...]: writes a loopback-only, unicast-only
# Cyclone DDS configuration to DIR/cyclone.xml, flies MISSION with `tern fly --dds --realtime` on
# DDS domain DOMAIN in the background, runs CLIENT ARGS with that configuration, stops the vehicle,
# prints the vehicle's log tail when the client failed and returns the client's exit status.
fly_with_client() {
  _tern=$1 _mission=$2 _domain=$3 _dir=$4
  shift 4
  # Cyclone: 127.0.0.1 only, no multicast; unicast discovery to the participant indices tern uses
  cat > "$_dir/cyclone.xml" <<XML
<CycloneDDS><Domain Id="any"><General><Interfaces><NetworkInterface address="127.0.0.1"/></Interfaces>
<AllowMulticast>false</AllowMulticast></General><Discovery><ParticipantIndex>auto</ParticipantIndex>
<MaxAutoParticipantIndex>31</MaxAutoParticipantIndex><Peers><Peer address="127.0.0.1"/></Peers></Discovery></Domain></CycloneDDS>
XML
  "$_tern" fly "$_mission" --dds --dds-domain "$_domain" --realtime --duration 60 --log-dir "$_dir/runs" > "$_dir/vehicle.log" 2>&1 &
  _vehicle=$!
  CYCLONEDDS_URI="file://$_dir/cyclone.xml" "$@"
  _rc=$?
  kill "$_vehicle" 2>/dev/null
  wait "$_vehicle" 2>/dev/null
  [ $_rc -eq 0 ] || { echo "--- vehicle log"; tail -20 "$_dir/vehicle.log"; }
  return $_rc
}
