#!/usr/bin/env bash
# test_sdk_install.sh BUILD_DIR [WORK_DIR]
#
# The installable SDK end to end (issue 10):
#  1. `cmake --install BUILD_DIR` into a temporary prefix: headers, libtern_sdk*.so, the CMake
#     package, `tern` and its extensions, the stock plugins, configs and templates are there,
#     and the installed `tern` runs from the prefix (RPATH $ORIGIN/../lib).
#  2. `tern new-plugin` (through the installed `tern`) writes one project of every kind; they are
#     built out of tree against the prefix alone (one CMake project holding the seven, to build
#     them in one go) and their ctest runs (unit tests, `tern check` and a 10 s `tern fly` of
#     each mission snippet).
#  3. The generated controller flies the default mission's first leg: the installed default
#     mission (sim_aero, estimator_ekf in the loop, path planner, manager and follower; take-off
#     and climb on the stock slc) with the generated controller in cruise, 70 s: it takes over at
#     the start of cruise, waypoints 0 and 1 are passed in order, the fallback never engages and
#     the largest cross-track on the lines stays under 25 m.
# WORK_DIR (default: BUILD_DIR/sdk_install_test, emptied first, removed on success) keeps
# everything for a look. The seven projects build at -O1 (this checks that they build, test and
# fly, not how fast) and through ccache with CCACHE_BASEDIR, so that a re-run is quick.
set -euo pipefail

build="$(cd "${1:?usage: test_sdk_install.sh BUILD_DIR [WORK_DIR]}" && pwd)"
if [ -n "${2:-}" ]; then
  work="$2"; keep=1
else
  work="$build/sdk_install_test"; keep=0
fi
rm -rf "$work"
mkdir -p "$work"
work="$(cd "$work" && pwd)"
prefix="$work/prefix"
fail() { echo "FAIL: $*" >&2; echo "(work directory kept: $work)" >&2; exit 1; }
step() { echo "== $* ($(date +%T))"; }

step "install $build into $prefix"
cmake --install "$build" --prefix "$prefix" > "$work/install.log" 2>&1 || { tail -20 "$work/install.log"; fail "cmake --install"; }

libdir=lib
[ -d "$prefix/lib" ] || libdir="$(cd "$prefix" && ls -d lib* | head -1)"
for f in bin/tern bin/tern-new-plugin bin/tern-plot include/tern/plugin.hpp include/tern/testing/harness.hpp \
         include/tern/msg/state.hpp "$libdir/libtern_sdk.so" "$libdir/libtern_sdk_testing.so" \
         "$libdir/cmake/tern/ternConfig.cmake" "$libdir/cmake/tern/ternConfigVersion.cmake" \
         "$libdir/cmake/tern/ternTargets.cmake" "$libdir/cmake/tern/tern_plugin.cmake" \
         "$libdir/tern/plugins/libtern_sim_aero.so" "$libdir/tern/plugins/libtern_control_slc.so" \
         "$libdir/tern/plugins/libtern_path_follower.so" \
         share/tern/configs/missions/default.yaml share/tern/configs/aircraft/anaconda.yaml \
         share/tern/templates/common/CMakeLists.txt share/tern/templates/controller/src/plugin.cpp \
         share/doc/tern/aircraft-modelling.md share/doc/tern/aero-samples/sample_vspaero.stab \
         share/doc/tern/aero-samples/sample_xflr5.txt share/doc/tern/aero-samples/sample_mass.yaml; do
  [ -e "$prefix/$f" ] || fail "not installed: $f"
done
# every program the build puts next to tern (tern-aero, tern-plot, ...) is installed too
for f in "$build"/bin/tern-*; do
  [ -e "$prefix/bin/$(basename "$f")" ] || fail "not installed: bin/$(basename "$f") (it is in $build/bin)"
done

