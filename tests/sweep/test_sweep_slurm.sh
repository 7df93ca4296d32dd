#!/usr/bin/env bash
# A real single-node Slurm cluster, started here without systemd (munged with
# a generated key, slurmctld and slurmd with a generated slurm.conf, all in a
# temporary directory, on free loopback ports, with known pids), runs a popc
# sweep as a job array of two shards with data/slurm/popc-sweep.sbatch. The
# merged summary must equal the one-machine sweep's but for wall time.
# Exit 77 (skip) only when the daemons cannot start on this machine.
set -u
POPC=${POPC:?POPC must name the popc program}
SRC=${POPC_SOURCE_ROOT:?}
SCENE=$SRC/data/scenes/paper.ini
SBATCH_SCRIPT=$SRC/data/slurm/popc-sweep.sbatch
T=$(mktemp -d /tmp/popc-slurm-XXXXXX)
chmod 755 "$T"
pids=()
cleanup() {
  for p in "${pids[@]}"; do kill "$p" 2>/dev/null; done
  for p in "${pids[@]}"; do wait "$p" 2>/dev/null; done
  rm -rf "$T"
}
trap cleanup EXIT
skip() { echo "SKIP: $*"; for f in "$T"/*.log; do [ -f "$f" ] && { echo "--- $f"; tail -5 "$f"; }; done; exit 77; }
fail() { echo "not ok - $*"; for f in "$T"/*.log "$T"/job-*.out; do [ -f "$f" ] && { echo "--- $f"; tail -15 "$f"; }; done; exit 1; }
ok() { echo "ok - $*"; }

for prog in munged slurmctld slurmd sbatch sinfo scontrol; do
  command -v "$prog" >/dev/null || PATH=$PATH:/usr/sbin:/sbin
  command -v "$prog" >/dev/null || skip "$prog is not installed (Debian packages slurm-wlm and munge)"
done
[ "$(id -u)" -eq 0 ] || skip "a test cluster with SlurmUser=root needs root"

# two free TCP ports: ones this test can bind (python3 binds each on the
# wildcard address, IPv4 and IPv6, and lets it go), and below the kernel's
# ephemeral range, so that no test running beside this one (a
# popc-servo-sim on port 0, a client's connect) can be given one of them
# between this check and the daemons' bind. (It read /proc/net/tcp with
# gawk's strtonum, which mawk lacks: every port looked free.)
eph_lo=$(cut -f1 /proc/sys/net/ipv4/ip_local_port_range 2>/dev/null || echo 32768)
[ "${eph_lo:-0}" -gt 12000 ] 2>/dev/null || eph_lo=32768
# free_port [NOT]: a port in [10000, eph_lo) that binds, other than NOT
free_port() {
  python3 - "$eph_lo" "${1:-0}" <<'PY'
import random, socket, sys
eph_lo, avoid = int(sys.argv[1]), int(sys.argv[2])
start = random.randrange(10000, eph_lo - 1000)
for p in list(range(start, eph_lo)) + list(range(10000, start)):
    if p == avoid:
        continue
    try:
        for fam, addr in ((socket.AF_INET, "0.0.0.0"), (socket.AF_INET6, "::")):
            try:
                s = socket.socket(fam, socket.SOCK_STREAM)
                if fam == socket.AF_INET6:
                    s.setsockopt(socket.IPPROTO_IPV6, socket.IPV6_V6ONLY, 1)
            except OSError:
                continue  # no IPv6 here
            with s:
                try:
                    s.bind((addr, p))
                except OSError as e:
                    # 99: EADDRNOTAVAIL, IPv6 off; any other error: the port is taken
                    if fam == socket.AF_INET6 and e.errno == 99:
                        continue
                    raise
    except OSError:
        continue
    print(p)
    sys.exit(0)
sys.exit(1)
PY
}
P1=$(free_port) && P2=$(free_port "$P1") || fail "no free TCP port below $eph_lo"

# munge with its own key and socket
dd if=/dev/urandom of="$T/munge.key" bs=1024 count=1 status=none
chmod 400 "$T/munge.key"
mkdir -m 700 "$T/munge"
munged -F --force --key-file="$T/munge.key" --socket="$T/munge/munge.sock" \
  --pid-file="$T/munge/munged.pid" --log-file="$T/munged.log" --seed-file="$T/munge/seed" \
  >>"$T/munged.log" 2>&1 &
pids+=($!)
for _ in $(seq 100); do [ -S "$T/munge/munge.sock" ] && break; kill -0 "${pids[0]}" 2>/dev/null || break; sleep 0.1; done
[ -S "$T/munge/munge.sock" ] || skip "munged did not start"

host=$(hostname -s)
mkdir "$T/state" "$T/spool"
cat > "$T/slurm.conf" <<CONF
ClusterName=popctest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$P1
SlurmdPort=$P2
AuthType=auth/munge
AuthInfo=socket=$T/munge/munge.sock
CredType=cred/munge
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
ReturnToService=2
MpiDefault=none
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
SlurmdTimeout=30
InactiveLimit=0
NodeName=localhost NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN
PartitionName=test Nodes=localhost Default=YES MaxTime=10 State=UP
CONF
export SLURM_CONF=$T/slurm.conf
slurmctld -D -i -f "$SLURM_CONF" >>"$T/slurmctld.log" 2>&1 &
pids+=($!)
slurmd -D -N localhost -f "$SLURM_CONF" >>"$T/slurmd.log" 2>&1 &
pids+=($!)
# readiness: the controller answers and the node is idle (bounded: 30 s)
ready=
for _ in $(seq 150); do
  for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null || skip "a daemon exited at start"; done
  if scontrol ping 2>/dev/null | grep -q "UP" && [ "$(sinfo -h -n localhost -o %T 2>/dev/null)" = "idle" ]; then ready=1; break; fi
  sleep 0.2
done
[ -n "$ready" ] || skip "slurmctld/slurmd did not become ready in 30 s"
ok "single-node Slurm up (ports $P1, $P2)"

VARY=(--vary operator.speed=0.02:0.08:4 --vary controller.variant=none,ref-energy,improved)
# the array: two shards, one CPU each, side by side on the 2-CPU node. Its
# end is awaited by asking the controller for the tasks' states (bounded:
# 90 s), not with sbatch --wait, which looks after 2 s and then only every
# 8 s: the 1-second job took 10 s of this test that way.
timeout 30 sbatch --parsable --array=1-2 --cpus-per-task=1 --output="$T/job-%a.out" \
  --chdir="$T" --export=ALL,POPC="$POPC" \
  "$SBATCH_SCRIPT" "$SCENE" "${VARY[@]}" -o "$T/out" --no-log >"$T/sbatch.txt" 2>&1
rc=$?
job=$(head -1 "$T/sbatch.txt" | cut -d';' -f1)
[ "$rc" -eq 0 ] && [ -n "$job" ] || fail "sbatch --array=1-2: exit $rc: $(cat "$T/sbatch.txt")"
# task_states: one "JobState ExitCode" line per array task
task_states() { scontrol -o show job "$job" 2>/dev/null | sed -n 's/.* JobState=\([A-Z_]*\) .* ExitCode=\([0-9:]*\) .*/\1 \2/p'; }
done_=
for _ in $(seq 450); do
  st=$(task_states)
  if [ "$(echo "$st" | grep -c .)" -eq 2 ] && ! echo "$st" | grep -Eq '^(PENDING|RUNNING|CONFIGURING|COMPLETING|SUSPENDED|REQUEUED|RESIZING)'; then done_=1; break; fi
  sleep 0.2
done
[ -n "$done_" ] || fail "array job $job not finished in 90 s: $(task_states | tr '\n' ' ')"
[ "$(task_states | sort -u)" = "COMPLETED 0:0" ] || fail "array job $job: tasks ended $(task_states | tr '\n' ' ')"
ok "array job $job done: both tasks COMPLETED, exit 0"
[ -s "$T/out/summary-shard-1-of-2.csv" ] && [ -s "$T/out/summary-shard-2-of-2.csv" ] || fail "the two shard summaries (1-of-2, 2-of-2) are missing"
ok "both array tasks wrote their shard"
"$POPC" sweep merge "$T/out" >"$T/merge.txt" 2>&1 || fail "merge: $(cat "$T/merge.txt")"
ok "merged"
"$POPC" sweep "$SCENE" "${VARY[@]}" -o "$T/one" --no-log -q -j 2 || fail "the one-machine sweep failed"
nowall() { sed 's/,[^,]*$//' "$1"; }
if cmp -s <(nowall "$T/out/summary.csv") <(nowall "$T/one/summary.csv"); then
  ok "merged summary of the array equals the one-machine sweep's (12 runs, but wall time)"
else
  diff <(nowall "$T/out/summary.csv") <(nowall "$T/one/summary.csv") | head
  fail "merged summary differs from the one-machine sweep's"
fi
[ "$(wc -l < "$T/out/summary.csv")" -eq 13 ] || fail "expected 12 rows"
ok "12 rows"
