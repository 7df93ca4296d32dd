/* The sweep directory's lock and the output directory check (sweep_lock.h). */
#define _DEFAULT_SOURCE /* flock */
#include "popc/sweep/sweep_lock.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include "popc/util/atomic_file.h"
#include "popc/util/parse.h"

/* The lock this process holds: DIR/sweep.lock, and a shard's own file. */
static struct {
	int fd, shard_fd;             /* -1: none */
	dev_t dev;                    /* DIR/sweep.lock's identity */
	ino_t ino;
} held = {.fd = -1, .shard_fd = -1};

/* ---- the output directory, before any work ----------------------------------- */

static int dir_usable(const char *opt, const char *dir, const char *shown, popc_error *err)
{
	struct stat sb;
	if (stat(dir, &sb) != 0)
		return popc_error_set(err, POPC_ERR_INVALID, "%s %s: %s cannot be used: %s", opt, shown,
				      dir, strerror(errno));
	if (!S_ISDIR(sb.st_mode))
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s %s: %s is a file, not a directory (%s names the sweep's "
				      "output directory)",
				      opt, shown, dir, opt);
	if (access(dir, W_OK | X_OK) != 0)
		return popc_error_set(err, POPC_ERR_INVALID, "%s %s: no file can be made in %s: %s", opt,
				      shown, dir, strerror(errno));
	return 0;
}

int popc_sweep_output_dir_check(const char *opt, const char *dir, popc_error *err)
{
	if (!dir[0])
		return popc_error_set(err, POPC_ERR_INVALID, "%s '': give a directory name", opt);
	struct stat sb;
	if (stat(dir, &sb) == 0)
		return dir_usable(opt, dir, dir, err);
	if (errno != ENOENT) /* through a file (ENOTDIR), a loop, no permission */
		return popc_error_set(err, POPC_ERR_INVALID, "%s %s: cannot be used as a directory: %s",
				      opt, dir, strerror(errno));
	/* made with its missing parents (popc_mkdir_p): the nearest one that
	 * exists must take them */
	size_t len = strlen(dir);
	char *parent = malloc(len + 2);
	if (!parent)
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	memcpy(parent, dir, len + 1);
	int st = 0;
	for (;;) {
		while (len > 1 && parent[len - 1] == '/')
			parent[--len] = '\0';
		char *slash = strrchr(parent, '/');
		if (!slash) {
			strcpy(parent, ".");
		} else if (slash == parent) {
			parent[1] = '\0';
		} else {
			*slash = '\0';
			len = (size_t)(slash - parent);
		}
		if (stat(parent, &sb) == 0 || errno != ENOENT || strcmp(parent, ".") == 0 ||
		    strcmp(parent, "/") == 0) {
			st = dir_usable(opt, parent, dir, err);
			break;
		}
	}
	free(parent);
	return st;
}

/* ---- the lock ----------------------------------------------------------------- */

/* The pid a holder wrote into a lock file; -1 when none can be read. */
static long holder_pid(const char *path)
{
	char buf[32];
	int fd = open(path, O_RDONLY | O_CLOEXEC);
	if (fd < 0)
		return -1;
	ssize_t n = pread(fd, buf, sizeof buf - 1, 0);
	close(fd);
	if (n <= 0)
		return -1;
	buf[n] = '\0';
	char *end = buf;
	while (*end == ' ')
		end++;
	char *start = end;
	while (*end >= '0' && *end <= '9')
		end++;
	long long pid;
	if (popc_parse_ll_span(start, end, 1, 1LL << 30, 0, &pid) != 0)
		return -1;
	return (long)pid;
}

/* Writes our pid at the start of the lock file: a fixed-width line, so
 * that holders sharing it (shards) never leave a mixture of two. */
static void write_pid(int fd)
{
	char line[24];
	int n = snprintf(line, sizeof line, "%20ld\n", (long)getpid());
	if (pwrite(fd, line, (size_t)n, 0) != n) {
		/* the pid is for the message of a refused sweep only */
	}
}

/* Opens (creating) a lock file; the descriptor is close-on-exec (the crash
 * handler clears that before its execve). */
