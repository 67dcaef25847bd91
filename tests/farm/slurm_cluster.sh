#!/usr/bin/env bash
# A one-node Slurm cluster for as long as a command runs (the `farm` CTest label):
#   bash tests/farm/slurm_cluster.sh COMMAND [ARGS...]
# Starts munged (unless one already answers), slurmctld and slurmd in the foreground
# from a config in a temporary folder — SLURM_CONF points the daemons and the
# clients at it; /etc/slurm is not touched — runs COMMAND with SLURM_CONF exported,
# and stops the daemons it started, by PID, however COMMAND ends. The config and the
# start-up are the verified ones of ../shared/reference/ecosystem-2.md §5.1
# (batch_sched_delay=0: tasks start at once; ports moved off the defaults).
# Exit 77 (CTest: skipped) when Slurm is not installed or we are not root;
# `bash scripts/setup.sh test` installs slurm-wlm.
set -euo pipefail

for tool in slurmctld slurmd munged munge sbatch squeue sinfo; do
  if ! command -v "$tool" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$tool" ]; then
    echo "slurm_cluster: $tool is missing (bash scripts/setup.sh test installs slurm-wlm): skipped"
    exit 77
  fi
done
if [ "$(id -u)" -ne 0 ]; then
  echo "slurm_cluster: starting Slurm's daemons needs root: skipped"
  exit 77
fi

# One cluster at a time on this machine: its ports are fixed.
exec 9>/tmp/snell-slurm-cluster.lock
flock -w 300 9

W=$(mktemp -d /tmp/snell-slurm.XXXXXX)
chmod 755 "$W"
install -d -o slurm -g slurm "$W/state" "$W/spool" "$W/log"
cat > "$W/slurm.conf" <<CONF
ClusterName=snelltest
SlurmctldHost=localhost
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=slurm
AuthType=auth/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MailProg=/bin/true
ReturnToService=2
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
StateSaveLocation=$W/state
SlurmdSpoolDir=$W/spool
SlurmctldLogFile=$W/log/slurmctld.log
SlurmdLogFile=$W/log/slurmd.log
SlurmctldPidFile=$W/slurmctld.pid
SlurmdPidFile=$W/slurmd.pid
NodeName=localhost CPUs=$(nproc) State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$W/slurm.conf"

pids=()
cleanup() {
  local p
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
  rm -rf "$W"
}
trap cleanup EXIT

if ! munge -n </dev/null >/dev/null 2>&1; then
  install -d -o munge -g munge -m 0755 /run/munge
  setpriv --reuid=munge --regid=munge --init-groups /usr/sbin/munged --foreground \
    >"$W/log/munged.out" 2>&1 &
  pids+=($!)
  for _ in $(seq 50); do munge -n </dev/null >/dev/null 2>&1 && break; sleep 0.1; done
fi
/usr/sbin/slurmctld -D -c -f "$SLURM_CONF" >"$W/log/slurmctld.out" 2>&1 &
pids+=($!)
/usr/sbin/slurmd -D -f "$SLURM_CONF" >"$W/log/slurmd.out" 2>&1 &
pids+=($!)
start=$(date +%s%N)
for _ in $(seq 150); do
  sinfo -h -o %T 2>/dev/null | grep -qx idle && break
  sleep 0.2
done
if ! sinfo -h -o %T 2>/dev/null | grep -qx idle; then
  echo "slurm_cluster: the cluster did not come up in 30 s"
  tail -n 20 "$W"/log/* || true
  exit 1
fi
echo "slurm_cluster: one-node cluster up in $((($(date +%s%N) - start) / 1000000)) ms"
"$@"
