#!/usr/bin/env bash
# The README's Quick start on two fresh machines: two Debian 12 roots from
# the mirror this machine's apt uses,
#   minbase   debootstrap --variant=minbase bookworm: essential, required
#             and apt, nothing else (the least a machine can have);
#   standard  a standard Debian install: debootstrap's default variant
#             (required + important) plus tasksel's "standard" task (every
#             package of priority standard), installed with their
#             recommends as the installer does; among them bash-completion,
#             whose pkg-config file once sent `meson install` out of its
#             prefix (issue 27).
# Into each it copies the checkout as git has it (the tracked files with
# their working-tree contents: no build directories, no out/), and runs
# there, as root, with a clean environment and no standard input, the
# commands of the README's Quick start block as they are written
# (tools/paper.sh, then tools/run-tests.sh). It checks, in each root, that
#   - both exit 0;
#   - paper.sh made out/paper/report/index.html and out/paper/compare.md;
#   - paper.sh installed no package that ships, enables or tries to start a
#     service (a policy-rc.d in the root refuses and records every start);
#   - run-tests.sh's last line is "N passed, 0 failed[, N skipped]".
# Each phase's time is printed, and a summary at the end.
#
# Cost (CI's 90 minutes): one debootstrap (minbase) serves both roots: the
# standard root is a copy of it, raised to the standard set by apt (the
# same packages debootstrap's default variant and tasksel would unpack).
# The two roots then run side by side, each its own command 1 then command 2
# (the tests take free loopback ports and each root has its own /run and
# /dev/shm, so the two do not meet): about one command 2's time on a
# 2-core machine plus what the two share of the cores, rather than two. No
# build is shared: each root builds from its own copy of the source.
#
# Exit: 0 passed; 1 failed; 77 only where the roots cannot be made here: not
# root, debootstrap missing and not installable, the mirror unreachable, not
# enough free space, chroot or the mounts not allowed.
#
# Environment:
#   KEEP=1              keep the roots afterwards (their mounts are undone anyway)
#   FRESH_ROOT_DIR=DIR  make them under DIR (default /var/tmp; needs ~8 GiB)
#   FRESH_ROOT_MIRROR=URL  Debian mirror (default: the one apt uses here)
#   FRESH_ROOTS="minbase standard"  the roots to check (either or both)
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
need_kib=$((8 * 1024 * 1024)) # measured: 1.3 GiB a root at the end of a run, and apt's downloads
avail=$(df -Pk "$base" | awk 'NR == 2 { print $4 }')
[ "${avail:-0}" -ge "$need_kib" ] || skip "$((avail / 1024)) MiB free under $base, two fresh roots with both builds need 8 GiB"
W=$(mktemp -d "$base/popc-fresh-root.XXXXXX") || skip "cannot make a directory under $base"
W=$(cd "$W" && pwd -P) # as /proc/PID/root names it
roots=(${FRESH_ROOTS:-minbase standard})
for r in "${roots[@]}"; do
  case $r in minbase|standard) ;; *) say "FAIL: FRESH_ROOTS: '$r' is not minbase or standard"; exit 1 ;; esac
done
root=$W/minbase # debootstrap's; the standard root is copied from it
say "roots: ${roots[*]} under $W; mirror: $mirror (suites: $(awk '{ printf "%s%s", sep, $2; sep = " " }' <<<"$sources"))"

