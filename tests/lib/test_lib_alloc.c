/* A step allocates nothing (docs/LIBRARY.md, "Real-time safety"): 100,000
 * ticks of every controller variant through the public API (the port's
 * step, the simulated device's exchange, the observer's step), and of every
 * admittance variant (the admittance port's step, the admittance device's
 * exchange), under an
 * allocation counter, which must read zero. The counter is malloc, calloc,
 * realloc and free defined here, over glibc's own (__libc_*): the program's
 * definitions interpose libpopc.so's calls. Under ASan, which owns malloc,
 * its hooks count instead. That the counter counts is checked too: creating
 * a port must count its allocation. The bytes a port asks for at create
 * follow its variant and window (docs/LIBRARY.md): a windowed-po port of N
 * ticks asks for exactly N doubles more than a port of variant none. */
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "popc/popc.h"
#include "popc/core/admittance.h" /* POPC_ADMITTANCE_VARIANT_COUNT only */
#include "popc/core/controller.h" /* POPC_VARIANT_COUNT only: every variant is here */

static volatile long long allocations;
static volatile size_t allocated_bytes; /* asked for by malloc, calloc and realloc */

#if defined(__SANITIZE_ADDRESS__)
#define COUNTER_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define COUNTER_ASAN 1
#endif
#endif

#ifdef COUNTER_ASAN
/* the sanitizers' runtime's hooks (compiler-rt's allocator_interface.h,
 * which gcc does not install) */
int __sanitizer_install_malloc_and_free_hooks(void (*malloc_hook)(const volatile void *, size_t),
					      void (*free_hook)(const volatile void *));
static void on_malloc(const volatile void *p, size_t n)
{
	(void)p;
	allocations++;
	allocated_bytes += n;
}
static void on_free(const volatile void *p)
{
	if (p)
		allocations++;
}
static void counter_install(void)
{
	__sanitizer_install_malloc_and_free_hooks(on_malloc, on_free);
}
#else
void *__libc_malloc(size_t n);
void *__libc_calloc(size_t m, size_t n);
void *__libc_realloc(void *p, size_t n);
void __libc_free(void *p);
void *malloc(size_t n);
void *calloc(size_t m, size_t n);
void *realloc(void *p, size_t n);
void free(void *p);
void *malloc(size_t n)
{
	allocations++;
	allocated_bytes += n;
	return __libc_malloc(n);
}
void *calloc(size_t m, size_t n)
{
	allocations++;
	allocated_bytes += m * n;
	return __libc_calloc(m, n);
}
void *realloc(void *p, size_t n)
{
	allocations++;
	allocated_bytes += n;
	return __libc_realloc(p, n);
}
void free(void *p)
{
	if (p)
		allocations++;
	__libc_free(p);
}
static void counter_install(void)
{
}
#endif

static const char *const variants[] = {
	"none", "po-pc", "ref-energy", "filtered-velocity", "ignore", "hold", "improved",
	"pc-off-reversals", "energy-bounding", "windowed-po",
};
#define N_VARIANTS (int)(sizeof variants / sizeof variants[0])
#define STEPS 100000

static const char *const adm_variants[] = {
	"none", "parallel-pc", "parallel-ignore", "parallel-hold", "parallel-improved",
};
#define N_ADM_VARIANTS (int)(sizeof adm_variants / sizeof adm_variants[0])