# The installed tern loads libtern_sdk.so from the prefix.
sdk_resolved="$(ldd "$prefix/bin/tern" | awk '/libtern_sdk/ {print $3}')"
case "$sdk_resolved" in
  "$prefix"/*) ;;
  *) fail "installed tern resolves libtern_sdk.so to '$sdk_resolved', not to the prefix" ;;
esac
# Every installed program starts from the prefix (its RPATH finds libtern_sdk.so there, not in the
# build tree: nothing here sets LD_LIBRARY_PATH): `--help` gets an answer from the program itself
# (its help or its usage line: tern-isolate and tern-campaign-dask are started by tern with
# arguments), never the loader's "error while loading shared libraries" (exit 127) or a Python
# traceback.
for exe in "$prefix"/bin/*; do
  name="$(basename "$exe")"
  status=0
  out="$(env -u LD_LIBRARY_PATH "$exe" --help 2>&1)" || status=$?
  case "$out" in *"error while loading shared libraries"*|*Traceback*) echo "$out"; fail "installed $name does not start" ;; esac
  [ $status -ne 127 ] && [ -n "$out" ] || { echo "$out"; fail "installed $name --help: exit $status, no answer of its own"; }
  if [ "$(head -c 4 "$exe" | tail -c 3)" = ELF ] && ldd "$exe" | grep -q 'not found'; then
    ldd "$exe" | grep 'not found'; fail "installed $name has unresolved libraries"
  fi
done
"$prefix/bin/tern" plugins > "$work/plugins.txt" 2>&1 || { cat "$work/plugins.txt"; fail "installed tern plugins"; }
grep -q "$prefix/$libdir/tern/plugins" "$work/plugins.txt" || fail "installed tern does not search $prefix/$libdir/tern/plugins"

step "generate one plugin of every kind with the installed tern new-plugin"
kinds="controller estimator path_follower path_manager io generic coordination"
mkdir -p "$work/plugins"
{
  echo "cmake_minimum_required(VERSION 3.20)"
  echo "project(tern_sdk_install_test LANGUAGES CXX)"
  echo "enable_testing()"
} > "$work/plugins/CMakeLists.txt"
for k in $kinds; do
  "$prefix/bin/tern" new-plugin "my_$k" --kind "$k" --dir "$work/plugins/$k" > /dev/null || fail "tern new-plugin my_$k --kind $k"
  for f in CMakeLists.txt README.md mission.yaml src/plugin.cpp src/plugin.hpp "tests/test_my_$k.cpp"; do
    [ -f "$work/plugins/$k/$f" ] || fail "tern new-plugin --kind $k did not write $f"
  done
  if grep -rq '@NAME@\|@CLASS@\|@TERN_CONFIGS@\|@KIND@\|@ALGO_SOURCES@' "$work/plugins/$k"; then fail "placeholders left in the $k project"; fi
  echo "add_subdirectory($k)" >> "$work/plugins/CMakeLists.txt"
done
# refused: bad name, unknown kind, non-empty directory
if "$prefix/bin/tern" new-plugin Bad-Name --kind generic --dir "$work/bad" 2> /dev/null; then fail "a bad name was accepted"; fi
if "$prefix/bin/tern" new-plugin ok --kind nope --dir "$work/bad" 2> /dev/null; then fail "an unknown kind was accepted"; fi
if "$prefix/bin/tern" new-plugin ok --kind io --dir "$work/plugins/io" 2> /dev/null; then fail "a non-empty directory was overwritten"; fi

step "build the seven projects out of tree against the prefix"
gen=()
command -v ninja > /dev/null && gen=(-G Ninja)
launcher=()
if command -v ccache > /dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
  export CCACHE_BASEDIR="$work" CCACHE_NOHASHDIR=1
fi
# Only the prefix: no path into the source or build tree of tern.
cmake -S "$work/plugins" -B "$work/plugins/build" "${gen[@]}" "${launcher[@]}" -DCMAKE_PREFIX_PATH="$prefix" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
  > "$work/configure.log" 2>&1 || { tail -30 "$work/configure.log"; fail "configure of the generated projects"; }
# tern comes from the prefix, and nothing points into tern's source or build tree (the work
# directory itself may be inside the build tree)
tern_dir="$(sed -n 's/^tern_DIR:PATH=//p' "$work/plugins/build/CMakeCache.txt")"
[ "$tern_dir" = "$prefix/$libdir/cmake/tern" ] || fail "find_package(tern) found '$tern_dir', not the prefix"
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
if grep -v -- "$work" "$work/plugins/build/CMakeCache.txt" | grep -q -e "$build" -e "$source_dir/"; then
  fail "the generated projects see tern's source or build tree"
fi
cmake --build "$work/plugins/build" -j 2 > "$work/build.log" 2>&1 || { grep -B2 -A10 -m3 'error' "$work/build.log"; fail "build of the generated projects"; }
# (a sanitizer build's installed libraries pull in the sanitizer runtime, whose own link-time
# notes on tmpnam name libasan/libtsan, not the generated code: not counted)
warnings="$(grep 'warning:' "$work/build.log" | grep -v -E 'lib[at]san\.so[.0-9]*: warning: the use of' || true)"
if [ -n "$warnings" ]; then head -5 <<< "$warnings"; fail "the generated projects compile with warnings"; fi
ctest --test-dir "$work/plugins/build" --output-on-failure -j 2 > "$work/ctest.log" 2>&1 || { cat "$work/ctest.log"; fail "ctest of the generated projects"; }
n_tests="$(grep -c 'Test *#' "$work/ctest.log" || true)"
[ "$n_tests" -eq 21 ] || { cat "$work/ctest.log"; fail "expected 21 tests of the generated projects, ran $n_tests"; }
for k in $kinds; do
  [ -f "$work/plugins/build/plugins/libtern_my_$k.so" ] || fail "libtern_my_$k.so not built in build/plugins"
done

step "fly the default mission's first leg with the generated controller in cruise"
# The generated project's mission.yaml: the installed default mission, unchanged except for the
# generated controller (an instance `ctl` appended to its plugins, named for the cruise phase;
# take-off and climb stay on the stock slc, which is also the fallback), its paths into the prefix.
mission="$work/plugins/controller/mission.yaml"
grep -q "^aircraft: $prefix/share/tern/configs/aircraft/" "$mission" || fail "the generated mission.yaml does not fly the installed aircraft"
diff <(grep -v '^#' "$prefix/share/tern/configs/missions/default.yaml" | sed -e '/^name:/d' -e '/^phases:/d' -e "s| \.\./| $prefix/share/tern/configs/|" -e "s|^  file: |  file: $prefix/share/tern/configs/missions/|") \
     <(grep -v '^#' "$mission" | sed -e '/^name:/d' -e '/^phases:/d' -e '/^plugin_path:/d' -e '/^fallback:/d' -e '/^  - name: ctl$/,/^    params:/d') \
  > "$work/mission.diff" || { cat "$work/mission.diff"; fail "the generated mission.yaml is not the default mission plus the controller"; }
# 84 s: the default mission (seed 1, 12.2 s of preflight: the FCU's 7.7-s boot calibration, the
# estimator's gyro bias converging by 10.2 s and 2 s of passing checks) passes waypoint 0 at ~39 s
# and waypoint 1 at ~80 s, and ends before waypoint 2 (~88 s) and the next long line.
TERN_PLUGIN_PATH="$work/plugins/build/plugins" "$prefix/bin/tern" fly "$mission" --duration 84 \
  --log-dir "$work/runs" -q > "$work/fly.log" 2>&1 || { cat "$work/fly.log"; fail "tern fly of the first leg with the generated controller"; }
run="$(ls -d "$work"/runs/*/ 2> /dev/null | head -1)"
[ -n "$run" ] || { cat "$work/fly.log"; fail "no run directory written"; }
[ -f "$run/summary.json" ] || fail "no summary.json in $run"
python3 - "$run" <<'PY' || fail "the first leg with the generated controller"
import json, os, sys
s = json.load(open(os.path.join(sys.argv[1], "summary.json")))
if s["end_reason"] != "duration":
    sys.exit("the flight ended early: " + s["end_reason"])
