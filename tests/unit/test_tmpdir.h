/* A scratch directory per test program: made by test_tmpdir_make() in the
 * group setup, removed with its contents by test_tmpdir_remove() in the
 * group teardown. Header-only: each test program includes it once. */
#ifndef POPC_TEST_TMPDIR_H
#define POPC_TEST_TMPDIR_H

#include <stdio.h>
#include <stdlib.h>

static char tmpdir[256];

/* name: a short tag for the directory, e.g. "scene" */
static int test_tmpdir_make(const char *name)
{
	snprintf(tmpdir, sizeof tmpdir, "/tmp/popc-test-%s-XXXXXX", name);
	return mkdtemp(tmpdir) ? 0 : -1;
}

static int test_tmpdir_remove(void)
{
	char cmd[300];
	snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
	return system(cmd) == 0 ? 0 : -1;
}

#endif
