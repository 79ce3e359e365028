#!/usr/bin/env bash
# Hostile inputs (issue 78, docs/hostile-inputs.md), as a user or a stranger's file hands them to
# tern: each is refused with a non-zero exit and one line "tern: error: ..." naming the file, field
# or value; never a signal, a time-out (30 s each), memory beyond 3 GB of address space (ulimit -v)
# or a raw control character on the terminal. And a log never runs code: a flight log holding a
# libtern_estimator_ekf.so and a config.yaml with `plugin_path: [.]` replays with the installed
# estimator, the log's library never loaded (its constructor would write a marker file).
# The inputs are generated small (make_inputs.py); nothing large is committed.
# usage: test_hostile.sh TERN MARKER_LIBRARY REPO_DIR PYTHON3
set -uo pipefail
tern=$1 marker_lib=$2 repo=$3 python=$4
work=$(mktemp -d "${TMPDIR:-/tmp}/tern-hostile-XXXXXX")
trap 'rm -rf "$work"' EXIT
"$python" "$repo/tests/hostile/make_inputs.py" "$repo" "$work" || { echo "FAIL: make_inputs.py"; exit 1; }
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

# A tern built with a sanitizer (make sanitize, make tsan) reserves terabytes of address space for
# its shadow memory: there the bound is 3 GB of resident memory (the runtime's hard_rss_limit_mb,
# a report and a non-zero exit past it) and the time-out is four times longer, as the test's own.
seconds=30 sanitized=
if ldd "$tern" | grep -q 'lib[at]san\.so'; then
  sanitized=1 seconds=120
  export ASAN_OPTIONS="${ASAN_OPTIONS:+$ASAN_OPTIONS:}hard_rss_limit_mb=3000"
  export TSAN_OPTIONS="${TSAN_OPTIONS:+$TSAN_OPTIONS:}hard_rss_limit_mb=3000"
fi

# run NAME CMD...: runs CMD bounded ($seconds s, 3 GB of address space) with its output in
# $work/NAME.*; sets rc.
run() {
  local name=$1
  shift
  rc=0
  ( if [ -z "$sanitized" ]; then ulimit -v 3000000; fi && exec timeout -s KILL "$seconds" "$@") \
    > "$work/$name.out" 2> "$work/$name.err" || rc=$?
}

# refused NAME TEXT CMD...: a non-zero exit that is no signal nor time-out, exactly one error line,
# holding TEXT, and no control character on stderr.
refused() {
  local name=$1 text=$2
  shift 2
  run "$name" "$@"
  local err="$work/$name.err" lines
  lines=$(grep -c '^tern: error: ' "$err")
  if [ "$rc" -eq 0 ]; then
    fail "$name: accepted (exit 0)"
  elif [ "$rc" -ge 124 ]; then
    fail "$name: exit $rc (a signal or the $seconds-s time-out)"
  elif [ "$lines" -ne 1 ]; then
    fail "$name: $lines error lines"
  elif ! grep '^tern: error: ' "$err" | grep -qF -- "$text"; then
    fail "$name: the error does not name '$text': $(grep '^tern: error: ' "$err" | cut -c1-300)"
  elif LC_ALL=C grep -q $'[\x01-\x08\x0b-\x1f\x7f]' "$err"; then
    fail "$name: a raw control character on stderr"
  elif [ "$(wc -L < "$err")" -gt 2000 ]; then
    fail "$name: a line of $(wc -L < "$err") characters"
  else
    echo "ok: $name: $(grep '^tern: error: ' "$err" | cut -c1-220)"
  fi
}

logs=$work/logs configs=$work/configs

# ---- a log never runs code ----------------------------------------------------------------------
cp "$marker_lib" "$logs/code/libtern_estimator_ekf.so"
export TERN_HOSTILE_MARKER=$work/marker
run log_code "$tern" replay "$logs/code" --log-dir "$work/replays" -q
if [ -e "$work/marker" ]; then
  fail "log_code: tern replay loaded the log's libtern_estimator_ekf.so"
elif [ "$rc" -ne 0 ]; then
  fail "log_code: the replay with the installed estimator failed (exit $rc): $(tail -1 "$work/log_code.err")"
else
  echo "ok: log_code: replayed with the installed estimator, the log's library never loaded"
fi
# the control: a plugin path the user sets does load the library (so the marker shows a load)
TERN_PLUGIN_PATH=$logs/code run log_code_control "$tern" replay "$logs/code" --log-dir "$work/replays" -q
[ -e "$work/marker" ] || fail "log_code_control: a library on TERN_PLUGIN_PATH was not loaded: the marker cannot show a load"
rm -f "$work/marker"
refused log_code_path "never loads the library it names" \
  "$tern" replay "$("$python" -c '
import sys, yaml
d = sys.argv[1]
c = yaml.safe_load(open(d + "/config.yaml"))
c.pop("plugin_path")
c["plugins"][0]["plugin"] = "./libtern_estimator_ekf.so"
yaml.safe_dump(c, open(d + "/config.yaml", "w"))
print(d)' "$logs/code")" --log-dir "$work/replays"
[ -e "$work/marker" ] && fail "log_code_path: the library named by path was loaded"