/* The admittance port and device of the admittance scene: 0 or 1 (failed) */
static int admittance_variant(const char *scene_path, const char *variant)
{
	popc_lib_error err;
	popc_lib_scene *s = NULL;
	popc_lib_port *port = NULL;
	popc_lib_sim *sim = NULL;
	popc_lib_admittance_sample smp;
	int st = popc_lib_scene_create(&s, &err);
	if (!st)
		st = popc_lib_scene_load(s, scene_path, &err);
	if (!st)
		st = popc_lib_scene_set(s, "admittance.variant", variant, &err);
	if (!st)
		st = popc_lib_scene_set(s, "run.duration", "200", &err);
	long long before_create = allocations;
	if (!st)
		st = popc_lib_port_create_admittance(s, &port, &err);
	long long create_allocs = allocations - before_create;
	if (!st)
		st = popc_lib_sim_create_admittance(s, &sim, &smp, &err);
	if (st) {
		printf("not ok - admittance %s: %s\n", variant, err.msg);
		popc_lib_port_free(port);
		popc_lib_scene_free(s);
		return 1;
	}
	long long before = allocations, active = 0;
	for (int k = 0; k < STEPS && !st; k++) {
		popc_lib_tick t;
		popc_lib_admittance_tick a;
		popc_lib_port_step_admittance(port, smp.count, smp.force_count, &t, &a);
		active += a.v_pc_mps != 0.0;
		st = popc_lib_sim_exchange_admittance(sim, a.v_c_mps, &smp, &err);
	}
	long long during = allocations - before;
	int failed = 1;
	if (st)
		printf("not ok - admittance %s: %s\n", variant, err.msg);
	else if (create_allocs < 1)
		printf("not ok - admittance %s: the counter saw no allocation in "
		       "popc_lib_port_create_admittance: it does not count\n", variant);
	else if (during != 0)
		printf("not ok - admittance %s: %lld allocator calls in %d steps\n", variant, during, STEPS);
	else {
		printf("ok - admittance %s: 0 allocator calls in %d steps (port, device; PC active on "
		       "%lld ticks)\n", variant, STEPS, active);
		failed = 0;
	}
	popc_lib_sim_free(sim);
	popc_lib_port_free(port);
	popc_lib_scene_free(s);
	return failed;
}

/* The bytes popc_lib_port_create_impedance asks for with the scene's
 * controller.variant = variant and `key` = value (key NULL: none); 0 when
 * the port cannot be made. */
static size_t port_bytes(const char *scene_path, const char *variant, const char *key,
			 const char *value)
{
	popc_lib_error err;
	popc_lib_scene *s = NULL;
	popc_lib_port *port = NULL;
	int st = popc_lib_scene_create(&s, &err);
	if (!st)
		st = popc_lib_scene_load(s, scene_path, &err);
	if (!st)
		st = popc_lib_scene_set(s, "controller.variant", variant, &err);
	if (!st && key)
		st = popc_lib_scene_set(s, key, value, &err);
	size_t before = allocated_bytes;
	if (!st)
		st = popc_lib_port_create_impedance(s, 0.0, &port, &err);
	size_t bytes = allocated_bytes - before;
	if (st)
		printf("# %s: %s\n", variant, err.msg);
	popc_lib_port_free(port);
	popc_lib_scene_free(s);
	return st ? 0 : bytes;
}

/* A port is sized for its variant and window when it is made: variant none
 * holds no ring (it held a 4096-double ring, 34 kB, before), windowed-po
 * one of controller.po_window doubles, pc-off-reversals one of
 * controller.reversal_count ticks. 0 or 1 (failed). */
static int port_sizes(const char *scene_path)
{
	const size_t none = port_bytes(scene_path, "none", NULL, NULL);
	const struct {
		const char *variant, *key, *value;
		size_t ring;
	} sized[] = {
		{"ref-energy", NULL, NULL, 0},
		{"windowed-po", "controller.po_window", "1", sizeof(double)},
		{"windowed-po", "controller.po_window", "25", 25 * sizeof(double)},
		{"windowed-po", "controller.po_window", "4096", 4096 * sizeof(double)},
		{"pc-off-reversals", "controller.reversal_count", "4", 4 * sizeof(long long)},
		{"pc-off-reversals", "controller.reversal_count", "64", 64 * sizeof(long long)},
	};
	int failed = 0;
	if (none == 0 || none >= 4096) {
		printf("not ok - a port of variant none asks for %zu bytes at create; at most a page "
		       "(4096) without a window\n", none);
		failed = 1;
	}
	for (size_t i = 0; i < sizeof sized / sizeof sized[0]; i++) {
		size_t b = port_bytes(scene_path, sized[i].variant, sized[i].key, sized[i].value);
		if (b != none + sized[i].ring) {
			printf("not ok - a %s port (%s = %s) asks for %zu bytes at create; expected %zu "
			       "(none's %zu and its ring's %zu)\n", sized[i].variant,
			       sized[i].key ? sized[i].key : "-", sized[i].value ? sized[i].value : "-", b,
			       none + sized[i].ring, none, sized[i].ring);
			failed = 1;
		}
	}
	if (!failed)
		printf("ok - a port asks for %zu bytes at create, and its ring's length more with "
		       "windowed-po and pc-off-reversals\n", none);
	return failed;
}