# ---- cleanup on every way out: processes in the root, mounts, the root
mounts=() deb_pid= lane_pids=()
mounted_under() { # mount points under $1, deepest first
  awk -v p="$1/" 'index($5 "/", p) == 1 { print length($5), $5 }' /proc/self/mountinfo | sort -rn | cut -d' ' -f2-
}
kill_in_root() { # processes whose root is one of ours
  local sig=$1 p any=1 r
  for p in /proc/[0-9]*; do
    r=$(readlink "$p/root" 2>/dev/null) || continue
    case $r in "$W"/*) kill "-$sig" "${p#/proc/}" 2>/dev/null; any=0 ;; esac
  done
  return $any
}
cleanup() {
  local rc=$? m i left
  trap - EXIT INT TERM HUP
  [ -n "${W:-}" ] || exit "$rc"
  if [ -n "${deb_pid:-}" ]; then kill -TERM -- "-$deb_pid" 2>/dev/null; wait "$deb_pid" 2>/dev/null; fi
  for i in "${lane_pids[@]}"; do kill -TERM "$i" 2>/dev/null; done
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
    say "KEEP=1: the roots stay under $W (chroot $W/ROOT /bin/bash)"
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

# ---- the minbase root
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
# the standard root starts as a copy of it (before any mount or change):
# the same bytes a second debootstrap would unpack, without its download
if [[ " ${roots[*]} " == *" standard "* ]]; then
  cp -a --one-file-system "$root" "$W/standard" || { say "FAIL: cannot copy the minbase root to $W/standard"; exit 1; }
fi
[[ " ${roots[*]} " == *" minbase "* ]] || { rm -rf --one-file-system "$root"; }
phase_end

# prepare_root ROOT: what a machine has and a bare root lacks, the mounts,
# the checkout
prepare_root() {
  local root=$1 n rev
  # a hosts file as the installer writes it (localhost, and this host's
  # name: hostname -s, Slurm), the resolver, and apt's network settings
  # here (a proxy, a mirror's dates).
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
  # the checkout as git has it: HEAD with the working tree's changes to
  # tracked files (git stash create writes an object only: no ref, index or file)
  rev=$(git -C "$top" stash create 2>/dev/null)
  rev=${rev:-HEAD}
  git -C "$top" archive --format=tar --prefix=popc/ "$rev" | tar -x -C "$root/root" ||
    { say "FAIL: git archive of $top into $root failed"; exit 1; }
  say "source: $(git -C "$top" rev-parse --short HEAD)$([ "$rev" = HEAD ] || echo ' with uncommitted changes') in $root/root/popc"
  # the kernel's file systems: /proc, /sys (read-only), a /dev of its own
  # with the usual nodes, a new devpts instance (socat's pseudo-terminals),
  # /dev/shm and /run
  do_mount -t proc proc "$root/proc" || skip "cannot mount proc in the root (mount not allowed here)"
  do_mount -t sysfs -o ro,nosuid,nodev,noexec sysfs "$root/sys" || do_bind /sys "$root/sys" ||
    skip "cannot mount sysfs in the root"
  # the machine's cgroup tree: without it slurmd (sweep-slurm) stops at
  # start with "No filesystem mounted on /sys/fs/cgroup"
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
}
# a mount, remembered for the cleanup
do_mount() { # mount arguments..., mount point last
  mount "$@" || return 1
  mounts+=("${!#}")
}
# a bind of this machine's mounts, made a slave at once: an unmount in the
# root must never propagate to the machine's own mounts
do_bind() { # source target
  do_mount --rbind "$1" "$2" && mount --make-rslave "$2"
}

phase "prepare the roots"
for r in "${roots[@]}"; do prepare_root "$W/$r"; done
phase_end

# ---- the Quick start, as the README writes it
mapfile -t cmds < <(awk '/^## Quick start/ { q = 1 } q && /^```sh/ { b = 1; next } b && /^```/ { exit } b' "$top/README.md" |
  sed 's/[[:space:]]#.*//; s/[[:space:]]*$//' | grep -v '^$')
if [ ${#cmds[@]} -ne 2 ] || [ "${cmds[0]}" != tools/paper.sh ] || [ "${cmds[1]}" != tools/run-tests.sh ]; then
  say "FAIL: the README's Quick start block is not 'tools/paper.sh' then 'tools/run-tests.sh' (found: ${cmds[*]:-nothing}); this check knows what those two must leave"
  exit 1
fi

# ---- one lane a root, the lanes side by side. A lane runs in a subshell:
# it writes its output to $W/NAME.out (shown at the end, indented), its
# phases' times to $W/NAME.times and its failures to $W/NAME.failures.
# a login's environment, nothing of this one's; no standard input, as in CI;
# bounded against a hang (the standard packages 20 min, command 1 30 min as
# before, command 2 45 min as before; the two lanes share the cores)
in_root() { # root timeout-seconds command
  timeout -k 30 "$2" chroot "$1" /usr/bin/env -i HOME=/root USER=root LOGNAME=root SHELL=/bin/bash \
    PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
    /bin/bash -c "cd /root/popc && $3" </dev/null
}
lane() { # name
  local name=$1 root=$W/$1 rc t last new
  local out=$W/$1.out times=$W/$1.times fails=$W/$1.failures
  : >"$times"; : >"$fails"
  exec >"$out" 2>&1
  lfail() { echo "FAIL: $*"; echo "$*" >>"$fails"; }
  lphase() { t=$(date +%s); echo "== $name: $1"; }
  lphase_end() { printf '%s: %s\t%d\n' "$name" "$1" $(( $(date +%s) - t )) >>"$times"; }
  services() { # what a package ships or enables (init scripts, units), as files
    (cd "$root" && find etc/init.d usr/lib/systemd/system etc/systemd/system \( -type f -o -type l \) 2>/dev/null | sort)
  }
  if [ "$name" = standard ]; then
    # debootstrap's default variant adds priority important; tasksel's
    # standard task is priority standard (`tasksel --task-packages
    # standard`: ~pstandard). Both by priority from the root's own package
    # lists, with recommends (as the installer does); services refused.
    lphase "priority important and standard packages (debootstrap's default variant, tasksel's standard task)"
    in_root "$root" 1200 "export DEBIAN_FRONTEND=noninteractive && apt-get -o DPkg::Lock::Timeout=600 update -qq &&
      pkgs=\$(apt-cache dumpavail | awk '/^Package:/ { p = \$2 } /^Priority: (important|standard)\$/ { print p }' | sort -u) &&
      echo \"installing \$(echo \$pkgs | wc -w) packages: \"\$pkgs &&
      apt-get -o DPkg::Lock::Timeout=600 install -y -q \$pkgs >/var/log/standard-install.log 2>&1 ||
      { tail -40 /var/log/standard-install.log; exit 1; }"
    rc=$?
    lphase_end "standard packages"
    [ "$rc" -eq 0 ] || { lfail "the standard packages did not install (exit $rc)"; return; }
    dpkg-query --admindir="$root/var/lib/dpkg" -W bash-completion >/dev/null 2>&1 ||
      { lfail "bash-completion is not in the standard root"; return; }
    : >"$root/var/log/policy-rc.d.log" # what the standard packages asked for is theirs
  fi
  services >"$W/$name.services.base"
  lphase "command 1: ${cmds[0]}"
  in_root "$root" 1800 "${cmds[0]}"
  rc=$?
  [ "$rc" -eq 0 ] || lfail "${cmds[0]} exited $rc"
  for f in out/paper/report/index.html out/paper/compare.md; do
    [ -s "$root/root/popc/$f" ] || lfail "${cmds[0]} did not make $f"
  done
  services >"$W/$name.services.paper"
  new=$(comm -13 "$W/$name.services.base" "$W/$name.services.paper")
  [ -z "$new" ] || lfail "${cmds[0]} installed services: $(echo $new)"
  [ ! -s "$root/var/log/policy-rc.d.log" ] ||
    lfail "${cmds[0]} tried to start or stop services: $(tr '\n' ';' <"$root/var/log/policy-rc.d.log")"
  echo "packages after command 1: $(chroot "$root" dpkg-query -W -f '${db:Status-Abbrev}\n' | grep -c '^ii') installed"
  lphase_end "command 1"
  lphase "command 2: ${cmds[1]}"
  in_root "$root" 2700 "${cmds[1]}" | tee "$W/$name.tests.out"
  rc=${PIPESTATUS[0]}
  [ "$rc" -eq 0 ] || lfail "${cmds[1]} exited $rc"
  last=$(tail -n 1 "$W/$name.tests.out")
  if [[ $last =~ ^[0-9]+\ passed,\ 0\ failed(,\ [0-9]+\ skipped)?$ ]]; then
    echo "${cmds[1]} closed with: $last"
  else
    lfail "${cmds[1]}'s last line is not 'N passed, 0 failed[, N skipped]': '$last'"
  fi
  # each build's verdicts, as meson test printed them (a skip says why in testlog.txt)
  grep -E '^ *[0-9]+/[0-9]+ .* SKIP ' "$W/$name.tests.out" | sed 's/^ */  skipped: /'
  grep -E '^ *[0-9]+/[0-9]+ .* (FAIL|TIMEOUT|ERROR|UNEXPECTEDPASS) ' "$W/$name.tests.out" | sort -u | sed 's/^ */  failed: /'
  [ -s "$root/var/log/policy-rc.d.log" ] &&
    echo "service starts refused in the root (policy-rc.d): $(awk '{ print $1 }' "$root/var/log/policy-rc.d.log" | sort -u | tr '\n' ' ')"
  lphase_end "command 2"
  echo "the root takes $(du -sm --one-file-system "$root" 2>/dev/null | cut -f1) MiB"
}

phase "both Quick start commands in each root (${roots[*]}), side by side"
for r in "${roots[@]}"; do
  lane "$r" &
  lane_pids+=($!)
  say "lane $r: pid $!, output in $W/$r.out"
done
for i in "${!lane_pids[@]}"; do wait "${lane_pids[$i]}"; done
lane_pids=()
for r in "${roots[@]}"; do
  say "---- root $r (chroot $W/$r):"
  sed 's/^/  | /' "$W/$r.out" # the inner output, indented: its closing line is not ours
  while IFS= read -r f; do failures+=("$r: $f"); done <"$W/$r.failures"
  while IFS=$'\t' read -r n s; do phase_names+=("$n") phase_secs+=("$s"); done <"$W/$r.times"
done
phase_end

print_timings
if [ ${#failures[@]} -gt 0 ]; then
  say "FAILED (${#failures[@]}):"
  printf '  - %s\n' "${failures[@]}"
  exit 1
fi
say "PASS: both Quick start commands work on fresh Debian 12 roots (${roots[*]})"
exit 0
