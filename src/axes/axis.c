/* The axis factory (axis.h): axis.kind -> the backend's descriptor. */
#include "popc/axes/axis.h"

#include <stddef.h>
#include <string.h>

#include "axis_kind.h"

static const popc_axis_kind *const kinds[] = {&popc_axis_kind_sim, &popc_axis_kind_modbus};

static const popc_axis_kind *find_kind(const char *name)
{
	for (size_t i = 0; i < sizeof kinds / sizeof kinds[0]; i++)
		if (strcmp(kinds[i]->name, name) == 0)
			return kinds[i];
	return NULL;
}

int popc_axis_create(popc_axis **out, const popc_scene *s, const popc_axis_create_options *opt,
		     popc_error *err)
{
	*out = NULL;
	const popc_axis_kind *k = find_kind(s->axis);
	/* the scene's key table allows only the kinds above; a name that is not
	 * one of them comes from a caller that filled the scene by hand */
	if (!k)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: axis.kind = %s: this build has no such axis", s->source,
				      s->axis);
	static const popc_axis_create_options defaults;
	return k->create(out, s, opt ? opt : &defaults, err);
}

int popc_axis_is_simulated(const popc_scene *s)
{
	const popc_axis_kind *k = find_kind(s->axis);
	return k && k->simulated;
}

void popc_axis_destroy(popc_axis **a)
{
	if (a && *a) {
		(*a)->ops->destroy(*a);
		*a = NULL;
	}
}
