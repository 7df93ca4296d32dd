#!/usr/bin/env bash
# The README's Quick start on a fresh machine: makes a minimal Debian 12 root
# (debootstrap --variant=minbase bookworm, from the mirror this machine's apt
# uses), copies the checkout into it as git has it (the tracked files with
# their working-tree contents: no build directories, no out/), and runs there,
# as root, with a clean environment and no standard input, the commands of the
# README's Quick start block as they are written (tools/paper.sh, then
# tools/run-tests.sh). It checks that
#   - both exit 0;
#   - paper.sh made out/paper/report/index.html and out/paper/compare.md;
#   - paper.sh installed no package that ships, enables or tries to start a
#     service (a policy-rc.d in the root refuses and records every start);
#   - run-tests.sh's last line is "N passed, 0 failed[, N skipped]".
# Each phase's time is printed, and a summary at the end.
#
# Exit: 0 passed; 1 failed; 77 only where the root cannot be made here: not
# root, debootstrap missing and not installable, the mirror unreachable, not
# enough free space, chroot or the mounts not allowed.
#
# Environment:
#   KEEP=1              keep the root afterwards (its mounts are undone anyway)
#   FRESH_ROOT_DIR=DIR  make it under DIR (default /var/tmp; needs ~4 GiB)
#   FRESH_ROOT_MIRROR=URL  Debian mirror (default: the one apt uses here)
#
# Nothing is cached between runs: every run debootstraps anew (about 25 s on
# a 2-core machine) and installs every package through the project's own
# scripts, so a missing install step cannot hide behind an earlier run.
set -uo pipefail
top=$(cd "$(dirname "$0")/.." && pwd) || exit 1
PATH=$PATH:/usr/sbin:/sbin
me=check-fresh-root
t0=$(date +%s)

say() { echo "$me: $*"; }
skip() { say "SKIP: $*"; exit 77; }
failures=()
failed() { say "FAIL: $*"; failures+=("$*"); }

# phase timings
phase_names=() phase_secs=() phase_start=0 phase_name=
phase() { phase_name=$1; phase_start=$(date +%s); say "== $1"; }
phase_end() {
  local s=$(( $(date +%s) - phase_start ))
  phase_names+=("$phase_name") phase_secs+=("$s")
  say "-- $phase_name: ${s} s"
}
print_timings() {
  local i
  say "phase timings:"
  for i in "${!phase_names[@]}"; do printf '  %-38s %5d s\n' "${phase_names[$i]}" "${phase_secs[$i]}"; done
  printf '  %-38s %5d s\n' "total" $(( $(date +%s) - t0 ))
}

# ---- can a root be made here?
phase "preflight"
[ "$(id -u)" -eq 0 ] || skip "needs root (debootstrap, chroot and mounts); run it as root"
command -v git >/dev/null && git -C "$top" rev-parse --git-dir >/dev/null 2>&1 ||
  { say "FAIL: $top is not a git checkout (the copy into the root is made with git archive)"; exit 1; }
if ! command -v debootstrap >/dev/null; then
  say "debootstrap is missing: apt-get install debootstrap"
  { DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=600 update -qq &&
    DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=600 install -y -qq --no-install-recommends debootstrap; } </dev/null >/tmp/$me-apt.$$ 2>&1
  command -v debootstrap >/dev/null || { cat /tmp/$me-apt.$$; rm -f /tmp/$me-apt.$$; skip "debootstrap is not installed and apt-get could not install it"; }
  rm -f /tmp/$me-apt.$$
fi
# the Debian mirror and suites apt uses here (deb822 or one-line sources alike)
sources=$(apt-get indextargets --format '$(SITE) $(RELEASE)' 'Created-By: Packages' 'Component: main' 2>/dev/null |
  awk '$2 ~ /^bookworm(-updates|-security)?$/ && !seen[$0]++')
