#!/usr/bin/env bash
# A single-node Slurm cluster on loopback, for tests/command_line/guide_commands.rs's run of the guide's Slurm
# array job: `cluster.sh start DIR` writes DIR/slurm.conf, starts munged, slurmctld and slurmd
# with everything (state, spool, logs, pid files, munge socket) under DIR, and waits until the
# node takes jobs; `cluster.sh stop DIR` cancels what is left and stops the three daemons.
# Needs root and Debian's slurm-wlm and munge (.ci/run installs them).
set -euo pipefail
cmd="$1"
dir="$(realpath -m "$2")"
conf="$dir/slurm.conf"
case "$cmd" in
start)
    mkdir -p "$dir"/{state,spool,log,munge}
    chown munge:munge "$dir/munge" 2>/dev/null || true
    chmod 755 "$dir/munge"
    # The node claims 64 CPUs (config_overrides), so that an array of 4-CPU tasks runs 16 at a
    # time on a small machine: the test checks scheduling and results, not speed.
    cat > "$conf" <<CONF
ClusterName=rollphase-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=26817
SlurmdPort=26818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
ReturnToService=2
SlurmdParameters=config_overrides
MaxArraySize=1001
NodeName=localhost NodeAddr=127.0.0.1 CPUs=64 RealMemory=1000 State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
    # munged refuses to run as root unless forced; as the munge user it needs its folder.
    if id munge >/dev/null 2>&1; then
        runuser -u munge -- munged --socket="$dir/munge/munge.socket" \
            --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" \
            --seed-file="$dir/munge/munged.seed"
    else
        munged --force --socket="$dir/munge/munge.socket" --pid-file="$dir/munge/munged.pid" \
            --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed"
    fi
    export SLURM_CONF="$conf"
    slurmctld -f "$conf"
    slurmd -f "$conf"
    for _ in $(seq 1 120); do
        if sinfo -h -o '%t' 2>/dev/null | grep -qE '^(idle|mix|alloc)'; then
            exit 0
        fi
        sleep 0.5
    done
    echo "the test cluster did not come up; logs in $dir/log" >&2
    sinfo >&2 || true
    exit 1
    ;;
stop)
    export SLURM_CONF="$conf"
    scancel --quiet --full -u "$(id -un)" 2>/dev/null || true
    for pid in "$dir/slurmd.pid" "$dir/slurmctld.pid" "$dir/munge/munged.pid"; do
        if [ -s "$pid" ]; then kill "$(cat "$pid")" 2>/dev/null || true; fi
    done
    ;;
*)
    echo "usage: cluster.sh start|stop DIR" >&2
    exit 2
    ;;
esac
