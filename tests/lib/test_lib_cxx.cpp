// popc/popc.h compiles as C++ (extern "C", no C-only syntax) and links
// against libpopc from a C++ program.
#include <popc/popc.h>

#include <cstdio>

int main()
{
	popc_lib_scene *s = nullptr;
	popc_lib_error err;
	if (popc_lib_scene_create(&s, &err) != POPC_LIB_OK)
		return 1;
	popc_lib_port *p = nullptr;
	int st = popc_lib_port_create_impedance(s, 0.0, &p, &err);
	popc_lib_tick t;
	if (!st)
		popc_lib_port_step(p, 0, &t);
	std::printf("%s - C++: popc %s, API %#x, a port stepped\n", st ? "not ok" : "ok", popc_lib_version(),
		    popc_lib_api_version());
	popc_lib_port_free(p);
	popc_lib_scene_free(s);
	return st ? 1 : 0;
}