# ---- files that are no files: a directory, /dev/zero ---------------------------------------------
refused waypoints_dev_zero "zero_waypoints.yaml: mission file is not a regular file (a character device)" \
  "$tern" check "$configs/zero_waypoints.yaml"
refused imu_dev_zero "imu.csv: the table is not a regular file (a character device)" "$tern" replay "$logs/zero_imu" --log-dir "$work/replays"
refused mission_directory "dir: config file is a directory" "$tern" check "$work/dir"
refused param_file_directory "dir: parameter file is a directory" "$tern" check "$configs/param_dir.yaml"
refused aircraft_directory "dir: aircraft file is a directory" "$tern" check "$configs/aircraft_dir.yaml"

# ---- time stamps jumping by 1e18 ns from row 4000 (line 4002): one line, no hang -----------------
jump_text="imu.csv:4002: t [s] '1000000010.000000000'"
refused jump_replay "$jump_text" "$tern" replay "$logs/jump" --log-dir "$work/replays"
refused jump_sysid "$jump_text" "$tern" sysid "$logs/jump" --aircraft "$repo/configs/aircraft/anaconda.yaml" --out "$work/sysid"
refused jump_validate "$jump_text" "$tern" validate "$logs/jump" --aircraft "$repo/configs/aircraft/anaconda.yaml" --out "$work/validate"
# a time with two signs (found by fuzz_csv_table: "--880690500" parsed as -880690500 and negated)
cp -r "$logs/jump" "$work/double_sign" && sed -i '4002s/^[^,]*/--880690500/' "$work/double_sign/topics/imu.csv"
refused double_sign "imu.csv:4002: t [s] '--880690500' is not a decimal number" "$tern" replay "$work/double_sign" --log-dir "$work/replays"

# ---- silently wrong, now refused -----------------------------------------------------------------
refused inertia_triangle "bad_inertia.yaml: inertia.Jz:" "$tern" check "$configs/bad_inertia.yaml"
# QGroundControl plans (--plan): /dev/zero, a link to it, a directory, a plan cut short mid-item
ln -s /dev/zero "$work/zero.plan"
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
head -c 700 "$here/../data/qgc_plans/PX4SITL-ArduPlane.plan" > "$work/cut.plan"
refused plan_dev_zero "--plan: /dev/zero: not a file" "$tern" check "$here/../../configs/missions/default.yaml" --plan /dev/zero
refused plan_link_to_zero "zero.plan: not a file" "$tern" check "$here/../../configs/missions/default.yaml" --plan "$work/zero.plan"
refused plan_directory "--plan: $work: not a file" "$tern" check "$here/../../configs/missions/default.yaml" --plan "$work"
refused plan_cut_short "cut.plan: not JSON" "$tern" check "$here/../../configs/missions/default.yaml" --plan "$work/cut.plan"
# ArduPilot DataFlash logs (tern import dataflash): a link to /dev/zero, a log cut short before any
# IMU message, a FMT that gives one label for its three fields
ln -s /dev/zero "$work/zero.bin"
head -c 300 "$repo/tests/fuzz/corpus/fuzz_dataflash/plane.bin" > "$work/cut.bin"
"$python" -c "import sys; f = b'fff'.ljust(16, b'\\0'); sys.stdout.buffer.write(b'\\xa3\\x95\\x80\\x81\\x0f' + b'ABCD' + f + b'a'.ljust(64, b'\\0'))" > "$work/lying_fmt.bin"
refused dataflash_link_to_zero "zero.bin: not a regular file" "$tern" import dataflash "$work/zero.bin" "$work/df_zero"
refused dataflash_cut_short "cut.bin: no IMU messages" "$tern" import dataflash "$work/cut.bin" "$work/df_cut"
refused dataflash_lying_fmt "lying_fmt.bin: byte 0: FMT of type 129 'ABCD': field 'labels': 1 labels for the 3 fields" "$tern" import dataflash "$work/lying_fmt.bin" "$work/df_fmt"
# a run's waypoint list whose count and stamp no list has (tern export plan RUN)
mkdir -p "$work/bad_list/topics"
printf 't [s],stamp [ns],revision [],count [],loop [bool],loops [],immediate [bool]\n0,1e300,1,1000000000,0,0,0\n' > "$work/bad_list/topics/waypoints.csv"
printf 't [s],stamp [ns],revision [],index []\n' > "$work/bad_list/topics/waypoints_items.csv"
refused plan_of_a_bad_list "waypoints.csv: row 2: stamp 1e+300: expected a whole number" "$tern" export plan "$work/bad_list" "$work/bad.plan"
refused inertia_triangle_sysid "bad_inertia.yaml: inertia.Jz:" "$tern" sysid "$logs/good" --aircraft "$work/bad_inertia.yaml" --out "$work/sysid"
refused imu_without_gyro_z "imu.csv:1: no column 'gyro_z'" "$tern" replay "$logs/no_gyro_z" --log-dir "$work/replays"
refused imu_column_twice "imu.csv:1: column 'gyro_x' twice in the header" "$tern" replay "$logs/gyro_x_twice" --log-dir "$work/replays"
refused alfa_symlink_member "member 'seq/carbonZ_2018-07-18-mavros-imu-data_raw.csv' is a symlink" \
  "$tern" import alfa "$work/alfa.tar.gz" "$work/alfa_out"
