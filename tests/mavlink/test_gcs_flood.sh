#!/usr/bin/env bash
# The MAVLink endpoint never changes a flight (issue 64): the same mission and seed flown in lockstep
#   1. without --gcs, and
#   2. with --gcs while a flood of random and malformed datagrams (random bytes, half of them
#      starting with MAVLink 2's 0xFD) hits the vehicle's port,
# write byte-identical tables (topics/*.csv, params.csv) and summary.json; the endpoint counts the
# flood as dropped, a ground station's port gets the telemetry (HEARTBEAT, ATTITUDE,
# GLOBAL_POSITION_INT frames) and tern ends normally. Any mission: the simulator's, or the real
# firmware's through fcu_serial (default_sil.yaml). What only describes the host's run (timing.json,
# tern.log) is not compared.
#
# usage: test_gcs_flood.sh TERN CONFIG DURATION_S PYTHON3 (a DURATION_S that takes a few seconds of
# wall time in lockstep: the flood hits the endpoint all through the flight)
set -euo pipefail
tern=$1 config=$2 duration=$3 python=$4

work=$(mktemp -d "${TMPDIR:-/tmp}/tern-gcs-flood-XXXXXX")
flooder= listener=
cleanup() {
  [ -n "$flooder" ] && kill "$flooder" 2>/dev/null || true
  [ -n "$listener" ] && kill "$listener" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

free_port() { "$python" -c 'import socket; s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
vehicle_port=$(free_port)
gcs_port=$(free_port)

"$tern" fly "$config" --seed 7 --duration "$duration" --log-dir "$work/plain" -q >"$work/plain.out"

# the flood: until killed, datagrams of 0-300 random bytes to the vehicle's port
"$python" - "$vehicle_port" "$work/flooding" <<'PY' &
import os, random, socket, sys
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
rng = random.Random(1)
n = 0
while True:
    if n == 1000:
        open(sys.argv[2], "w").close()  # flooding: the flight may start
    d = bytearray(os.urandom(rng.randrange(0, 300)))
    if d and n % 2 == 0:
        d[0] = 0xFD
    s.sendto(bytes(d), ("127.0.0.1", int(sys.argv[1])))
    n += 1
PY
flooder=$!
# the ground station: counts the frames of each message id it gets, written when it is stopped
"$python" - "$gcs_port" "$work/gcs_frames" <<'PY' &
import collections, signal, socket, sys
s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM)
s.bind(("127.0.0.1", int(sys.argv[1])))
seen = collections.Counter()
def done(*_):
    with open(sys.argv[2], "w") as f:
        f.write(" ".join(f"{k}:{v}" for k, v in sorted(seen.items())) + "\n")
    sys.exit(0)
signal.signal(signal.SIGTERM, done)
while True:
    d = s.recv(65536)
    i = 0
    while i + 12 <= len(d) and d[i] == 0xFD:  # MAVLink 2 frames: 10-byte header, payload, CRC
        seen[d[i + 7] | d[i + 8] << 8 | d[i + 9] << 16] += 1
        i += 12 + d[i + 1] + (13 if d[i + 2] & 1 else 0)
PY
listener=$!
for _ in $(seq 100); do [ -e "$work/flooding" ] && break; sleep 0.1; done
[ -e "$work/flooding" ] || { echo "FAIL: the flood did not start"; exit 1; }
# a flight that does not end (the endpoint's thread not joining) fails here, named, well inside
# ctest's timeout (both times TERN_TEST_TIMEOUT_SCALE in a sanitizer build, where the flood's
# millions of datagrams go through instrumented code)
limit=$((120 * ${TERN_TEST_TIMEOUT_SCALE:-1}))
rc=0
timeout "$limit" "$tern" fly "$config" --seed 7 --duration "$duration" --log-dir "$work/gcs" -q \
  --gcs "127.0.0.1:$gcs_port" --gcs-bind "127.0.0.1:$vehicle_port" >"$work/gcs.out" || rc=$?
[ "$rc" -ne 124 ] || { cat "$work/gcs.out"; echo "FAIL: tern fly --gcs under the flood did not end within $limit s"; exit 1; }
[ "$rc" -eq 0 ] || { cat "$work/gcs.out"; echo "FAIL: tern fly --gcs under the flood exited $rc"; exit 1; }
kill "$flooder" "$listener"
wait "$flooder" 2>/dev/null || true
wait "$listener" 2>/dev/null || true
flooder= listener=
cat "$work/gcs.out"
frames=$(cat "$work/gcs_frames" 2>/dev/null || true)
echo "the ground station got (message id:frames): $frames"
for id in 0 30 33; do  # HEARTBEAT, ATTITUDE, GLOBAL_POSITION_INT
  [[ " $frames" == *" $id:"* ]] || { echo "FAIL: the ground station got no message $id"; exit 1; }
done

grep -q "^mavlink: udp 127.0.0.1:$vehicle_port -> 127.0.0.1:$gcs_port" "$work/gcs.out" || { echo "FAIL: no endpoint line"; exit 1; }
datagrams=$(sed -n 's/^mavlink: \([0-9]*\) datagrams, \([0-9]*\) frames.*/\1 \2/p' "$work/gcs.out")
read -r received frames <<<"$datagrams"
[ "${received:-0}" -gt 0 ] || { echo "FAIL: the endpoint read no datagram of the flood"; exit 1; }
[ "$frames" -eq 0 ] || { echo "FAIL: $frames frames made out of random bytes"; exit 1; }

plain=$(ls -1d "$work"/plain/*/) gcs=$(ls -1d "$work"/gcs/*/)
tables() { (cd "$1" && { find . -name '*.csv'; echo ./summary.json; } | sort); }
mapfile -t compared < <(tables "$plain")
[ "${#compared[@]}" -gt 2 ] || { echo "FAIL: the flight wrote no topic tables"; exit 1; }
mapfile -t files < <(tables "$gcs")
[ "${files[*]}" = "${compared[*]}" ] || { echo "FAIL: the flight with --gcs wrote other files"; exit 1; }
for f in "${compared[@]}"; do
  if ! cmp -s "$plain/$f" "$gcs/$f"; then
    echo "FAIL: $f differs with --gcs and the flood; first difference:"
    diff "$plain/$f" "$gcs/$f" | head -4 || true
    exit 1
  fi
done
echo "with --gcs and $received flooding datagrams (all dropped): ${#compared[@]} files byte-identical to the flight without --gcs"