int main(int argc, char **argv)
{
	if (argc < 3) {
		fprintf(stderr, "usage: test_lib_alloc SCENE ADMITTANCE_SCENE\n");
		return 2;
	}
	counter_install();
	int failed = 0;
	if (N_VARIANTS != POPC_VARIANT_COUNT) {
		printf("not ok - the test lists %d variants, popc has %d\n", N_VARIANTS, POPC_VARIANT_COUNT);
		return 1;
	}
	if (N_ADM_VARIANTS != POPC_ADMITTANCE_VARIANT_COUNT) {
		printf("not ok - the test lists %d admittance variants, popc has %d\n", N_ADM_VARIANTS,
		       POPC_ADMITTANCE_VARIANT_COUNT);
		return 1;
	}
	failed |= port_sizes(argv[1]);
	for (int v = 0; v < N_ADM_VARIANTS; v++)
		failed |= admittance_variant(argv[2], adm_variants[v]);
	for (int v = 0; v < N_VARIANTS; v++) {
		popc_lib_error err;
		popc_lib_scene *s = NULL;
		popc_lib_port *port = NULL;
		popc_lib_sim *sim = NULL;
		popc_lib_observer *obs = NULL;
		popc_lib_sample smp;
		int st = popc_lib_scene_create(&s, &err);
		if (!st)
			st = popc_lib_scene_load(s, argv[1], &err);
		if (!st)
			st = popc_lib_scene_set(s, "controller.variant", variants[v], &err);
		if (!st)
			st = popc_lib_scene_set(s, "run.duration", "200", &err);
		long long before_create = allocations;
		if (!st)
			st = popc_lib_port_create_impedance(s, 0.0, &port, &err);
		long long create_allocs = allocations - before_create;
		if (!st)
			st = popc_lib_sim_create(s, &sim, &smp, &err);
		if (!st)
			st = popc_lib_observer_create(s, &obs, &err);
		if (st) {
			printf("not ok - %s: %s\n", variants[v], err.msg);
			return 1;
		}
		long long before = allocations;
		double W_sum = 0.0;
		for (int k = 0; k < STEPS && !st; k++) {
			popc_lib_tick t;
			double W;
			/* the second half through popc_lib_sim_tick (API 1.3) */
			if (k < STEPS / 2) {
				popc_lib_port_step(port, smp.count, &t);
				st = popc_lib_sim_exchange(sim, t.f_c_N, &smp, &err);
			} else {
				st = popc_lib_sim_tick(port, sim, &smp, &t, &err);
			}
			popc_lib_observer_step(obs, &t, &W, NULL);
			W_sum += W;
		}
		long long during = allocations - before;
		if (st) {
			printf("not ok - %s: %s\n", variants[v], err.msg);
			failed = 1;
		} else if (create_allocs < 1) {
			printf("not ok - %s: the counter saw no allocation in popc_lib_port_create_impedance: "
			       "it does not count\n", variants[v]);
			failed = 1;
		} else if (during != 0) {
			printf("not ok - %s: %lld allocator calls in %d steps\n", variants[v], during, STEPS);
			failed = 1;
		} else {
			printf("ok - %s: 0 allocator calls in %d steps (port, observer, device; the "
			       "second half by popc_lib_sim_tick; W sum %g)\n",
			       variants[v], STEPS, W_sum);
		}
		popc_lib_observer_free(obs);
		popc_lib_sim_free(sim);
		popc_lib_port_free(port);
		popc_lib_scene_free(s);
	}
	return failed;
}
