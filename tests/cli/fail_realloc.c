/* LD_PRELOAD shim for tests/cli/test_popc_cli.sh: every realloc() fails with
 * ENOMEM, as when memory is exhausted. The option lists of the popc verbs
 * grow with realloc (popc_cli_push), the first realloc a `popc run --set`,
 * `popc scene show --set` or `popc sweep --vary` command line makes, so the
 * shim reaches the out-of-memory path of option parsing and nothing else.
 * It never allocates, so a sanitizer's allocator never sees its pointers. */
#include <errno.h>
#include <stddef.h>

void *realloc(void *ptr, size_t size);

void *realloc(void *ptr, size_t size)
{
	(void)ptr;
	(void)size;
	errno = ENOMEM;
	return NULL;
}
