# Sourced by test_cluster.sh: a single-node Slurm cluster in a temporary directory, started as root from
# Debian's packages (munge, slurmctld, slurmd) and torn down after. Own munge key and socket, own ports,
# state and spool directories, no cgroups (proctrack/linuxproc, task/none) and no accounting.
#
#   slurm_start DIR    starts munged, slurmctld, slurmd; exports SLURM_CONF; returns 1 (saying why) on failure
#   slurm_stop         cancels the jobs and stops the three daemons this started (by their pids)

slurm_why=""
slurm_pids=()

slurm_fail() {
  slurm_why=$1
  echo "slurm: cannot start the test cluster: $1" >&2
  local log
  for log in "$slurm_dir"/munged.log "$slurm_dir"/slurmctld.log "$slurm_dir"/slurmd.log; do
    [ -s "$log" ] && { echo "--- last lines of $log:" >&2; tail -n 15 "$log" >&2; }
  done
  return 1
}

slurm_start() {
  slurm_dir=$1
  mkdir -p "$slurm_dir"/{state,spool,munge}
  chmod 700 "$slurm_dir/munge"
  local tool
  for tool in munged slurmctld slurmd sbatch squeue scancel sinfo; do
    command -v "$tool" >/dev/null 2>&1 || PATH="$PATH:/usr/sbin:/sbin"
    command -v "$tool" >/dev/null 2>&1 ||
      { slurm_fail "'$tool' is not installed (Debian: munge slurmctld slurmd slurm-client; scripts/install_deps.sh)"; return 1; }
  done
  [ "$(id -u)" = 0 ] || { slurm_fail "the test cluster runs as root (SlurmUser=root), as CI does; this is uid $(id -u)"; return 1; }
  # munge: its own key and socket.
  dd if=/dev/urandom of="$slurm_dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$slurm_dir/munge/munge.key"
  munged --force --key-file="$slurm_dir/munge/munge.key" --socket="$slurm_dir/munge/munge.sock" \
    --pid-file="$slurm_dir/munge/munged.pid" --log-file="$slurm_dir/munged.log" \
    --seed-file="$slurm_dir/munge/munged.seed" >"$slurm_dir/munged.out" 2>&1 ||
    { cat "$slurm_dir/munged.out" >&2; slurm_fail "munged did not start"; return 1; }
  local i
  for i in $(seq 50); do [ -s "$slurm_dir/munge/munged.pid" ] && break; sleep 0.1; done
  [ -s "$slurm_dir/munge/munged.pid" ] || { slurm_fail "munged wrote no pid file"; return 1; }
  slurm_pids+=("$(cat "$slurm_dir/munge/munged.pid")")
  local node port
  node=$(hostname -s)
  port=$((20000 + RANDOM % 20000))
  cat >"$slurm_dir/slurm.conf" <<CONF
ClusterName=sbtest
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$slurm_dir/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$slurm_dir/state
SlurmdSpoolDir=$slurm_dir/spool
SlurmctldPidFile=$slurm_dir/slurmctld.pid
SlurmdPidFile=$slurm_dir/slurmd.pid
SlurmctldLogFile=$slurm_dir/slurmctld.log
SlurmdLogFile=$slurm_dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
SlurmctldTimeout=30
SlurmdTimeout=30
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$slurm_dir/slurm.conf"
  slurmctld -D -f "$SLURM_CONF" >"$slurm_dir/slurmctld.out" 2>&1 &
  slurm_pids+=($!)
  slurmd -D -f "$SLURM_CONF" -N "$node" >"$slurm_dir/slurmd.out" 2>&1 &
  slurm_pids+=($!)
  # Up when the node is idle (a minute at most; in seconds here).
  for i in $(seq 600); do
    sinfo -h -N -o %T 2>/dev/null | grep -qx idle && return 0
    local pid
    for pid in "${slurm_pids[@]}"; do
      kill -0 "$pid" 2>/dev/null || {
        cat "$slurm_dir"/slurmctld.out "$slurm_dir"/slurmd.out >&2
        slurm_fail "a daemon (pid $pid) exited while starting"
        return 1
      }
    done
    sleep 0.1
  done
  slurm_fail "the node did not become idle within 60 s (sinfo: $(sinfo -h -N -o '%N %T %E' 2>&1))"
}

slurm_stop() {
  [ -n "${SLURM_CONF:-}" ] && scancel --user=root >/dev/null 2>&1
  local pid
  for pid in "${slurm_pids[@]}"; do kill "$pid" 2>/dev/null; done
  for pid in "${slurm_pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null
  done
  slurm_pids=()
}
