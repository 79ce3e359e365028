#!/usr/bin/env bash
# test_sdk_install.sh BUILD_DIR [WORK_DIR]
#
# The installable SDK end to end (issue 10):
#  1. `cmake --install BUILD_DIR` into a temporary prefix: headers, libtern_sdk*.so, the CMake
#     package, `tern` and its extensions, the stock plugins, configs and templates are there,
#     and the installed `tern` runs from the prefix (RPATH $ORIGIN/../lib).
#  2. `tern new-plugin` (through the installed `tern`) writes one project of every kind; they are
#     built out of tree against the prefix alone (one CMake project holding the six, to build
#     them in one go) and their ctest runs (unit tests, `tern check` and a 10 s `tern fly` of
#     each mission snippet).
#  3. The generated controller flies 20 s of simulated flight (sim_aero, truth as state): the
#     run ends normally, the log is written, the aircraft stays airborne and near wings level.
# WORK_DIR (default: BUILD_DIR/sdk_install_test, emptied first, removed on success) keeps
# everything for a look. The six projects build at -O1 (this checks that they build, test and
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
         share/tern/templates/controller/CMakeLists.txt; do
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
"$prefix/bin/tern" plugins > "$work/plugins.txt" 2>&1 || { cat "$work/plugins.txt"; fail "installed tern plugins"; }
grep -q "$prefix/$libdir/tern/plugins" "$work/plugins.txt" || fail "installed tern does not search $prefix/$libdir/tern/plugins"

step "generate one plugin of every kind with the installed tern new-plugin"
kinds="controller estimator path_follower path_manager io generic"
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
  if grep -rq '@NAME@\|@CLASS@\|@TERN_CONFIGS@' "$work/plugins/$k"; then fail "placeholders left in the $k project"; fi
  echo "add_subdirectory($k)" >> "$work/plugins/CMakeLists.txt"
done
# refused: bad name, unknown kind, non-empty directory
if "$prefix/bin/tern" new-plugin Bad-Name --kind generic --dir "$work/bad" 2> /dev/null; then fail "a bad name was accepted"; fi
if "$prefix/bin/tern" new-plugin ok --kind nope --dir "$work/bad" 2> /dev/null; then fail "an unknown kind was accepted"; fi
if "$prefix/bin/tern" new-plugin ok --kind io --dir "$work/plugins/io" 2> /dev/null; then fail "a non-empty directory was overwritten"; fi

step "build the six projects out of tree against the prefix"
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
if grep -q 'warning:' "$work/build.log"; then grep -m5 'warning:' "$work/build.log"; fail "the generated projects compile with warnings"; fi
ctest --test-dir "$work/plugins/build" --output-on-failure -j 2 > "$work/ctest.log" 2>&1 || { cat "$work/ctest.log"; fail "ctest of the generated projects"; }
n_tests="$(grep -c 'Test *#' "$work/ctest.log" || true)"
[ "$n_tests" -eq 18 ] || { cat "$work/ctest.log"; fail "expected 18 tests of the generated projects, ran $n_tests"; }
for k in $kinds; do
  [ -f "$work/plugins/build/plugins/libtern_my_$k.so" ] || fail "libtern_my_$k.so not built in build/plugins"
done

step "fly the generated controller for 20 s in sim_aero"
cat > "$work/fly_controller.yaml" <<EOF
name: sdk_controller
seed: 3
duration: 20
aircraft: $prefix/share/tern/configs/aircraft/anaconda.yaml
plugin_path: [plugins/build/plugins]
plugins:
  - name: sim
    plugin: sim_aero
    rate: 400
    params: {init_mode: air, init_altitude: 100.0, init_airspeed: 15.0, init_heading: 0.5, turbulence: light}
    remap: {truth: state}
  - name: ctl
    plugin: my_controller
    rate: 100
phases: {takeoff: ctl, climb: ctl, cruise: ctl}
EOF
"$prefix/bin/tern" fly "$work/fly_controller.yaml" --log-dir "$work/runs" -q > "$work/fly.log" 2>&1 || { cat "$work/fly.log"; fail "tern fly with the generated controller"; }
run="$(ls -d "$work"/runs/*/ 2> /dev/null | head -1)"
[ -n "$run" ] || { cat "$work/fly.log"; fail "no run directory written"; }
[ -f "$run/summary.json" ] || fail "no summary.json in $run"
python3 - "$run" <<'PY' || fail "the flight with the generated controller"
import csv, glob, json, math, os, sys
run = sys.argv[1]
summary = json.load(open(os.path.join(run, "summary.json")))
text = json.dumps(summary)
if '"sim_crashed": true' in text or '"sim_crashed": 1' in text:
    sys.exit("the aircraft crashed: " + text[:400])
# the state topic (truth remapped): last 5 s near wings level, airborne, airspeed near 17 m/s
files = [f for f in glob.glob(os.path.join(run, "**", "*"), recursive=True)
         if os.path.basename(f).startswith("state") and f.endswith(".csv")]
if not files:
    sys.exit("no state log in " + run + ": " + ", ".join(sorted(os.listdir(run))))
# columns are "name [unit]"
rows = [{k.split(" [")[0]: v for k, v in r.items()} for r in csv.DictReader(open(files[0]))]
t = [float(r["t"]) for r in rows]
if t[-1] < 19.0:
    sys.exit(f"the flight ended at {t[-1]:.1f} s")
tail = [r for r, x in zip(rows, t) if x >= t[-1] - 5.0]
phi = max(abs(float(r["phi"])) for r in tail)
h = min(-float(r["p_d"]) for r in rows)
Va = sum(float(r["Va"]) for r in tail) / len(tail)
print(f"last 5 s: max |phi| {phi:.3f} rad, mean Va {Va:.2f} m/s; lowest altitude {h:.1f} m")
if phi > 0.1 or h < 50.0 or abs(Va - 17.0) > 1.5:
    sys.exit("not holding wings level and airspeed")
PY

echo "PASS: SDK installed, 6 template kinds built and tested out of tree, generated controller flew 20 s"
[ $keep -eq 1 ] || rm -rf "$work"