static int open_lock(const char *path, popc_error *err)
{
	int fd = open(path, O_RDWR | O_CREAT | O_CLOEXEC, 0666);
	if (fd >= 0)
		return fd;
	int e = errno;
	/* an -o that cannot hold a file (read-only, no permission): nothing
	 * ran, as for an -o refused by popc_sweep_output_dir_check */
	int usage = e == EACCES || e == EROFS || e == EPERM || e == ENOTDIR || e == EISDIR;
	return popc_error_set(err, usage ? POPC_ERR_INVALID : POPC_ERR_IO,
			      "%s: cannot create the sweep directory's lock: %s", path, strerror(e));
}

/* flock without waiting, EINTR retried: 0 taken, 1 held by another, -1 error */
static int try_flock(int fd, int how)
{
	for (;;) {
		if (flock(fd, how | LOCK_NB) == 0)
			return 0;
		if (errno == EINTR)
			continue;
		return errno == EWOULDBLOCK ? 1 : -1;
	}
}

static int busy(const char *path, const char *what, popc_error *err)
{
	long pid = holder_pid(path);
	char who[64];
	if (pid > 0)
		snprintf(who, sizeof who, "pid %ld", pid);
	else
		snprintf(who, sizeof who, "pid unknown");
	return popc_error_set(err, POPC_ERR_BUSY,
			      "%s: %s is in use by another popc sweep or map (%s, or a worker "
			      "process it started): two sweeps into one directory would both make "
			      "every run. Wait for it to end, or choose another -o DIR",
			      path, what, who);
}

/* A lock handed over by the popc that started this one (the crash handler's
 * execve): its descriptor, when it is DIR/sweep.lock's; else -1. */
static int inherited(const char *path, int which)
{
	const char *v = getenv(POPC_SWEEP_LOCK_FDS_ENV);
	if (!v || !v[0])
		return -1;
	const char *comma = strchr(v, ',');
	const char *start = which == 0 ? v : comma ? comma + 1 : NULL;
	if (!start)
		return -1;
	const char *end = which == 0 && comma ? comma : start + strlen(start);
	long long fd;
	if (popc_parse_ll_span(start, end, 0, 1 << 20, 0, &fd) != 0)
		return -1;
	struct stat a, b;
	if (fstat((int)fd, &a) != 0 || stat(path, &b) != 0 || a.st_dev != b.st_dev ||
	    a.st_ino != b.st_ino)
		return -1;
	fcntl((int)fd, F_SETFD, FD_CLOEXEC);
	return (int)fd;
}

/* Shards of another count than `count` that run in dir: their lock files
 * (sweep-shard-I-of-M.lock, M != count) still held. Called under
 * DIR/sweep-shards.lock, so that no shard takes its lock meanwhile. Returns
 * 0, or POPC_ERR_BUSY naming the first one found. */
static int other_counts(const char *dir, long long count, popc_error *err)
{
	DIR *d = opendir(dir);
	if (!d)
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", dir, strerror(errno));
	int st = 0;
	for (struct dirent *e; !st && (e = readdir(d)) != NULL;) {
		long long i, m;
		int used = 0;
		if (sscanf(e->d_name, "sweep-shard-%lld-of-%lld.lock%n", &i, &m, &used) != 2 ||
		    e->d_name[used] != '\0' || m == count)
			continue;
		char path[POPC_PATH_MAX + 300];
		snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
		int fd = open(path, O_RDONLY | O_CLOEXEC);
		if (fd < 0)
			continue;
		/* a shard holds its file alone: a shared lock is refused while
		 * it runs, and taken (then dropped) once it has ended */
		if (try_flock(fd, LOCK_SH) == 1) {
			char what[POPC_PATH_MAX + 160];
			snprintf(what, sizeof what,
				 "%s (shard %lld/%lld runs there; this is a shard of %lld: the shards "
				 "of one sweep have one count, or they overlap)",
				 dir, i, m, count);
			st = busy(path, what, err);
		}
		close(fd);
	}
	closedir(d);
	return st;
}