# a sparse member's holes count: 8 GiB declared in a few hundred bytes (fuzz_archive's finding)
refused alfa_sparse_member "the archive unpacks to more than 4294967296 bytes" \
  "$tern" import alfa "$work/sparse.tar.gz" "$work/sparse_out"
# an mtree listing is no archive tern reads (its members' bytes would come from this machine's files)
refused alfa_mtree "mtree.tar: Unrecognized archive format" "$tern" import alfa "$work/mtree.tar" "$work/mtree_out"
refused alfa_dot_member "dot.tar: member '.' names the archive's top directory, but is no directory" \
  "$tern" import alfa "$work/dot.tar" "$work/dot_out"

# ---- clearer lines ---------------------------------------------------------------------------------
refused alias_bomb "alias_bomb.yaml: more than 100000 YAML nodes" "$tern" check "$configs/alias_bomb.yaml"
refused deep_nesting "deep.yaml:2:10010: YAML nested too deeply" "$tern" check "$configs/deep.yaml"
refused empty_imu "imu.csv: the IMU table has no rows" "$tern" replay "$logs/empty_imu" --log-dir "$work/replays"
refused empty_imu_sysid "imu.csv: the IMU table has no rows" \
  "$tern" sysid "$logs/empty_imu" --aircraft "$repo/configs/aircraft/anaconda.yaml" --out "$work/sysid"
refused noted_sysid "sensor_log.yaml: import warning: log.bin: no actuators.csv written without --max-deflection A E R" \
  "$tern" sysid "$logs/no_actuators_noted" --aircraft "$repo/configs/aircraft/anaconda.yaml" --out "$work/sysid"
refused mcap_chunk_length "chunk declares 4611686018427387904 bytes uncompressed" \
  "$tern" export csv "$work/chunk.mcap" --out "$work/chunk_tables"
refused mcap_bad_crc "bad_crc.mcap: byte 25: chunk's CRC-32 does not match its records" \
  "$tern" export csv "$work/bad_crc.mcap" --out "$work/crc_tables"
refused nan_number "nan_duration.yaml" "$tern" check "$configs/nan_duration.yaml"
refused inf_number "base_rate: expected a number, got '.inf'" "$tern" check "$configs/inf_rate.yaml"
refused list_as_number "duration: expected a number, got <list>" "$tern" check "$configs/list_duration.yaml"
refused self_param_file "self_param.yaml:" "$tern" check "$configs/self_param.yaml"
refused key_twice "key 'duration' given twice (first at line" "$tern" check "$configs/dup_key.yaml"
refused fleet_key_list "fleet_dds_key.yaml:2:3: dds: a key is a name, got a list" "$tern" check "$configs/fleet_dds_key.yaml"
refused plugin_not_elf "libtern_estimator_ekf.so': not an ELF file" "$tern" check "$configs/not_elf_plugin.yaml"
truncated="$work/plugins_cut"  # the first 5000 bytes of a built plugin: an interrupted copy
mkdir -p "$truncated" && head -c 5000 "$(dirname "$tern")/../plugins/libtern_control_slc.so" > "$truncated/libtern_control_slc.so"
TERN_PLUGIN_PATH="$truncated" refused plugin_truncated "libtern_control_slc.so': truncated" "$tern" check "$repo/configs/missions/default.yaml"
refused utf16_table "imu.csv:1: the first column must be 't [s]'" "$tern" replay "$logs/utf16_imu" --log-dir "$work/replays"
refused baro_in_hpa "baro.csv: the pressure's median is 850 Pa" "$tern" replay "$logs/baro_hpa" --log-dir "$work/replays"
refused stamp_in_us "imu.csv:403: stamp 1002500 ns is -1.0015 s from t 1.0025 s" "$tern" replay "$logs/stamp_us" --log-dir "$work/replays"
refused semicolons "imu.csv:1: the header's cells are separated by ';'" "$tern" replay "$logs/semicolons" --log-dir "$work/replays"
refused too_many_columns "imu.csv:5: expected 8 values, got 11 (more cells than the header names)" "$tern" replay "$logs/wide_row" --log-dir "$work/replays"
refused control_characters "name: '\\x1b[31mred\\x07'" "$tern" check "$configs/escape.yaml"
refused long_name "aaaa..." "$tern" check "$configs/long_name.yaml"

if [ "$failures" -ne 0 ]; then
  echo "hostile: $failures failure(s)"
  exit 1
fi
echo "hostile: every input answered in one line"
