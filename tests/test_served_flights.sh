#!/usr/bin/env bash
# Flight N on a served host is flight 1 on a fresh host (issue 45), as a user gets there:
#   tern fly CONFIG                       a fresh host's first flight
#   tern serve CONFIG; tern remote fly x3 three flights on one host
#   tern swap INSTANCE PLUGIN; fly        a hot swap back to the same plugin, one more flight
# Every flight's tables (topics/*.csv, params.csv) and summary.json must be byte-identical to the fresh
# flight's. What only describes the host's run (timing.json: wall time and the host's flight
# number; tern.log) is not compared.
#
# usage: test_served_flights.sh TERN CONFIG DURATION_S SWAP_INSTANCE SWAP_PLUGIN
set -euo pipefail
tern=$1 config=$2 duration=$3 swap_instance=$4 swap_plugin=$5

work=$(mktemp -d "${TMPDIR:-/tmp}/tern-served-XXXXXX")
sock=$work/serve.sock
server=
cleanup() {
  if [ -n "$server" ] && kill -0 "$server" 2>/dev/null; then
    "$tern" remote quit --socket "$sock" >/dev/null 2>&1 || kill "$server" 2>/dev/null || true
    wait "$server" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup EXIT

"$tern" fly "$config" --duration "$duration" --log-dir "$work/fresh" -q >/dev/null
fresh=$(ls -1d "$work"/fresh/*/)

# No server: a client waits --wait seconds, then says so in one line.
t0=$(date +%s%N)
if reply=$("$tern" remote status --socket "$work/nobody.sock" --wait 0.5 2>&1); then
  echo "$reply"; echo "FAIL: remote status answered without a server"; exit 1
fi
elapsed_ms=$(( ($(date +%s%N) - t0) / 1000000 ))
case "$reply" in *"no tern serve is listening at $work/nobody.sock after waiting 0.5 s"*) ;;
  *) echo "$reply"; echo "FAIL: remote status without a server: unexpected message"; exit 1 ;; esac
[ "$elapsed_ms" -ge 500 ] || { echo "FAIL: remote status gave up after $elapsed_ms ms, before its 0.5-s wait"; exit 1; }

# As the README writes it: the server in the background, the first command at once (the client
# waits for the starting server).
"$tern" serve "$config" --socket "$sock" --log-dir "$work/served" >"$work/serve.log" 2>&1 &
server=$!

fly() {
  local reply
  reply=$("$tern" remote fly "$duration" --socket "$sock") || { echo "$reply"; echo "FAIL: remote fly ($1)"; exit 1; }
  echo "$1: ${reply%%$'\n'*}"
}
fly "served flight 1"
fly "served flight 2"
fly "served flight 3"
"$tern" swap "$swap_instance" "$swap_plugin" --socket "$sock"
fly "after swapping $swap_instance back to $swap_plugin"
"$tern" remote quit --socket "$sock" >/dev/null
wait "$server"
server=

tables() { (cd "$1" && { find . -name '*.csv'; echo ./summary.json; } | sort); }
mapfile -t compared < <(tables "$fresh")
[ "${#compared[@]}" -gt 2 ] || { echo "FAIL: the fresh flight wrote no topic tables"; exit 1; }
failed=0
n=0
for run in $(ls -1d "$work"/served/*/ | sort); do
  n=$((n + 1))
  mapfile -t files < <(tables "$run")
  if [ "${files[*]}" != "${compared[*]}" ]; then
    echo "FAIL: served flight $n wrote other files than the fresh flight"
    diff <(printf '%s\n' "${compared[@]}") <(printf '%s\n' "${files[@]}") || true
    failed=1
    continue
  fi
  for f in "${compared[@]}"; do
    if ! cmp -s "$fresh/$f" "$run/$f"; then
      echo "FAIL: served flight $n: $f differs from the fresh flight's; first difference:"
      diff "$fresh/$f" "$run/$f" | head -4 || true
      failed=1
    fi
  done
done
[ "$n" -eq 4 ] || { echo "FAIL: $n served flights logged, 4 expected"; exit 1; }
[ "$failed" -eq 0 ] || exit 1
echo "served flights 1-3 and the flight after the swap: ${#compared[@]} files each, byte-identical to a fresh host's flight 1"