int popc_sweep_lock_take(const char *dir, const popc_sweep_shard *shard, popc_error *err)
{
	char path[POPC_PATH_MAX + 64];
	snprintf(path, sizeof path, "%s/sweep.lock", dir);
	struct stat sb;
	if (held.fd >= 0 && stat(path, &sb) == 0 && sb.st_dev == held.dev && sb.st_ino == held.ino)
		return 0;
	popc_sweep_lock_release();
	int sharded = shard && shard->count > 1;
	/* a lock file is never removed: a holder and a newcomer must lock the
	 * same file, not two files of one name */
	int fd = inherited(path, 0);
	if (fd < 0 && (fd = open_lock(path, err)) < 0)
		return fd;
	/* flock on a descriptor that holds it already (inherited) converts,
	 * never conflicts with itself */
	int r = try_flock(fd, sharded ? LOCK_SH : LOCK_EX);
	if (r != 0) {
		int e = errno;
		close(fd);
		return r > 0 ? busy(path, dir, err)
			     : popc_error_set(err, POPC_ERR_IO, "%s: flock: %s", path, strerror(e));
	}
	if (fstat(fd, &sb) != 0) {
		int e = errno;
		close(fd);
		return popc_error_set(err, POPC_ERR_IO, "%s: %s", path, strerror(e));
	}
	int shard_fd = -1;
	if (sharded) {
		char spath[POPC_PATH_MAX + 96];
		snprintf(spath, sizeof spath, "%s/sweep-shard-%lld-of-%lld.lock", dir, shard->index + 1,
			 shard->count);
		shard_fd = inherited(spath, 1);
		if (shard_fd < 0) {
			/* the check of the other counts and the taking of ours as
			 * one step: two shards of different counts started at once
			 * must not both find the other absent. Held for a directory
			 * listing only, so waited for */
			char mpath[POPC_PATH_MAX + 64];
			snprintf(mpath, sizeof mpath, "%s/sweep-shards.lock", dir);
			int mfd = open_lock(mpath, err);
			if (mfd < 0) {
				close(fd);
				return mfd;
			}
			while (flock(mfd, LOCK_EX) != 0 && errno == EINTR)
				;
			int st = other_counts(dir, shard->count, err);
			if (!st && (shard_fd = open_lock(spath, err)) < 0)
				st = shard_fd;
			if (!st && (r = try_flock(shard_fd, LOCK_EX)) != 0) {
				int e = errno;
				close(shard_fd);
				char what[POPC_PATH_MAX + 64];
				snprintf(what, sizeof what, "shard %lld/%lld of %s", shard->index + 1,
					 shard->count, dir);
				st = r > 0 ? busy(spath, what, err)
					   : popc_error_set(err, POPC_ERR_IO, "%s: flock: %s", spath,
							    strerror(e));
			}
			close(mfd);
			if (st) {
				close(fd);
				return st;
			}
		}
		r = try_flock(shard_fd, LOCK_EX);
		if (r != 0) {
			int e = errno;
			close(shard_fd);
			close(fd);
			char what[POPC_PATH_MAX + 64];
			snprintf(what, sizeof what, "shard %lld/%lld of %s", shard->index + 1, shard->count,
				 dir);
			return r > 0 ? busy(spath, what, err)
				     : popc_error_set(err, POPC_ERR_IO, "%s: flock: %s", spath, strerror(e));
		}
		write_pid(shard_fd);
	}
	write_pid(fd);
	held.fd = fd;
	held.shard_fd = shard_fd;
	held.dev = sb.st_dev;
	held.ino = sb.st_ino;
	unsetenv(POPC_SWEEP_LOCK_FDS_ENV); /* handed over: not passed on further */
	return 0;
}

void popc_sweep_lock_exec_entry(char *env_entry, size_t cap)
{
	if (held.fd < 0) {
		if (cap)
			env_entry[0] = '\0';
		return;
	}
	if (held.shard_fd >= 0)
		snprintf(env_entry, cap, "%s=%d,%d", POPC_SWEEP_LOCK_FDS_ENV, held.fd, held.shard_fd);
	else
		snprintf(env_entry, cap, "%s=%d", POPC_SWEEP_LOCK_FDS_ENV, held.fd);
}

void popc_sweep_lock_keep_across_exec(void)
{
	if (held.fd >= 0)
		fcntl(held.fd, F_SETFD, 0);
	if (held.shard_fd >= 0)
		fcntl(held.shard_fd, F_SETFD, 0);
}

void popc_sweep_lock_release(void)
{
	if (held.shard_fd >= 0)
		close(held.shard_fd);
	if (held.fd >= 0)
		close(held.fd);
	held.fd = held.shard_fd = -1;
}
