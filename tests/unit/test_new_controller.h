/* A controller for a test: popc_controller_create, which must succeed (the
 * caller frees it with popc_controller_free). Include after cmocka.h. */
#ifndef POPC_TEST_NEW_CONTROLLER_H
#define POPC_TEST_NEW_CONTROLLER_H

#include "popc/core/controller.h"

static inline popc_controller *new_controller(const popc_controller_config *cfg)
{
	popc_controller *c = NULL;
	popc_error err;
	if (popc_controller_create(cfg, &c, &err) != 0)
		fail_msg("popc_controller_create: %s", err.msg);
	return c;
}

#endif
