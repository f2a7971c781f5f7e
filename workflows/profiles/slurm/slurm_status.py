#!/usr/bin/env python3
"""Snakemake cluster-status for Slurm: prints success, running or failed for a job id.

Asks slurmctld (scontrol), then the accounting database (sacct) when the
controller has forgotten the job. When neither knows it, says success and
lets Snakemake check the job's output files: a job whose outputs are missing
still fails the run.
"""
import subprocess
import sys

RUNNING = {"PENDING", "CONFIGURING", "RUNNING", "COMPLETING", "SUSPENDED", "REQUEUED", "RESIZING", "STAGE_OUT",
           "SIGNALING", "REQUEUE_HOLD", "REQUEUE_FED"}


def state_of(job):
    try:
        out = subprocess.run(["scontrol", "show", "job", "-o", job], capture_output=True, text=True, timeout=30)
        if out.returncode == 0 and "JobState=" in out.stdout:
            return out.stdout.split("JobState=")[1].split()[0]
        out = subprocess.run(["sacct", "-n", "-X", "-P", "-o", "State", "-j", job], capture_output=True, text=True,
                             timeout=30)
        if out.returncode == 0 and out.stdout.strip():
            return out.stdout.split()[0]
    except (OSError, subprocess.TimeoutExpired):
        return "RUNNING"  # ask again later
    return "UNKNOWN"


def main():
    state = state_of(sys.argv[1])
    if state == "COMPLETED" or state == "UNKNOWN":
        print("success")
    elif state.rstrip("+") in RUNNING:
        print("running")
    else:
        print("failed")


if __name__ == "__main__":
    main()
