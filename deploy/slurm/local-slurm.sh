#!/bin/bash
# Runs a raydiance render on a real single-node Slurm started here from Debian's packages
# (slurmctld, slurmd, slurm-client, munge; installed with apt-get when missing and we are root):
# a private munged and the two Slurm daemons, all state in a temporary folder, nothing written
# to /etc. Submits deploy/slurm/submit.sh (a job array of SHARES shares plus the dependent
# merge job), waits for the merge, prints each job's end state, and stops the daemons by the
# PIDs it started. One at a time on a machine: a second run alongside did not come up.
#
#   deploy/slurm/local-slurm.sh SCENE OUT [SHARES] [--frames F0..F1] [-- RENDER OPTIONS...]
#
# Exit status: 0 when the merge job completed ($OUT/image.exr, or one frame-NNNN.exr a frame,
# written), 1 when a job failed,
# 77 when Slurm is not installed and cannot be installed here.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
if [ $# -lt 2 ]; then
  sed -n '2,12p' "$0" >&2
  exit 2
fi
scene=$1 out=$2
shift 2
shares=4
case "${1:-}" in
  '' | --*) ;;
  *) shares=$1; shift ;;
esac
frames=()
if [ "${1:-}" = "--frames" ]; then
  frames=(--frames "$2")
  shift 2
fi
if [ "${1:-}" = "--" ]; then
  shift
fi

if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null \
  || ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
  if [ "$(id -u)" != 0 ] || ! command -v apt-get >/dev/null; then
    echo "local-slurm.sh: Slurm is not installed and cannot be installed here (root and apt-get needed)" >&2
    exit 77
  fi
  export DEBIAN_FRONTEND=noninteractive
  packages=(slurmctld slurmd slurm-client munge)
  apt-get install -y -o DPkg::Lock::Timeout=600 "${packages[@]}" >/dev/null 2>&1 \
    || { apt-get update >/dev/null && apt-get install -y -o DPkg::Lock::Timeout=600 "${packages[@]}" >/dev/null; } \
    || { echo "local-slurm.sh: apt-get could not install ${packages[*]}" >&2; exit 77; }
fi

work=$(mktemp -d /tmp/raydiance-slurm.XXXXXX)
chmod 0755 "$work"
pids=()
status=1
stop() {
  if [ "$status" != 0 ] && [ -d "$work/log" ]; then
    mkdir -p "$out" && cp -r "$work/log" "$out/slurm-logs" 2>/dev/null || true
    echo "local-slurm.sh: the daemons' logs are in $out/slurm-logs" >&2
  fi
  # Only the daemons this script started, by their PIDs; all at once (each takes ~2 s).
  if [ ${#pids[@]} -gt 0 ]; then
    kill "${pids[@]}" 2>/dev/null || true
    wait "${pids[@]}" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap stop EXIT
mkdir -p "$work"/{munge-socket,munge-key,state,spool,log}
chmod 0755 "$work/munge-socket"
chmod 0700 "$work/munge-key"
# A private munge: its own key, and a socket in a 0755 folder (munged refuses a 0700 one).
dd if=/dev/urandom of="$work/munge-key/munge.key" bs=1024 count=1 status=none
chmod 0400 "$work/munge-key/munge.key"
socket=$work/munge-socket/munge.sock
munged --foreground --force --socket="$socket" --key-file="$work/munge-key/munge.key" \
  --pid-file="$work/munged.pid" --log-file="$work/log/munged.log" \
  --seed-file="$work/munge-key/munge.seed" >"$work/log/munged.out" 2>&1 &
pids+=($!)

# Ports of our own, so that another Slurm on this machine is left alone.
base=$((20000 + $$ % 20000))
node=$(hostname)
cpus=$(slurmd -C | sed -n 's/.*CPUs=\([0-9]*\).*/\1/p' | head -1)
cat >"$work/slurm.conf" <<CONF
ClusterName=raydiance
SlurmctldHost=$node
SlurmctldPort=$base
SlurmdPort=$((base + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
DependencyParameters=kill_invalid_depend
SchedulerParameters=batch_sched_delay=0
JobCompType=jobcomp/filetxt
JobCompLoc=$work/log/jobcomp.txt
MinJobAge=600
NodeName=$node CPUs=${cpus:-1} State=UNKNOWN
PartitionName=local Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
slurmctld -D -f "$SLURM_CONF" >"$work/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$work/log/slurmd.out" 2>&1 &
pids+=($!)

wait_for() { # seconds, command...: polls until the command succeeds
  local deadline=$((SECONDS + $1))
  shift
  until "$@" >/dev/null 2>&1; do
    if [ $SECONDS -ge $deadline ]; then
      return 1
    fi
    sleep 0.2
  done
}
node_idle() { [ "$(sinfo -h -n "$node" -o %t 2>/dev/null)" = idle ]; }
if ! wait_for 60 node_idle; then
  echo "local-slurm.sh: the Slurm node did not come up; its logs:" >&2
  tail -n 20 "$work"/log/*.log >&2
  exit 1
fi

start=$SECONDS
read -r render merge < <("$here/submit.sh" "$scene" "$out" "$shares" "${frames[@]}" -- "$@")
echo "submitted render array $render ($shares shares) and merge job $merge (afterok:$render)"
job_done() { ! squeue -h -j "$1" 2>/dev/null | grep -q .; }
if ! wait_for 1800 job_done "$merge" || ! wait_for 60 job_done "$render"; then
  echo "local-slurm.sh: the jobs did not finish in 30 minutes" >&2
  exit 1
fi
status=0
for id in "$render" "$merge"; do
  scontrol -o show job "$id" | while read -r line; do
    fields=$(echo "$line" | tr ' ' '\n' | grep -E '^(JobId|ArrayTaskId|JobName|JobState|ExitCode)=' | paste -sd' ')
    echo "  $fields"
  done
done
merge_state=$(scontrol -o show job "$merge" | tr ' ' '\n' | sed -n 's/^JobState=//p')
if [ "$merge_state" != COMPLETED ]; then
  echo "local-slurm.sh: the merge job ended $merge_state; see $out/*.log" >&2
  status=1
fi
echo "Slurm: $shares shares and the merge in $((SECONDS - start)) s"
exit $status
