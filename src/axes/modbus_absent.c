/* The Modbus kind of a build without libmodbus (meson option modbus,
 * meson_options.txt): axis.kind = modbus stays a valid scene, so a scene file
 * means the same on every build, but this build cannot drive it. */
#include "axis_kind.h"

static int modbus_absent_create(popc_axis **out, const popc_scene *s,
				const popc_axis_create_options *opt, popc_error *err)
{
	(void)opt;
	*out = NULL;
	return popc_error_set(err, POPC_ERR_INVALID,
			      "%s: axis.kind = modbus: this build of popc has no Modbus support (built "
			      "without libmodbus: meson -Dmodbus=disabled, or libmodbus not found); "
			      "run the scene with a popc built with libmodbus, or use axis.kind = sim",
			      s->source[0] ? s->source : "scene");
}

const popc_axis_kind popc_axis_kind_modbus = {"modbus", 0, modbus_absent_create};
