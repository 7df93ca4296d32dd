/* The sweep directory's lock (src/sweep/sweep_lock.c), and the check of an
 * output directory before any work.
 *
 * Two sweeps (or maps, or a resume beside a running sweep) into one
 * directory would each make every run: the rows files would hold each run
 * twice. So a sweep holds DIR/sweep.lock for its whole life, with flock(2):
 * the kernel releases it when the last descriptor of its open file goes,
 * i.e. when the holder and every worker it forked (which share the
 * descriptor) have ended, however they end (SIGKILL included). A shard I/N
 * holds it shared and DIR/sweep-shard-I-of-N.lock exclusively, so that the
 * shards of one sweep (a Slurm array into one DIR) run side by side and the
 * same shard twice does not; nor do shards of two counts, which overlap (a
 * shard looks for the others' files under DIR/sweep-shards.lock). The holder writes its pid into the lock file,
 * which a refused sweep names. Readers (merge, stats) take no lock: they
 * read whole rows (sweep_results.c) and a whole summary.csv (renamed into
 * place).
 *
 * One sweep directory's lock per process, kept here. The -j 1 crash
 * handler starts popc again in the same process (execve): it clears the
 * descriptors' close-on-exec flags first (popc_sweep_lock_keep_across_exec)
 * and names them in POPC_SWEEP_LOCK_FDS, so the new popc takes over the lock
 * it already holds instead of finding it taken by itself. */
#ifndef POPC_SWEEP_LOCK_H
#define POPC_SWEEP_LOCK_H

#include "popc/sweep/sweep_plan.h"
#include "popc/util/error.h"

/* The environment variable that hands the held lock's descriptors to the
 * popc the crash handler starts: "FD" or "FD,SHARD_FD". */
#define POPC_SWEEP_LOCK_FDS_ENV "POPC_SWEEP_LOCK_FDS"

/* Whether DIR can be a sweep's output, before any work: it is a directory
 * where files can be made, or does not exist and its nearest existing parent
 * is such a directory. Otherwise POPC_ERR_INVALID naming opt, DIR and why
 * (a file, a scene, a read-only directory). */
int popc_sweep_output_dir_check(const char *opt, const char *dir, popc_error *err);

/* Takes DIR's lock (DIR exists) for the runs of shard (NULL or 1/1: the
 * whole sweep). Returns 0; POPC_ERR_BUSY when another popc holds it, naming
 * its pid; POPC_ERR_INVALID when the lock file cannot be made (a read-only
 * DIR: nothing ran); another negative popc_status otherwise. Taking it
 * again for the same DIR is a no-op. */
int popc_sweep_lock_take(const char *dir, const popc_sweep_shard *shard, popc_error *err);

/* Lets the held lock's descriptors survive an execve and sets
 * POPC_SWEEP_LOCK_FDS_ENV's value into env_entry (cap bytes: "NAME=FDS"),
 * "" when no lock is held. Called when the crash handler is armed. */
void popc_sweep_lock_exec_entry(char *env_entry, size_t cap);

/* Async-signal-safe: clears the close-on-exec flag of the held lock's
 * descriptors (the crash handler, right before execve). */
void popc_sweep_lock_keep_across_exec(void);

/* Releases the held lock (no-op when none). */
void popc_sweep_lock_release(void);

#endif
