#!/usr/bin/env bash
# A short flight logged with log.format both, as a user gets there (docs/logs.md):
#   tern fly CONFIG --log-format both     topics/*.csv and flight.mcap from one flight (--log-level full:
#                                         every ROS-typed copy, which the default level thins)
#   tern export csv RUN --out DIR         the MCAP file's tables equal topics/*.csv byte for byte
#   the same flight again                 the same flight.mcap, byte for byte (determinism)
#   flight.mcap cut at several offsets    tern export recover: a complete file whose tables are
#                                         the start of the flight's (every row of the chunks kept)
#
#   a flight logged as MCAP only         tern replay RUN and tern plot RUN read it
#   node mcap_reader/test_mcap_reader.mjs Foxglove's @mcap/core and rosmsg2-serialization decode every
#                                         channel of flight.mcap; every value equals the CSV table's
#   node mcap_reader/test_foxglove_scene.mjs  the 3-D scene: /tf equals truth in ENU/FLU, the model,
#                                         markers and configs/foxglove/tern-3d.json's topics; a
#                                         fleet's vehicles' scenes under their names
#
# usage: test_mcap_flight.sh TERN CONFIG DURATION_S NODE
set -euo pipefail
tern=$1 config=$2 duration=$3 node=$4
readers=$(cd "$(dirname "$0")/mcap_reader" && pwd)

work=$(mktemp -d "${TMPDIR:-/tmp}/tern-mcap-XXXXXX")
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*"; exit 1; }

"$tern" fly "$config" --duration "$duration" --log-level full --log-format both --log-dir "$work/a" -q >/dev/null
"$tern" fly "$config" --duration "$duration" --log-level full --log-format both --log-dir "$work/b" -q >/dev/null
a=$(ls -1d "$work"/a/*/) b=$(ls -1d "$work"/b/*/)
[ -s "$a/flight.mcap" ] || fail "no flight.mcap in $a"
cmp "$a/flight.mcap" "$b/flight.mcap" || fail "two flights of the same config and seed wrote different flight.mcap"

"$tern" export csv "$a" --out "$work/exported" >/dev/null
direct=$(cd "$a/topics" && ls) exported=$(cd "$work/exported" && ls)
[ "$direct" = "$exported" ] || fail "tables differ: topics/ has [$direct], the export [$exported]"
n=0
for f in $direct; do
  cmp "$a/topics/$f" "$work/exported/$f" || fail "$f: the export differs from the CSV log"
  n=$((n + 1))
done
echo "export csv: $n tables equal to the CSV log's, $(stat -c %s "$a/flight.mcap") bytes of MCAP"

[ -d "$readers/node_modules/@mcap/core" ] || fail "Foxglove's readers are not installed: make deps (npm ci in tests/mcap_reader)"
"$node" "$readers/test_mcap_reader.mjs" "$a" "$a/topics" || fail "the ecosystem's readers disagree with the CSV log"
# Foxglove's 3-D panel: /tf against truth, the model, the markers, the shipped layout (docs/logs.md)
root=$(cd "$(dirname "$0")/.." && pwd)
"$node" "$readers/test_foxglove_scene.mjs" "$a" "$root/configs/foxglove/tern-3d.json" "$(dirname "$config")/$(sed -n 's/^aircraft: *//p' "$config")" ||
  fail "the 3-D scene of flight.mcap"
# a fleet (docs/multi-vehicle.md): each vehicle's scene under its name (uav1/base_link ...)
"$tern" fly "$root/configs/missions/crossing.yaml" --duration 20 --log-format mcap --log-dir "$work/fleet" -q >/dev/null
for v in uav1 uav2; do
  "$node" "$readers/test_foxglove_scene.mjs" "$(ls -1d "$work"/fleet/*/)$v" - "$root/configs/aircraft/anaconda.yaml" "$v/" ||
    fail "the 3-D scene of fleet vehicle $v"
done

size=$(stat -c %s "$a/flight.mcap")
for frac in 13 37 50 71 97; do
  cut=$((size * frac / 100))
  head -c "$cut" "$a/flight.mcap" >"$work/cut.mcap"
  rm -rf "$work/recovered.mcap" "$work/rec"
  "$tern" export recover "$work/cut.mcap" --out "$work/recovered.mcap" >"$work/recover.txt" \
    || { cat "$work/recover.txt"; fail "recover of a file cut at $cut bytes"; }
  "$tern" export csv "$work/recovered.mcap" --out "$work/rec" >/dev/null 2>"$work/export.err"
  [ ! -s "$work/export.err" ] || { cat "$work/export.err"; fail "the recovered file (cut at $cut) is not complete"; }
  rows=0
  for f in $(cd "$work/rec" && ls); do
    len=$(stat -c %s "$work/rec/$f")
    cmp -n "$len" "$work/rec/$f" "$a/topics/$f" || fail "cut at $cut: $f is not the start of the flight's table"
    rows=$((rows + $(wc -l <"$work/rec/$f") - 1))
  done
  echo "cut at $frac % ($cut bytes): $rows rows recovered; $(head -1 "$work/recover.txt")"
  [ "$rows" -gt 0 ] || [ "$frac" -lt 20 ] || fail "cut at $cut: nothing recovered"
done
# a flight logged as MCAP only: tern replay and tern plot read it (its tables exported first)
"$tern" fly "$config" --duration "$duration" --log-level full --log-format mcap --log-dir "$work/m" -q >/dev/null
m=$(ls -1d "$work"/m/*/)
[ ! -d "$m/topics" ] || fail "an MCAP-only flight wrote topics/"
"$tern" replay "$m" -q --log-dir "$work/replays" >"$work/replay.txt" 2>&1 || { cat "$work/replay.txt"; fail "tern replay of an MCAP-only flight"; }
grep -q "topic tables exported from" "$work/replay.txt" || fail "tern replay did not say it exported the tables"
for f in $direct; do cmp "$m/topics/$f" "$a/topics/$f" || fail "$f: the replay's export differs from the CSV log"; done
"$(dirname "$tern")/tern-plot" "$m" >"$work/plot.txt" 2>&1 || { cat "$work/plot.txt"; fail "tern plot of an MCAP-only flight"; }
[ -s "$m/plots/index.html" ] || fail "tern plot wrote no index.html for the MCAP-only flight"
echo "MCAP-only flight: tern replay and tern plot read it"
echo "PASS"
