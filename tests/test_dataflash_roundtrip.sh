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
