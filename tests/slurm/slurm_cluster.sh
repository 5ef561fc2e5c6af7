#!/bin/bash
# slurm_cluster.sh - throw-away single-node Slurm cluster for tests.
#
#   slurm_cluster.sh start DIR   start munged + slurmctld + slurmd, all state under DIR;
#                                on success print "export SLURM_CONF=DIR/slurm.conf"
#   slurm_cluster.sh stop DIR    stop the daemons started by "start DIR"
#
# Nothing outside DIR is written (no /etc/slurm, /etc/munge, /run, /var).
# On failure "start" prints ONE line "slurm_cluster: cannot start: <reason>" on
# stderr, stops whatever it had started and exits non-zero, so that a test
# can skip with a visible message.  Daemon logs stay in DIR/log/.
#
# Written for Slurm 22.05 / MUNGE 0.5 as packaged in Debian 12
# (apt-get install --no-install-recommends slurmctld slurmd slurm-client munge).

set -u

PROG=slurm_cluster
STARTING=        # set once "start" begins launching daemons in DIR
START_TIMEOUT=${SLURM_CLUSTER_TIMEOUT:-30}   # seconds to wait for the node to be idle
# SLURM_CLUSTER_CPUS: CPUs to give the node (default: nproc).

die() {
    echo "$PROG: cannot start: $*" >&2
    # Undo a half-done start (never touch a cluster that was already there).
    [ -n "$STARTING" ] && stop_daemons "$DIR" >/dev/null 2>&1
    exit 1
}

# Last meaningful error line of the given daemon logs (skips the errors that
# every start logs here: missing PMIx library, no state files yet).
last_error() {
    grep -hE 'fatal|error' "$@" 2>/dev/null |
        grep -vE 'pmix|MPI|state file|backup state|No .* state file' | tail -n 1
}

# The first of them: where a daemon fails to initialise, the cause (e.g. "No
# filesystem mounted on /sys/fs/cgroup") comes before "initialization failed".
first_error() {
    grep -hE 'fatal|error' "$@" 2>/dev/null |
        grep -vE 'pmix|MPI|state file|backup state|No .* state file' | head -n 1
}

# Why daemon $1 failed to start: its last line on stdout/stderr, else its log's first error.
start_failure() {
    local why
    why=$(tail -n 1 "$DIR/log/$1.out" 2>/dev/null)
    [ -n "$why" ] || why=$(first_error "$DIR/log/$1.log")
    echo "$why"
}

usage() {
    echo "usage: $0 start DIR | stop DIR" >&2
    exit 2
}

# Is a TCP port free on this machine?  Uses ss when present, /proc otherwise.
port_in_use() {
    local port=$1 hex
    if command -v ss >/dev/null 2>&1; then
        ss -Htan 2>/dev/null | awk '{print $4}' | grep -Eq "[:.]$port\$"
        return
    fi
    hex=$(printf '%04X' "$port")
    cat /proc/net/tcp /proc/net/tcp6 2>/dev/null | awk '{print $2}' | grep -qi ":$hex\$"
}

# Print two consecutive free ports.  A random start in 20000-59999 keeps
# clusters started in parallel (one per test) from picking the same pair;
# the small race between choosing and binding is accepted.
pick_ports() {
    local p
    p=$(( 20000 + (RANDOM * 32768 + RANDOM) % 40000 ))
    for _ in $(seq 1 200); do
        if ! port_in_use "$p" && ! port_in_use $((p + 1)); then
            echo "$p $((p + 1))"
            return 0
        fi
        p=$(( p + 2 ))
        [ "$p" -ge 60000 ] && p=20000
    done
    return 1
}

# Is process $1 alive?  A zombie is not: daemons are re-parented to PID 1,
# which in a container may be slow to reap them, and kill -0 succeeds on a
# zombie.
alive() {
    local st
    case $1 in ''|*[!0-9]*) return 1 ;; esac
    kill -0 "$1" 2>/dev/null || return 1
    st=$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null)
    [ "$st" != Z ] && [ "$st" != X ]
}

# Send TERM to the processes in the given pid files, wait (up to ~15 s) for
# them to go, KILL the ones that are left, remove the pid files.
kill_pidfiles() {
    local f pid pids="" left=""
    for f in "$@"; do
        pid=$(cat "$f" 2>/dev/null)
        case $pid in ''|*[!0-9]*) continue ;; esac
        kill -TERM "$pid" 2>/dev/null && pids="$pids $pid"
    done
    for _ in $(seq 1 150); do
        left=''
        for pid in $pids; do alive "$pid" && left="$left $pid"; done
        [ -z "$left" ] && break
        sleep 0.1
    done
    if [ -n "$left" ]; then
        # shellcheck disable=SC2086  # a list of pids
        kill -KILL $left 2>/dev/null
        sleep 0.2
    fi
    rm -f "$@"
}