if s["instances"]["sim"].get("sim_crashed"):
    sys.exit("the aircraft crashed")
passages = s["metrics"]["waypoint_passages"]
handovers = s["controller_handovers"]
xt = s["instances"]["manager"]["line_cross_track_max_m"]
print("handovers:", ", ".join(f"{h['from']} -> {h['to']} at {h['t_s']:.1f} s ({h['reason']})" for h in handovers))
print("waypoints:", ", ".join(f"{p['waypoint']} at {p['t_s']:.1f} s" for p in passages))
print(f"fallback engaged: {s['fallback_engaged']}; max cross-track on the lines: {xt:.1f} m")
# the generated controller had the aircraft before waypoint 0 and kept it: handed over once, at
# the start of cruise, and never handed back to the fallback
# (the preflight's hold, slc -> (none) -> slc before the takeoff, is not a handover to ctl)
flying = [h for h in handovers if "(none)" not in (h["from"], h["to"])]
to_ctl = [h for h in flying if h["to"] == "ctl"]
if len(flying) != 1 or len(to_ctl) != 1 or to_ctl[0]["reason"] != "phase cruise":
    sys.exit("expected one handover slc -> ctl at the start of cruise")
if s["fallback_engaged"]:
    sys.exit("the fallback controller took over")
if [p["waypoint"] for p in passages[:2]] != [0, 1]:
    sys.exit("waypoints 0 and 1 not passed in that order")
if to_ctl[0]["t_s"] >= passages[0]["t_s"]:
    sys.exit("the generated controller took over only after waypoint 0")
# The bound: the stock control_slc in cruise flies the same 70 s (same mission and seed) at
# 15.6 m of largest cross-track, all of it on the line 0 -> 1 just after the near-reversal at
# waypoint 0 (12-19 m over seeds 1-8); the template controller at 6.5 m (5-8 m). 25 m is the
# stock figure with 60 % to spare: a controller that holds the line about as well as the stock
# one passes; a course loop that oscillates, diverges or has a sign wrong (hundreds of metres
# on an 800 m line) does not.
if not xt <= 25.0:
    sys.exit(f"max cross-track {xt:.1f} m on the first leg exceeds 25 m")
PY

step "the installed tern plot (its modules in share/tern/plot) draws the flight"
"$prefix/bin/tern" plot "$run" > "$work/plot.log" 2>&1 || { cat "$work/plot.log"; fail "tern plot of the first leg"; }
for f in actuators.png estimation_errors.png index.html; do
  [ -s "$run/plots/$f" ] || { cat "$work/plot.log"; fail "tern plot wrote no plots/$f"; }
done

echo "PASS: SDK installed, 7 template kinds built and tested out of tree, generated controller flew the default mission's first leg"
[ $keep -eq 1 ] || rm -rf "$work"
