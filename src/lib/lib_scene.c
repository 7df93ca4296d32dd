/* libpopc: versions, errors and scenes (popc/popc.h). */
#include <stdio.h>
#include <stdlib.h>

#include "lib_private.h"
#include "popc/scene/data_path.h"
#include "popc_config.h"

POPC_API unsigned popc_lib_api_version(void)
{
	return POPC_LIB_API_VERSION;
}

POPC_API const char *popc_lib_version(void)
{
	return POPC_VERSION;
}

int popc_lib_error_set(popc_lib_error *out, int st, const char *what)
{
	if (out)
		snprintf(out->msg, sizeof out->msg, "%s", what);
	return st;
}

POPC_API int popc_lib_scene_create(popc_lib_scene **out, popc_lib_error *err)
{
	*out = NULL;
	popc_lib_scene *s = malloc(sizeof *s);
	if (!s)
		return popc_lib_error_set(err, POPC_LIB_ERR_NOMEM, "popc_lib_scene_create: out of memory");
	popc_scene_defaults(&s->scene);
	*out = s;
	return 0;
}

POPC_API int popc_lib_scene_load(popc_lib_scene *s, const char *path, popc_lib_error *err)
{
	popc_error e;
	/* the name rule of popc run (README, "Install"): a name that is no file
	 * here and has no '/' is looked up in the data directories */
	char found[POPC_PATH_MAX];
	int st = popc_data_find(POPC_DATA_SCENES, path, NULL, s->scene.data_path, found, sizeof found,
				&e);
	if (st < 0)
		return popc_lib_fail(err, st, &e);
	st = popc_scene_load(&s->scene, st == 1 ? found : path, &e);
	return popc_lib_fail(err, st, &e);
}

POPC_API int popc_lib_scene_set_data_path(popc_lib_scene *s, const char *data_path,
					  popc_lib_error *err)
{
	popc_error e;
	int st = popc_scene_set_data_path(&s->scene, data_path, "popc_lib_scene_set_data_path", &e);
	return popc_lib_fail(err, st, &e);
}

POPC_API int popc_lib_scene_set(popc_lib_scene *s, const char *key, const char *value,
				popc_lib_error *err)
{
	popc_error e;
	const char *dot = key ? strchr(key, '.') : NULL;
	if (!dot || dot == key || dot[1] == '\0' || (size_t)(dot - key) >= POPC_NAME_MAX)
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_scene_set: the key must be section.key");
	char section[POPC_NAME_MAX];
	memcpy(section, key, (size_t)(dot - key));
	section[dot - key] = '\0';
	int st = popc_scene_set(&s->scene, section, dot + 1, value ? value : "", &e);
	return popc_lib_fail(err, st, &e);
}

POPC_API int popc_lib_scene_validate(const popc_lib_scene *s, popc_lib_error *err)
{
	popc_error e;
	return popc_lib_fail(err, popc_scene_validate(&s->scene, &e), &e);
}

POPC_API double popc_lib_scene_period_s(const popc_lib_scene *s)
{
	return popc_scene_period_s(&s->scene);
}

POPC_API long long popc_lib_scene_tick_count(const popc_lib_scene *s)
{
	return popc_scene_ticks(&s->scene) + 1; /* t = 0, T, ..., duration, as popc_run */
}

POPC_API void popc_lib_scene_free(popc_lib_scene *s)
{
	free(s);
}
