#!/usr/bin/env bash
# Start (or stop) a single-node Slurm cluster on this machine, so that the job-array path of
# spectrace can be tried without a real cluster. Debian/Ubuntu: installs slurm-wlm and munge
# with apt-get when they are missing (needs root), writes its configuration under
# $SLURM_LOCAL_DIR (default /tmp/spectrace-slurm), and runs munged, slurmctld and slurmd as
# plain background daemons (no systemd needed, so it also works in containers).
#
# Usage: scripts/slurm/local-slurm.sh start | stop | status
set -euo pipefail

DIR="${SLURM_LOCAL_DIR:-/tmp/spectrace-slurm}"
CONF=/etc/slurm/slurm.conf
HOST="$(hostname -s)"
CPUS="$(nproc)"
MEM_MB="$(awk '/MemTotal/ {print int($2 / 1024 * 0.8)}' /proc/meminfo)"

install_packages() {
    if command -v slurmctld >/dev/null && command -v munged >/dev/null; then
        return
    fi
    echo "installing slurm-wlm and munge (apt-get)"
    apt-get update
    DEBIAN_FRONTEND=noninteractive apt-get install -y slurm-wlm munge
}

write_config() {
    mkdir -p "$DIR"/{state,spool,log} /etc/slurm /run/munge /var/log/munge /var/lib/munge
    cat > "$CONF" <<CONF
# Single-node Slurm for trying spectrace's job arrays (written by scripts/slurm/local-slurm.sh).
ClusterName=spectrace-local
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/slurmctld.pid
SlurmdPidFile=$DIR/slurmd.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
ReturnToService=2
MpiDefault=none
NodeName=$HOST CPUs=$CPUS RealMemory=$MEM_MB State=UNKNOWN
PartitionName=local Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF
    # slurmd (22.05) initialises a cgroup plugin even when none of its users are configured;
    # let it detect the machine's cgroup version.
    echo "CgroupPlugin=autodetect" > /etc/slurm/cgroup.conf
    if [ ! -s /etc/munge/munge.key ]; then
        mkdir -p /etc/munge
        dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none
    fi
    chown -R munge:munge /etc/munge /run/munge /var/log/munge /var/lib/munge 2>/dev/null || true
    chmod 0700 /etc/munge
    chmod 0400 /etc/munge/munge.key
}

start() {
    install_packages
    write_config
    if ! pgrep -x munged >/dev/null; then
        if id munge >/dev/null 2>&1; then
            su -s /bin/sh munge -c "munged --force" || munged --force
        else
            munged --force
        fi
    fi
    [ -f "$DIR/slurmctld.pid" ] && kill -0 "$(cat "$DIR/slurmctld.pid")" 2>/dev/null \
        || slurmctld -i
    [ -f "$DIR/slurmd.pid" ] && kill -0 "$(cat "$DIR/slurmd.pid")" 2>/dev/null || slurmd
    for _ in $(seq 1 30); do
        if sinfo -h -o "%T" 2>/dev/null | grep -qE "idle|mixed|alloc"; then
            sinfo
            return 0
        fi
        sleep 1
    done
    echo "slurm did not come up; see $DIR/log/" >&2
    sinfo || true
    exit 1
}

stop() {
    for d in slurmd slurmctld; do
        if [ -f "$DIR/$d.pid" ]; then
            kill "$(cat "$DIR/$d.pid")" 2>/dev/null || true
            rm -f "$DIR/$d.pid"
        fi
    done
}

case "${1:-start}" in
    start) start ;;
    stop) stop ;;
    status) sinfo ;;
    *) echo "usage: $0 start|stop|status" >&2; exit 2 ;;
esac
