#!/bin/bash
# tests/test_dataflash_roundtrip.sh TERN SOURCE PYTHON3: a 40-s flight of the default mission written
# as an ArduPilot DataFlash log by bench/dataflash_log.py (its own encoder, from AP_Logger's
# LogStructure.h) and read back by `tern import dataflash`: every row of the six sensor and
# command tables back at its stamp, every value within half the format's step (dataflash_log.py
# --check exits 1 otherwise). The writer of the foreign bench's DataFlash route, checked against
# the importer it feeds (issue 76).
set -euo pipefail
tern=$1 src=$2 python3=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$tern" fly "$src/configs/missions/default.yaml" --duration 40 --log-dir "$work/runs" -q > /dev/null
run=$(ls -d "$work"/runs/*-default)
"$python3" "$src/bench/dataflash_log.py" "$run" "$work/log.bin" --check "$(dirname "$tern")"
# Imported without --max-deflection the commands are not written: the import's warning is kept in
# sensor_log.yaml's notes, and tern sysid's error names it (the user who missed it at import time
# learns there what to do)
"$tern" import dataflash "$work/log.bin" "$work/no_throws" > /dev/null 2>&1
grep -q '^  - "import warning: .*no actuators.csv written without --max-deflection A E R' "$work/no_throws/sensor_log.yaml" ||
  { echo "sensor_log.yaml keeps no import warning of the missing commands"; exit 1; }
if err=$("$tern" sysid "$work/no_throws" --aircraft "$src/configs/aircraft/aerosonde.yaml" --out "$work/sysid" 2>&1); then
  echo "tern sysid ran without a commands table"; exit 1
fi
[[ $(printf '%s\n' "$err" | wc -l) -eq 1 && $err == *"actuators.csv: no such table"*"sensor_log.yaml: import warning:"*"--max-deflection A E R"* ]] ||
  { echo "tern sysid's error does not name the import's warning: $err"; exit 1; }
echo "without --max-deflection: the import's warning kept and named by tern sysid"
