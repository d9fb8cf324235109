# A throwaway one-node Slurm cluster on 127.0.0.1, for tests and benchmarks.
# Source this file, then `slurm_start DIR` and `slurm_stop`. Needs root and
# Debian's slurm-wlm and munge; uses no systemd and no cgroups. Everything
# (munge key, socket, config, state, logs, PID files) lives in DIR.

slurm_start() {
    SLURM_DIR=$1
    mkdir -p "$SLURM_DIR/munge" "$SLURM_DIR/state" "$SLURM_DIR/spool"
    chmod 700 "$SLURM_DIR" "$SLURM_DIR/munge"
    # A private munge key and daemon: slurm authenticates through it.
    dd if=/dev/urandom of="$SLURM_DIR/munge/munge.key" bs=1024 count=1 status=none
    chmod 400 "$SLURM_DIR/munge/munge.key"
    munged --force --key-file="$SLURM_DIR/munge/munge.key" \
        --socket="$SLURM_DIR/munge/munge.socket" \
        --pid-file="$SLURM_DIR/munge/munged.pid" \
        --log-file="$SLURM_DIR/munge/munged.log" \
        --seed-file="$SLURM_DIR/munge/munged.seed"
    # The node as slurmd sees the hardware (CPUs, sockets, cores, threads):
    # a node configured with more cores than slurmd finds is drained
    # ("Low socket*core count"), e.g. CPUs=$(nproc) on a machine whose
    # CPUs are hyperthreads.
    local hw
    hw=$(slurmd -C 2>/dev/null | head -n1 |
        grep -oE '\b(CPUs|Boards|SocketsPerBoard|CoresPerSocket|ThreadsPerCore)=[0-9]+' |
        paste -sd ' ')
    [ -n "$hw" ] || hw="CPUs=$(nproc)"
    cat >"$SLURM_DIR/slurm.conf" <<CONF
ClusterName=spar-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=${SLURM_TEST_PORT:-16817}
SlurmdPort=$(( ${SLURM_TEST_PORT:-16817} + 1 ))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$SLURM_DIR/munge/munge.socket
StateSaveLocation=$SLURM_DIR/state
SlurmdSpoolDir=$SLURM_DIR/spool
SlurmctldPidFile=$SLURM_DIR/slurmctld.pid
SlurmdPidFile=$SLURM_DIR/slurmd.pid
SlurmctldLogFile=$SLURM_DIR/slurmctld.log
SlurmdLogFile=$SLURM_DIR/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$SLURM_DIR/jobcomp.txt
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=2
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
MinJobAge=3600
KillWait=5
MailProg=/bin/true
NodeName=localhost NodeAddr=127.0.0.1 $hw State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
    export SLURM_CONF=$SLURM_DIR/slurm.conf
    slurmctld -f "$SLURM_CONF"
    slurmd -f "$SLURM_CONF" -N localhost
    local i
    for i in $(seq 60); do
        if [ "$(sinfo -h -o %T 2>/dev/null)" = idle ]; then
            return 0
        fi
        sleep 0.5
    done
    echo "slurm did not come up; logs:" >&2
    tail -n 30 "$SLURM_DIR"/*.log "$SLURM_DIR"/munge/munged.log >&2
    return 1
}

# Stops the daemons by their PID files and waits for them to exit.
slurm_stop() {
    local f pid
    for f in "$SLURM_DIR/slurmd.pid" "$SLURM_DIR/slurmctld.pid" "$SLURM_DIR/munge/munged.pid"; do
        [ -s "$f" ] || continue
        pid=$(cat "$f")
        kill "$pid" 2>/dev/null || continue
        for _ in $(seq 50); do
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.1
        done
    done
}

# Waits until none of the given job ids is pending or running (polling
# squeue; `sbatch --wait` lags). Fails after $2 seconds.
slurm_wait() {
    local jobs=$1 timeout=$2 t=0
    while [ -n "$(squeue -h -j "$jobs" 2>/dev/null)" ]; do
        sleep 1
        t=$((t + 1))
        if [ "$t" -ge "$timeout" ]; then
            echo "jobs $jobs still queued after ${timeout}s:" >&2
            squeue >&2
            return 1
        fi
    done
}

# One line per job (each array task on its own): "TASK STATE EXIT", TASK
# the array index or - for a plain job.
slurm_states() {
    scontrol show job -o "$1" | while read -r line; do
        local task state code
        task=$(grep -oE ' ArrayTaskId=[0-9]+' <<<"$line" | cut -d= -f2)
        state=$(grep -oE ' JobState=[A-Z_]+' <<<"$line" | cut -d= -f2)
        code=$(grep -oE ' ExitCode=[0-9:]+' <<<"$line" | cut -d= -f2)
        echo "${task:--} $state $code"
    done | sort -n
}
