#!/usr/bin/env bash
# Starts a one-node Slurm cluster on this machine (munged, slurmctld, slurmd,
# configuration from tests/slurm/slurm.conf.in in a temporary folder), runs
# the tiny campaign tests/slurm/tiny.json through workflows/profiles/slurm,
# checks that its steps ran as Slurm jobs, that a second run submits nothing
# and that the campaign report equals a local run's, and stops the daemons it
# started. Exits 77 (ctest: SKIPPED) with the
# reason when Slurm cannot start here: not root, packages missing, a daemon
# that does not come up.
# Usage: tests/slurm/run_campaign.sh ROVERLAB_EXE
set -euo pipefail
roverlab=$1
here=$(cd "$(dirname "$0")" && pwd)

skip() {
  echo "SKIPPED: $*"
  exit 77
}

[ "$(id -u)" -eq 0 ] || skip "starting slurmd and munged needs root"
for program in munged slurmctld slurmd sbatch scontrol sinfo snakemake; do
  command -v "$program" >/dev/null || skip "$program is not installed (scripts/install-deps installs slurm-wlm, munge, snakemake)"
done

work=$(mktemp -d /tmp/roverlab-slurm.XXXXXX)
chmod 755 "$work"
cleanup() {
  local status=$?
  for pidfile in "$work/slurmd.pid" "$work/slurmctld.pid" "$work/munge/munged.pid"; do
    if [ -s "$pidfile" ]; then kill "$(cat "$pidfile")" 2>/dev/null || true; fi
  done
  sleep 1
  if [ "${KEEP_SLURM_TEST:-0}" = 1 ]; then echo "kept $work"; else rm -rf "$work"; fi
  exit "$status"
}
trap cleanup EXIT

show_logs() {
  for f in "$work"/munge/munged.log "$work"/slurmctld.log "$work"/slurmd.log; do
    [ -f "$f" ] && { echo "--- $f"; tail -20 "$f"; }
  done
  return 0
}

# munge: a fresh key and a socket of our own.
mkdir -p "$work/munge" "$work/state" "$work/spool"
chmod 700 "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
if ! munged --force --key-file="$work/munge/munge.key" --socket="$work/munge/munge.socket" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/munge/munged.log" \
  --seed-file="$work/munge/munged.seed" 2>"$work/munge/start.err"; then
  show_logs
  skip "munged does not start here: $(head -1 "$work/munge/start.err")"
fi

node=$(hostname -s)
# Ports of our own (so a real Slurm on this machine is left alone), chosen by this shell's pid.
ctld_port=$((20000 + $$ % 20000))
slurmd_port=$((ctld_port + 1))
cpus=$(nproc)
sed -e "s|@WORK@|$work|g" -e "s|@NODE@|$node|g" -e "s|@CTLD_PORT@|$ctld_port|g" \
  -e "s|@SLURMD_PORT@|$slurmd_port|g" -e "s|@CPUS@|$cpus|g" "$here/slurm.conf.in" >"$work/slurm.conf"
export SLURM_CONF=$work/slurm.conf

if ! slurmctld -c -i 2>"$work/slurmctld.err"; then
  show_logs
  skip "slurmctld does not start here: $(head -1 "$work/slurmctld.err")"
fi
if ! slurmd -N "$node" 2>"$work/slurmd.err"; then
  show_logs
  skip "slurmd does not start here: $(head -1 "$work/slurmd.err")"
fi

# Wait (30 s at most) for the node to take jobs.
state=""
for _ in $(seq 60); do
  state=$(sinfo -h -n "$node" -o %T 2>/dev/null | head -1 || true)
  [ "$state" = idle ] && break
  sleep 0.5
done
if [ "$state" != idle ]; then
  show_logs
  skip "the Slurm node did not become idle (state '$state')"
fi
echo "slurm: node $node idle, controller on port $ctld_port"

# The campaign, each step a Slurm job; the campaign report runs locally.
out=$work/campaign
if ! "$roverlab" campaign "$here/tiny.json" -o "$out" --profile slurm; then
  show_logs
  echo "FAILED: the campaign did not finish through Slurm"
  exit 1
fi
jobs=$(find "$out/.snakemake" -maxdepth 1 -name 'slurm-*.txt' | wc -l)
runs=$(find "$out/runs" -name run.json | wc -l)
echo "slurm: $runs runs, $jobs Slurm job logs"
[ "$runs" -eq 2 ] || { echo "FAILED: expected 2 runs, got $runs"; exit 1; }
# Two steps per run (log, report) went through sbatch; provenance and the campaign report are local.
[ "$jobs" -eq 4 ] || { echo "FAILED: expected 4 Slurm jobs, got $jobs"; exit 1; }
[ -s "$out/report/index.html" ] || { echo "FAILED: no campaign report"; exit 1; }
grep -q '"roverlab-campaign-report"' "$out/report/campaign.json" || { echo "FAILED: campaign.json"; exit 1; }
# A second run submits nothing.
"$roverlab" campaign "$here/tiny.json" -o "$out" --profile slurm 2>&1 | tee "$work/second.txt"
grep -q "Nothing to be done" "$work/second.txt" || { echo "FAILED: the second run did work"; exit 1; }
# The same campaign run locally gives the same campaign report (paths aside).
local=$work/local
"$roverlab" campaign "$here/tiny.json" -o "$local" >/dev/null ||
  { echo "FAILED: the local campaign did not finish"; exit 1; }
if ! diff <(sed "s|$out|OUT|g" "$out/report/campaign.json") <(sed "s|$local|OUT|g" "$local/report/campaign.json") \
  >"$work/report.diff"; then
  echo "FAILED: the campaign report through Slurm differs from the local one:"
  head -20 "$work/report.diff"
  exit 1
fi
echo "PASSED: a campaign through Slurm, its report identical to the local run's"
