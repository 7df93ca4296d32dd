/* A device's 1 kHz servo callback on libpopc's public API (docs/LIBRARY.md).
 *
 * A haptic device's SDK calls the application once a period with the
 * encoder's count and takes a force back. Here the "device" is popc's
 * simulated one (popc_lib_sim: the scene's operator, plant and encoder), so
 * the example runs anywhere and its log can be checked: its rows equal those
 * of `popc run SCENE --log` bit for bit (tests/lib/test_device_loop.sh).
 * On real hardware, servo_callback stays as it is and the SDK calls it.
 *
 *     device_loop SCENE [LOG|-] [section.key=value ...]
 *
 * Build against an installed popc:
 *     cc device_loop.c $(pkg-config --cflags --libs popc) -o device_loop */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <popc/popc.h>

/* What the application keeps between callbacks. */
typedef struct app {
	popc_lib_port *port;        /* the VE and PO/PC: made before the loop starts */
	popc_lib_log_writer *log;   /* NULL: no log */
	popc_lib_sample sample;     /* the device's last sample (for the log's x_true, E_port) */
	int log_failed;
} app;

/* The servo callback: count in, force out. No allocation, no lock, no system
 * call in the step; the log write is buffered (it writes out when its
 * buffer fills: a real-time program would hand rows to another thread). */
static double servo_callback(app *a, long long count)
{
	popc_lib_tick tick;
	popc_lib_port_step(a->port, count, &tick);
	if (a->log && !a->log_failed) {
		popc_lib_row row = {.tick = tick, .x_true_m = a->sample.x_true_m,
				    .E_port_J = a->sample.E_port_J};
		popc_lib_error err;
		if (popc_lib_log_write_row(a->log, &row, &err)) {
			fprintf(stderr, "device_loop: %s\n", err.msg);
			a->log_failed = 1;
		}
	}
	return tick.f_c_N;
}

int main(int argc, char **argv)
{
	if (argc < 2 || strcmp(argv[1], "--help") == 0) {
		fprintf(argc < 2 ? stderr : stdout,
			"usage: device_loop SCENE [LOG|-] [section.key=value ...]\n");
		return argc < 2 ? 2 : 0;
	}
	popc_lib_error err;
	popc_lib_scene *scene = NULL;
	int st = popc_lib_scene_create(&scene, &err);
	/* a bare SCENE name is looked up where popc run looks (the library
	 * reads no environment: the program passes POPC_DATA_PATH) */
	if (!st)
		st = popc_lib_scene_set_data_path(scene, getenv("POPC_DATA_PATH"), &err);
	if (!st)
		st = popc_lib_scene_load(scene, argv[1], &err);
	for (int i = 3; !st && i < argc; i++) {
		char key[128];
		const char *eq = strchr(argv[i], '=');
		if (!eq || (size_t)(eq - argv[i]) >= sizeof key) {
			fprintf(stderr, "device_loop: '%s': expected section.key=value\n", argv[i]);
			popc_lib_scene_free(scene);
			return 2;
		}
		memcpy(key, argv[i], (size_t)(eq - argv[i]));
		key[eq - argv[i]] = '\0';
		st = popc_lib_scene_set(scene, key, eq + 1, &err);
	}
	app a = {0};
	popc_lib_sim *device = NULL;
	if (!st)
		st = popc_lib_port_create_impedance(scene, 0.0, &a.port, &err);
	if (!st)
		st = popc_lib_sim_create(scene, &device, &a.sample, &err);
	if (!st && argc > 2)
		st = popc_lib_log_writer_open(&a.log, argv[2], scene, "sim", POPC_LIB_LOG_X_TRUE, &err);
	if (st) {
		fprintf(stderr, "device_loop: %s\n", err.msg);
		popc_lib_sim_free(device);
		popc_lib_port_free(a.port);
		popc_lib_scene_free(scene);
		return st == POPC_LIB_ERR_INVALID ? 2 : 1;
	}
	/* the device's loop: t = 0, T, ..., the scene's duration */
	const long long ticks = popc_lib_scene_tick_count(scene);
	const char *why = "completed";
	for (long long k = 0; k < ticks && !a.log_failed; k++) {
		double f_c_N = servo_callback(&a, a.sample.count);
		if (k + 1 < ticks && (st = popc_lib_sim_exchange(device, f_c_N, &a.sample, &err)) != 0) {
			fprintf(stderr, "device_loop: %s\n", err.msg);
			why = "device error";
			break;
		}
	}
	if (a.log_failed)
		why = "log write failed";
	int cst = popc_lib_log_writer_close(a.log, why, &err);
	if (cst)
		fprintf(stderr, "device_loop: %s\n", err.msg);
	popc_lib_sim_free(device);
	popc_lib_port_free(a.port);
	popc_lib_scene_free(scene);
	return st || cst || a.log_failed ? 1 : 0;
}