# Is process $1 one of this cluster's (working directory or an open file
# under DIR $2)?  slurmstepd's command line and environment name no path.
uses_dir() {
    local f
    for f in "/proc/$1/cwd" "/proc/$1"/fd/*; do
        case $(readlink "$f" 2>/dev/null) in "$2"|"$2"/*) return 0 ;; esac
    done
    return 1
}

# Kill, by session, the job steps left behind by this cluster's slurmd
# (normally none: stop cancels all jobs first).  A slurmstepd outlives
# slurmd by design; ours have slurmd's cwd (DIR/log) and its log open.  The
# batch script and its children share the slurmstepd's session.
kill_orphan_steps() {
    local d=$1 p sid mysid
    command -v pgrep >/dev/null 2>&1 || return 0
    mysid=$(ps -o sid= -p $$ 2>/dev/null | tr -d ' ')
    for p in $(pgrep -x slurmstepd 2>/dev/null); do
        uses_dir "$p" "$d" || continue
        sid=$(ps -o sid= -p "$p" 2>/dev/null | tr -d ' ')
        if [ -n "$sid" ] && [ "$sid" != 0 ] && [ "$sid" != "$mysid" ]; then
            pkill -KILL -s "$sid" 2>/dev/null
        else
            kill -KILL "$p" 2>/dev/null
        fi
    done
}

stop_daemons() {
    local d=$1 jobs
    # Cancel every job first so that slurmd reaps its steps (SIGTERM, then
    # SIGKILL after KillWait), and wait for them to finish (<= ~10 s).
    # (Only with a live controller: clients wait long for a dead one.)
    if alive "$(cat "$d/run/slurmctld.pid" 2>/dev/null)" &&
       [ -f "$d/slurm.conf" ]; then
        export SLURM_CONF=$d/slurm.conf
        jobs=$(timeout 5 squeue -h -o '%A' 2>/dev/null)
        if [ -n "$jobs" ]; then
            # shellcheck disable=SC2086  # a list of job ids
            timeout 5 scancel $jobs 2>/dev/null
            for _ in $(seq 1 50); do
                [ -z "$(timeout 5 squeue -h -o '%A' 2>/dev/null)" ] && break
                sleep 0.2
            done
        fi
    fi
    # All three at once: each takes 1-2 s to exit after SIGTERM, and with
    # no jobs left none of them needs the others while shutting down.
    kill_pidfiles "$d/run/slurmd.pid" "$d/run/slurmctld.pid" "$d/run/munged.pid"
    kill_orphan_steps "$d"
    return 0
}

cmd_stop() {
    [ -d "$DIR" ] || { echo "$PROG: no such directory: $DIR" >&2; exit 1; }
    stop_daemons "$DIR"
}

cmd_start() {
    local b
    export PATH=$PATH:/usr/sbin:/sbin
    for b in munged slurmctld slurmd sinfo squeue sbatch scancel scontrol; do
        command -v "$b" >/dev/null 2>&1 ||
            die "'$b' not found (apt-get install --no-install-recommends slurmctld slurmd slurm-client munge)"
    done
    # slurmd must be root to start job steps as the submitting user, and we
    # use SlurmUser=root so that slurmctld can share it.
    [ "$(id -u)" -eq 0 ] || die "must run as root (slurmd needs root), running as $(id -un)"

    mkdir -p "$DIR" 2>/dev/null || die "cannot create $DIR"
    DIR=$(cd "$DIR" 2>/dev/null && pwd -P) || die "cannot enter $DIR"
    [ -e "$DIR/run/slurmctld.pid" ] && die "$DIR already holds a cluster (run: $0 stop $DIR)"
    mkdir -p "$DIR/munge" "$DIR/state" "$DIR/spool" "$DIR/log" "$DIR/run" ||
        die "cannot create sub-directories of $DIR"
    chmod 0700 "$DIR/munge" "$DIR/state" "$DIR/spool"

    local host cpus mem_kb mem ports ctld_port slurmd_port conf
    host=$(hostname -s 2>/dev/null) || host=
    [ -n "$host" ] || die "hostname -s gives nothing"
    # SLURM_CLUSTER_CPUS may claim more CPUs than there are, to run more
    # tasks at once (config_overrides below makes slurmd accept it).
    cpus=${SLURM_CLUSTER_CPUS:-$(nproc 2>/dev/null || echo 1)}
    case $cpus in ''|*[!0-9]*|0) die "bad CPU count '$cpus' (SLURM_CLUSTER_CPUS)" ;; esac
    mem_kb=$(awk '/^MemTotal:/ {print $2}' /proc/meminfo 2>/dev/null)
    # RealMemory in MB, 10% below the total: slurmd drains the node if the
    # configured value is above what it measures.
    mem=$(( ${mem_kb:-1048576} * 9 / 10 / 1024 ))
    [ "$mem" -ge 1 ] || mem=1
    ports=$(pick_ports) || die "no free TCP port pair found"
    # SlurmdSpoolDir (slurmd-%n below) exists before slurmd looks for it.
    mkdir -p "$DIR/spool/slurmd-$host" || die "cannot create $DIR/spool/slurmd-$host"
    ctld_port=${ports% *}
    slurmd_port=${ports#* }

    # --- MUNGE ---------------------------------------------------------
    STARTING=1
    # Own key, socket, pid, log and seed files; munged runs as root.
    # --force: munged refuses to start when a parent directory of the
    # socket is not world-executable (mktemp -d gives 0700).  Only root
    # talks to this munged, so that check does not matter here.
    dd if=/dev/urandom of="$DIR/munge/munge.key" bs=1024 count=1 2>/dev/null ||
        die "cannot create munge key"
    chmod 0400 "$DIR/munge/munge.key"
    munged --force \
        --key-file="$DIR/munge/munge.key" \
        --socket="$DIR/munge/munge.socket" \
        --pid-file="$DIR/run/munged.pid" \
        --log-file="$DIR/log/munged.log" \
        --seed-file="$DIR/munge/munged.seed" >"$DIR/log/munged.out" 2>&1 ||
        die "munged failed: $(tail -n 1 "$DIR/log/munged.out" 2>/dev/null) (see $DIR/log/munged.log)"

    # --- slurm.conf ----------------------------------------------------
    conf=$DIR/slurm.conf
    cat >"$conf" <<EOF
# Generated by slurm_cluster.sh for a throw-away test cluster.
ClusterName=partita-test
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root

AuthType=auth/munge
CredType=cred/munge
# Our own munged; used by the daemons and by every client command.
AuthInfo=socket=$DIR/munge/munge.socket

StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool/slurmd-%n
SlurmctldPidFile=$DIR/run/slurmctld.pid
SlurmdPidFile=$DIR/run/slurmd.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# Not /etc/slurm/plugstack.conf: no SPANK plugins.
PlugStackConfig=$DIR/plugstack.conf

# No cgroups in a container: plain /proc process tracking, no task binding.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
# Without slurmdbd, sacct has nothing to read; finished jobs are written
# one line each to this file instead (and kept by squeue for MinJobAge).
JobCompType=jobcomp/filetxt
JobCompLoc=$DIR/log/jobcomp.txt
MpiDefault=none
# No mail in tests (the default /bin/mail is usually missing).
MailProg=/bin/true
SwitchType=switch/none

SchedulerType=sched/backfill
# Start pending work as soon as resources free up: the defaults
# (batch_sched_delay=3 s) make each wave of array tasks wait ~3 s.
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MaxArraySize=100001
MaxJobCount=200000
# Keep finished jobs visible to squeue/scontrol for 5 minutes.
MinJobAge=300
# A node that was down comes back by itself when slurmd registers.
ReturnToService=2
# Trust the node line below rather than what slurmd detects (containers
# can report odd sockets/threads).
SlurmdParameters=config_overrides
# Fast feedback in tests.
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
Waittime=0

NodeName=$host NodeAddr=127.0.0.1 NodeHostname=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=NO
EOF
    : >"$DIR/plugstack.conf"
    export SLURM_CONF=$conf

    # --- daemons -------------------------------------------------------
    # -c: fresh state (nothing to recover in a new DIR).  Both daemonize and
    # write their pid files given in slurm.conf.
    slurmctld -c -f "$conf" >"$DIR/log/slurmctld.out" 2>&1 ||
        die "slurmctld failed: $(start_failure slurmctld) (see $DIR/log/slurmctld.log)"
    slurmd -N "$host" -f "$conf" >"$DIR/log/slurmd.out" 2>&1 ||
        die "slurmd failed: $(start_failure slurmd) (see $DIR/log/slurmd.log)"

    # --- wait for the node -----------------------------------------------
    # The daemons fork before they bind their ports, so a port clash or a
    # bad setting shows up here, as a daemon that went away.
    local t0 elapsed state='' pid why
    t0=$(date +%s)
    while :; do
        state=$(sinfo -h -N -n "$host" -o '%T' 2>/dev/null | head -n 1)
        [ "$state" = idle ] && break
        elapsed=$(( $(date +%s) - t0 ))
        for b in munged slurmctld slurmd; do
            pid=$(cat "$DIR/run/$b.pid" 2>/dev/null)
            # The pid file appears shortly after the fork; allow 5 s for it.
            if { [ -n "$pid" ] && ! alive "$pid"; } ||
               { [ -z "$pid" ] && [ "$elapsed" -ge 5 ]; }; then
                why=$(last_error "$DIR/log/$b.log")
                die "$b exited${why:+: $why} (see $DIR/log/$b.log)"
            fi
        done
        if [ "$elapsed" -ge "$START_TIMEOUT" ]; then
            why=$(last_error "$DIR/log/slurmctld.log" "$DIR/log/slurmd.log")
            die "node $host not idle after ${START_TIMEOUT}s (state '${state:-none}'${why:+; last error: $why})"
        fi
        sleep 0.2
    done
    echo "export SLURM_CONF=$conf"
}

[ $# -eq 2 ] || usage
DIR=$2
case $1 in
    start) cmd_start ;;
    stop)  cmd_stop ;;
    *)     usage ;;
esac