mirror=${FRESH_ROOT_MIRROR:-$(awk '$2 == "bookworm" { print $1; exit }' <<<"$sources")}
mirror=${mirror:-http://deb.debian.org/debian}
[ -n "$sources" ] && [ -z "${FRESH_ROOT_MIRROR:-}" ] || sources="$mirror bookworm"
awk '$2 == "bookworm" { f = 1 } END { exit !f }' <<<"$sources" || sources=$(printf '%s bookworm\n%s' "$mirror" "$sources")
base=${FRESH_ROOT_DIR:-/var/tmp}
mkdir -p "$base" 2>/dev/null && [ -w "$base" ] || skip "cannot write under $base (FRESH_ROOT_DIR)"
need_kib=$((4 * 1024 * 1024)) # measured: 1.3 GiB at the end of a run, and apt's downloads
avail=$(df -Pk "$base" | awk 'NR == 2 { print $4 }')
[ "${avail:-0}" -ge "$need_kib" ] || skip "$((avail / 1024)) MiB free under $base, a fresh root with both builds needs 4 GiB"
W=$(mktemp -d "$base/popc-fresh-root.XXXXXX") || skip "cannot make a directory under $base"
W=$(cd "$W" && pwd -P) # as /proc/PID/root names it
root=$W/root
say "root: $root; mirror: $mirror (suites: $(awk '{ printf "%s%s", sep, $2; sep = " " }' <<<"$sources"))"

# ---- cleanup on every way out: processes in the root, mounts, the root
mounts=() deb_pid=
mounted_under() { # mount points under $1, deepest first
  awk -v p="$1/" 'index($5 "/", p) == 1 { print length($5), $5 }' /proc/self/mountinfo | sort -rn | cut -d' ' -f2-
}
kill_in_root() {
  local sig=$1 p any=1
  for p in /proc/[0-9]*; do
    [ "$(readlink "$p/root" 2>/dev/null)" = "$root" ] && { kill "-$sig" "${p#/proc/}" 2>/dev/null; any=0; }
  done
  return $any
}
cleanup() {
  local rc=$? m i left
  trap - EXIT INT TERM HUP
  [ -n "${root:-}" ] || exit "$rc"
  if [ -n "${deb_pid:-}" ]; then kill -TERM -- "-$deb_pid" 2>/dev/null; wait "$deb_pid" 2>/dev/null; fi
  if kill_in_root TERM; then
    for i in $(seq 50); do kill_in_root 0 || break; sleep 0.1; done
    kill_in_root KILL && sleep 0.5
  fi
  for ((i = ${#mounts[@]} - 1; i >= 0; i--)); do umount -R "${mounts[$i]}" 2>/dev/null; done
  for m in $(mounted_under "$W"); do umount "$m" 2>/dev/null || umount -l "$m"; done
  left=$(mounted_under "$W")
  if [ -n "$left" ]; then
    say "still mounted, so $W is left in place: $left"
    [ "$rc" -eq 0 ] && rc=1
  elif [ "${KEEP:-}" = 1 ]; then
    say "KEEP=1: the root stays at $root (chroot $root /bin/bash)"
  else
    rm -rf --one-file-system "$W"
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM
trap 'exit 129' HUP
phase_end

# ---- the root
# debootstrap --variant=minbase: essential and required packages and apt only;
# nothing of the project's. Not cached (see the header).
phase "debootstrap --variant=minbase bookworm"
# in the background and waited for, here and below: a signal to this script
# then ends it at once (and the cleanup) instead of after the command
# (debootstrap in a session of its own, so that its wget and dpkg end with it)
setsid debootstrap --variant=minbase bookworm "$root" "$mirror" </dev/null >"$W/debootstrap.log" 2>&1 &
deb_pid=$!
if ! wait "$deb_pid"; then
  deb_pid=
  tail -40 "$W/debootstrap.log"
  if grep -qi 'no space left' "$W/debootstrap.log"; then
    skip "debootstrap: no space left under $base"
  elif grep -qiE "failed getting release|couldn't download|could not resolve|temporary failure in name|unable to resolve|network is unreachable|connection (refused|timed out)|failed: (connection|no route)|release signed by unknown key" "$W/debootstrap.log"; then
    skip "debootstrap cannot get bookworm from $mirror (above)"
  elif grep -qiE 'failure trying to run: chroot|operation not permitted' "$W/debootstrap.log"; then
    skip "debootstrap cannot chroot or mount here (above)"
  fi
  say "FAIL: debootstrap failed (above; KEEP=1 keeps the whole log, $W/debootstrap.log)"
  exit 1
fi
deb_pid=
phase_end

phase "prepare the root"
# what a machine has and a bare root lacks: a hosts file as the installer
# writes it (localhost, and this host's name: hostname -s, Slurm), the
# resolver, and apt's network settings here (a proxy, a mirror's dates).
printf '127.0.0.1\tlocalhost\n127.0.1.1\t%s\n::1\t\tlocalhost ip6-localhost ip6-loopback\n' "$(hostname)" >"$root/etc/hosts"
cp -L /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null
apt-config dump 2>/dev/null | grep -E '^Acquire::((https?|ftp)::Proxy|Check-Valid-Until|Check-Date|Max-ValidTime) ' \
  >"$root/etc/apt/apt.conf.d/00fresh-root-host"
awk '{ print "deb " $1 " " $2 " main" }' <<<"$sources" >"$root/etc/apt/sources.list"
# no service starts in the root: invoke-rc.d and deb-systemd-invoke ask
# policy-rc.d, which refuses (101) and records what was asked
cat >"$root/usr/sbin/policy-rc.d" <<'EOF'
#!/bin/sh
# check-fresh-root: no service starts inside this root
echo "$*" >>/var/log/policy-rc.d.log
exit 101
EOF
chmod 755 "$root/usr/sbin/policy-rc.d"
# the checkout as git has it: HEAD with the working tree's changes to tracked
# files (git stash create writes an object only: no ref, index or file)
rev=$(git -C "$top" stash create 2>/dev/null)
rev=${rev:-HEAD}
git -C "$top" archive --format=tar --prefix=popc/ "$rev" | tar -x -C "$root/root" ||
  { say "FAIL: git archive of $top into the root failed"; exit 1; }
say "source: $(git -C "$top" rev-parse --short HEAD)$([ "$rev" = HEAD ] || echo ' with uncommitted changes') in /root/popc"
# the kernel's file systems: /proc, /sys (read-only), a /dev of its own with
# the usual nodes, a new devpts instance (socat's pseudo-terminals), /dev/shm
# and /run
do_mount() { # mount arguments..., mount point last
  mount "$@" || return 1
  mounts+=("${!#}")
}
# a bind of this machine's mounts, made a slave at once: an unmount in the
# root must never propagate to the machine's own mounts
do_bind() { # source target
  do_mount --rbind "$1" "$2" && mount --make-rslave "$2"
}
do_mount -t proc proc "$root/proc" || skip "cannot mount proc in the root (mount not allowed here)"
do_mount -t sysfs -o ro,nosuid,nodev,noexec sysfs "$root/sys" || do_bind /sys "$root/sys" ||
  skip "cannot mount sysfs in the root"
# the machine's cgroup tree: without it slurmd (sweep-slurm) stops at start
# with "No filesystem mounted on /sys/fs/cgroup"
if mountpoint -q /sys/fs/cgroup && ! mountpoint -q "$root/sys/fs/cgroup"; then
  do_bind /sys/fs/cgroup "$root/sys/fs/cgroup" || skip "cannot bind /sys/fs/cgroup into the root"
fi
do_mount -t tmpfs -o mode=755,nosuid dev "$root/dev" || skip "cannot mount a tmpfs on the root's /dev"
for n in null zero full random urandom tty; do
  if ! mknod -m 666 "$root/dev/$n" c "$((16#$(stat -c %t /dev/$n)))" "$((16#$(stat -c %T /dev/$n)))" 2>/dev/null; then
    touch "$root/dev/$n" && do_bind "/dev/$n" "$root/dev/$n" || skip "cannot make /dev/$n in the root"
  fi
done
mkdir -p "$root/dev/pts" "$root/dev/shm"
do_mount -t devpts -o newinstance,ptmxmode=0666,mode=620,gid=5 devpts "$root/dev/pts" ||
  skip "cannot mount a devpts instance in the root"
ln -s pts/ptmx "$root/dev/ptmx"
ln -s /proc/self/fd "$root/dev/fd"
ln -s /proc/self/fd/0 "$root/dev/stdin"; ln -s /proc/self/fd/1 "$root/dev/stdout"; ln -s /proc/self/fd/2 "$root/dev/stderr"
do_mount -t tmpfs -o mode=1777,nosuid,nodev shm "$root/dev/shm" || skip "cannot mount /dev/shm in the root"
do_mount -t tmpfs -o mode=755,nosuid,nodev run "$root/run" || skip "cannot mount /run in the root"
mkdir -m 1777 "$root/run/lock"
chroot "$root" /bin/true || skip "chroot into the new root is not allowed here"
# services, as files: what a package ships or enables (init scripts, units)
services() {
  (cd "$root" && find etc/init.d usr/lib/systemd/system etc/systemd/system \( -type f -o -type l \) 2>/dev/null | sort)
}
services >"$W/services.base"
phase_end

# ---- the Quick start, as the README writes it
mapfile -t cmds < <(awk '/^## Quick start/ { q = 1 } q && /^```sh/ { b = 1; next } b && /^```/ { exit } b' "$top/README.md" |
  sed 's/[[:space:]]#.*//; s/[[:space:]]*$//' | grep -v '^$')
if [ ${#cmds[@]} -ne 2 ] || [ "${cmds[0]}" != tools/paper.sh ] || [ "${cmds[1]}" != tools/run-tests.sh ]; then
  say "FAIL: the README's Quick start block is not 'tools/paper.sh' then 'tools/run-tests.sh' (found: ${cmds[*]:-nothing}); this check knows what those two must leave"
  exit 1
fi
# a login's environment, nothing of this one's; no standard input, as in CI;
# bounded (command 1 15 min, command 2 45 min) so that CI's 90 min hold
in_root() { # timeout-seconds command
  timeout -k 30 "$1" chroot "$root" /usr/bin/env -i HOME=/root USER=root LOGNAME=root SHELL=/bin/bash \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    /bin/bash -c "cd /root/popc && $2" </dev/null
}
show() { sed -u 's/^/  | /'; } # the inner output, indented: its closing line is not ours
run_in_root() { # timeout-seconds command output-file; sets rc, the command's exit code
  rm -f "$W/rc"
  { in_root "$1" "$2"; echo $? >"$W/rc"; } 2>&1 | tee "$3" | show &
  wait $!
  rc=$(cat "$W/rc" 2>/dev/null) || rc=1
}

phase "command 1: ${cmds[0]}"
run_in_root 1800 "${cmds[0]}" "$W/paper.out"
[ "$rc" -eq 0 ] || failed "${cmds[0]} exited $rc"
for f in out/paper/report/index.html out/paper/compare.md; do
  [ -s "$root/root/popc/$f" ] || failed "${cmds[0]} did not make $f"
done
services >"$W/services.paper"
new=$(comm -13 "$W/services.base" "$W/services.paper")
[ -z "$new" ] || failed "${cmds[0]} installed services: $(echo $new)"
[ ! -s "$root/var/log/policy-rc.d.log" ] ||
  failed "${cmds[0]} tried to start or stop services: $(tr '\n' ';' <"$root/var/log/policy-rc.d.log")"
say "packages after command 1: $(chroot "$root" dpkg-query -W -f '${db:Status-Abbrev}\n' | grep -c '^ii') installed"
phase_end

phase "command 2: ${cmds[1]}"
run_in_root 2700 "${cmds[1]}" "$W/tests.out"
[ "$rc" -eq 0 ] || failed "${cmds[1]} exited $rc"
last=$(tail -n 1 "$W/tests.out")
if [[ $last =~ ^[0-9]+\ passed,\ 0\ failed(,\ [0-9]+\ skipped)?$ ]]; then
  say "${cmds[1]} closed with: $last"
else
  failed "${cmds[1]}'s last line is not 'N passed, 0 failed[, N skipped]': '$last'"
fi
# each build's verdicts, as meson test printed them (a skip says why in testlog.txt)
grep -E '^ *[0-9]+/[0-9]+ .* SKIP ' "$W/tests.out" | sed 's/^ */  skipped: /'
grep -E '^ *[0-9]+/[0-9]+ .* (FAIL|TIMEOUT|ERROR|UNEXPECTEDPASS) ' "$W/tests.out" | sort -u | sed 's/^ */  failed: /'
[ -s "$root/var/log/policy-rc.d.log" ] &&
  say "service starts refused in the root (policy-rc.d): $(awk '{ print $1 }' "$root/var/log/policy-rc.d.log" | sort -u | tr '\n' ' ')"
phase_end

say "the root takes $(du -sm --one-file-system "$root" 2>/dev/null | cut -f1) MiB"
print_timings
if [ ${#failures[@]} -gt 0 ]; then
  say "FAILED (${#failures[@]}):"
  printf '  - %s\n' "${failures[@]}"
  exit 1
fi
say "PASS: both Quick start commands work on a fresh Debian 12 root"
exit 0
