#!/usr/bin/env bash
# scripts/build-jobs: one compile job per core, no more than one per 1.5 GiB of
# available memory, at least one; $ROVERLAB_BUILD_JOBS wins, and a value that
# is not a number of jobs is refused in one line naming it, with exit code 2.
set -uo pipefail
jobs_script="$(dirname "$0")/../../scripts/build-jobs"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
failures=0
expect() {  # expect WHAT WANTED GOT
  if [ "$2" != "$3" ]; then
    echo "FAIL: $1: wanted '$2', got '$3'"
    failures=$((failures + 1))
  fi
}
meminfo() { printf 'MemTotal:       25000000 kB\nMemFree:         1000000 kB\nMemAvailable:   %s kB\n' "$1" > "$tmp/meminfo"; }

unset ROVERLAB_BUILD_JOBS
# The cores: taskset limits what nproc counts, to the first one or two of the
# cores this process may use.
cpus=()
IFS=, read -ra ranges <<< "$(awk '/^Cpus_allowed_list/ { print $2 }' /proc/self/status)"
for range in "${ranges[@]}"; do
  for cpu in $(seq "${range%-*}" "${range#*-}"); do cpus+=("$cpu"); done
done
one=${cpus[0]}
meminfo 25000000
expect "one core, 24 GB" 1 "$(taskset -c "$one" "$jobs_script" "$tmp/meminfo")"
if [ "${#cpus[@]}" -ge 2 ]; then
  two="${cpus[0]},${cpus[1]}"
  expect "two cores, 24 GB" 2 "$(taskset -c "$two" "$jobs_script" "$tmp/meminfo")"
  # The memory: 2.5 GiB holds one job of 1.5 GiB, not two; 3 GiB holds two.
  meminfo 2621440
  expect "two cores, 2.5 GiB" 1 "$(taskset -c "$two" "$jobs_script" "$tmp/meminfo")"
  meminfo 3145728
  expect "two cores, 3 GiB" 2 "$(taskset -c "$two" "$jobs_script" "$tmp/meminfo")"
fi
meminfo 100000
expect "one core, 100 MB: still one job" 1 "$(taskset -c "$one" "$jobs_script" "$tmp/meminfo")"
# No meminfo to read: the cores alone.
expect "one core, no meminfo" 1 "$(taskset -c "$one" "$jobs_script" "$tmp/absent")"
# The environment variable wins over both; empty counts as unset.
expect "ROVERLAB_BUILD_JOBS=12" 12 "$(ROVERLAB_BUILD_JOBS=12 taskset -c "$one" "$jobs_script" "$tmp/meminfo")"
expect "ROVERLAB_BUILD_JOBS empty" 1 "$(ROVERLAB_BUILD_JOBS= taskset -c "$one" "$jobs_script" "$tmp/meminfo")"
for bad in 0 -1 2.5 abc 257 0003 "4 jobs"; do
  out=$(ROVERLAB_BUILD_JOBS="$bad" "$jobs_script" 2>"$tmp/err")
  rc=$?
  expect "ROVERLAB_BUILD_JOBS='$bad': exit code" 2 "$rc"
  expect "ROVERLAB_BUILD_JOBS='$bad': nothing printed" "" "$out"
  expect "ROVERLAB_BUILD_JOBS='$bad': one line of error" 1 "$(wc -l < "$tmp/err")"
  grep -qF "ROVERLAB_BUILD_JOBS: '$bad'" "$tmp/err" || { echo "FAIL: the error does not name '$bad': $(cat "$tmp/err")"; failures=$((failures + 1)); }
done
[ "$failures" -eq 0 ] && echo "build-jobs: all cases passed"
exit $((failures > 0))
