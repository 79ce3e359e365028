#!/bin/sh
# The arm64 -dev packages that apt cannot install next to their amd64 build (not "Multi-Arch:
# same" in bookworm): downloaded with apt-get download and unpacked into DIR (the cross build's
# TERN_ARM64_EXTRA_PREFIX is DIR/usr; cmake/toolchain-aarch64-linux-gnu.cmake). Their shared
# libraries come from the ordinary multiarch runtime packages (libyaml-cpp0.7:arm64,
# libgeographiclib23:arm64), which `make arm64` installs: the unpacked -dev symlinks are pointed
# at those, and the unpacked static archives are removed so that the link takes the shared ones.
#   usage: extra_dev.sh DIR PACKAGE:RUNTIME_PACKAGE ...
set -eu
dir=$1
shift
lib=usr/lib/aarch64-linux-gnu
mkdir -p "$dir/debs"
for pair in "$@"; do
  dev=${pair%%:*}
  runtime=${pair#*:}
  deb=$(ls "$dir"/debs/${dev}_*_arm64.deb 2>/dev/null | head -1 || true)
  if [ -z "$deb" ]; then
    (cd "$dir/debs" && apt-get download "$dev:arm64")
    deb=$(ls "$dir"/debs/${dev}_*_arm64.deb | head -1)
  fi
  # the -dev package must be the runtime package's version (its Depends: runtime (= version))
  want=$(dpkg-deb -f "$deb" Version)
  have=$(dpkg-query -W -f='${Version}' "$runtime:arm64" 2>/dev/null || true)
  if [ "$want" != "$have" ]; then
    echo "arm64: $deb is version $want but $runtime:arm64 is '${have:-not installed}'; remove $dir/debs and rerun" >&2
    exit 1
  fi
  dpkg-deb -x "$deb" "$dir"
  # the runtime's shared objects (absolute links), so that the -dev links and CMake's
  # IMPORTED_LOCATION (e.g. libyaml-cpp.so.0.7.0) resolve inside DIR
  dpkg-query -L "$runtime:arm64" | grep "^/$lib/[^/]*\.so[.0-9]*\$" | while read -r so; do
    ln -sfn "$so" "$dir/$lib/$(basename "$so")"
  done
  rm -f "$dir/$lib"/*.a
done
echo "arm64: unpacked into $dir:$(for p in "$@"; do printf ' %s' "${p%%:*}"; done)"
