/* libFuzzer's entry point for one harness, chosen at compile time with
 * -DPOPC_FUZZ_TARGET=popc_fuzz_NAME (run-fuzz.sh). */
#include "fuzz.h"

#ifndef POPC_FUZZ_TARGET
#error "define POPC_FUZZ_TARGET"
#endif

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
	return POPC_FUZZ_TARGET(data, size);
}
