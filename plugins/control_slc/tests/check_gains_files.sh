#!/bin/sh
# The committed gains files are what make_gains_files.sh generates from the aircraft files with
# `tern aero gains` (so configs/gains/README.md's recipe stays true). TERN_AERO: the tern-aero
# program (ctest sets it to the build's).
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
TERN_GAINS_OUT="$tmp" "$root/plugins/control_slc/tools/make_gains_files.sh" > /dev/null
status=0
for f in anaconda.yaml anaconda_tecs.yaml aerosonde.yaml aerosonde_tecs.yaml; do
  if ! diff -u "$root/configs/gains/$f" "$tmp/$f"; then
    echo "configs/gains/$f differs from what make_gains_files.sh generates (rerun it, or edit the script)"
    status=1
  fi
done
exit $status
