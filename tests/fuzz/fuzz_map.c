/* Map resume harness (sweep_map.h): what popc map reads back from a map
 * directory's rows when it resumes, as cmd_map.c's evaluate does: each row's
 * cells (popc_map_facts_from_row), its verdict under a criterion, and the
 * search replayed from the verdicts of one line (popc_map_search_line). The
 * rows files themselves are read by the sweep's loader (sweep_results.c),
 * which this harness does not open: it feeds rows as the loader hands them.
 *
 * Properties: a row is read or refused with a message, never half-read; its
 * facts are finite numbers and an exit status in [0, 999]; the search asks
 * only for points of the line that have no verdict, at most a scan's worth
 * at once, and answers the same twice; its result names points whose
 * verdicts say what it claims (K_ok acceptable, K_bad not, the band's top
 * acceptable and the point above it not); a search driven to its end from
 * these verdicts (the points it asks for given verdicts from the input)
 * ends within the scan and two bisections' batches.
 *
 * Input: byte 0 picks the criterion (bits 0-2), the port tolerance (bits
 * 3-4) and the scan step (bits 5-7: 1, 2, 3, 5, 8, 16, 31, 64 grid steps);
 * the rest is rows, one a line, the map's columns (a line whose run id is
 * not a point of the 98-point line is skipped, as the loader skips rows of
 * another plan). */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "popc/scene/scene.h"
#include "popc/sweep/sweep_map.h"
#include "popc/sweep/sweep_plan.h"

enum { N_K = 98 }; /* 1e2 to 1e6 N/m at 10 %: popc_map_grid_points(1e2, 1e6, 0.1) */

/* The plan of `popc map paper.ini --variant none --tol 0.1`, made once. */
static const popc_sweep_plan *map_plan(void)
{
	static popc_sweep_plan plan;
	static int made;
	if (made)
		return made > 0 ? &plan : NULL;
	made = -1;
	popc_scene base;
	popc_scene_defaults(&base);
	popc_sweep_axis *axes = calloc(2, sizeof *axes);
	popc_error err;
	char spec[128];
	if (!axes)
		return NULL;
	snprintf(spec, sizeof spec, "environment.stiffness=%.17g:%.17g:%ld:log", 1e2, 1e6,
		 popc_map_grid_points(1e2, 1e6, 0.1));
	if (popc_sweep_axis_parse("controller.variant=none", &axes[0], &err) != 0 ||
	    popc_sweep_axis_parse(spec, &axes[1], &err) != 0 ||
	    popc_sweep_plan_init(&plan, &base, axes, 2, 0, &err) != 0)
		return NULL;
	if (plan.n_runs != N_K)
		return NULL;
	made = 1;
	return &plan;
}

static void check_result(const uint8_t *data, size_t size, const unsigned char *v,
			 const popc_map_search *s, long n_scan)
{
	if (s->outcome == POPC_MAP_NEEDS_RUNS) {
		if (s->n_need < 1 || s->n_need > n_scan)
			popc_fuzz_fail(data, size, "asks for %d runs (scan of %ld)", s->n_need, n_scan);
		for (int q = 0; q < s->n_need; q++)
			if (s->need[q] < 0 || s->need[q] >= N_K || v[s->need[q]] != POPC_MAP_UNKNOWN)
				popc_fuzz_fail(data, size, "asks for point %ld, which is known or off the line",
					       s->need[q]);
		return;
	}
	long ok = s->ok_index, bad = s->bad_index, top = s->last_ok_index, above = s->last_bad_index;
	switch (s->outcome) {
	case POPC_MAP_BRACKET:
	case POPC_MAP_NOT_MONOTONIC:
	case POPC_MAP_NONE_OK:
		if (bad < 0 || bad >= N_K || v[bad] != POPC_MAP_BAD)
			popc_fuzz_fail(data, size, "first failure %ld is not an unacceptable point", bad);
		if (ok >= 0 && (ok != bad - 1 || v[ok] != POPC_MAP_OK))
			popc_fuzz_fail(data, size, "K_ok %ld is not the acceptable neighbour of %ld", ok, bad);
		if (ok < 0 && bad != 0)
			popc_fuzz_fail(data, size, "no K_ok, but the first failure %ld is not K_lo", bad);
		if (s->outcome == POPC_MAP_NOT_MONOTONIC) {
			if (top <= bad || top >= N_K || v[top] != POPC_MAP_OK)
				popc_fuzz_fail(data, size, "band top %ld is not acceptable above %ld", top, bad);
			if (above >= 0 ? above != top + 1 || v[above] != POPC_MAP_BAD : top != N_K - 1)
				popc_fuzz_fail(data, size, "band top %ld, above it %ld", top, above);
		} else if (top != -1 || above != -1)
			popc_fuzz_fail(data, size, "a band (%ld, %ld) on a monotonic result", top, above);
		break;
	case POPC_MAP_ALL_OK:
		if (ok != N_K - 1 || v[ok] != POPC_MAP_OK || bad != -1)
			popc_fuzz_fail(data, size, "above-range with K_ok %ld, K_bad %ld", ok, bad);
		break;
	case POPC_MAP_UNDECIDED_RUN:
		if (s->culprit < 0 || s->culprit >= N_K || v[s->culprit] != POPC_MAP_UNDECIDED)
			popc_fuzz_fail(data, size, "undecided, naming point %ld without that verdict",
				       s->culprit);
		break;
	default:
		popc_fuzz_fail(data, size, "outcome %d", (int)s->outcome);
	}
}

int popc_fuzz_map(const uint8_t *data, size_t size)
{
	static const long scans[8] = {1, 2, 3, 5, 8, 16, 31, 64};
	static const double tols[4] = {0, 1e-9, 1e-6, 1e-3};
	if (size < 1)
		return 0;
	const popc_sweep_plan *p = map_plan();
	if (!p) /* the harness itself is broken: said, not skipped */
		popc_fuzz_fail(data, size, "cannot make the plan of %d points", N_K);
	const popc_map_criterion crit = (popc_map_criterion)((data[0] & 7) % POPC_MAP_N_CRITERIA);
	const double tol = tols[(data[0] >> 3) & 3];
	const long scan = scans[data[0] >> 5];
	unsigned char v[N_K];
	memset(v, POPC_MAP_UNKNOWN, sizeof v);
	char row[2048];
	size_t at = 1;
	while (at < size) {
		const uint8_t *nl = memchr(data + at, '\n', size - at);
		size_t len = nl ? (size_t)(nl - (data + at)) : size - at;
		if (len < sizeof row && !memchr(data + at, '\0', len)) {
			memcpy(row, data + at, len);
			row[len] = '\0';
			popc_map_facts f;
			popc_error err;
			err.msg[0] = '\0';
			int st = popc_map_facts_from_row(p, row, &f, &err);
			if (st != 0 && !err.msg[0])
				popc_fuzz_fail(data, size, "a row refused without a message");
			/* the run id: the loader's key; four digits here */
			const char *cell;
			size_t cl;
			long id = -1;
			if (st == 0 && popc_map_row_cell(p, row, "run", &cell, &cl) == 0 && cl == 4) {
				id = 0;
				for (size_t c = 0; c < cl && id >= 0; c++)
					id = cell[c] >= '0' && cell[c] <= '9' ? id * 10 + (cell[c] - '0') : -1;
			}
			if (st == 0) {
				if (f.exit_status < 0 || f.exit_status > 999 ||
				    (f.has_chatter && !isfinite(f.chatter_s)) ||
				    (f.has_port_energy_min && !isfinite(f.port_energy_min_J)) ||
				    (f.has_device_energy_min && !isfinite(f.device_energy_min_J)) ||
				    (f.has_limit_cycle && f.limit_cycle != 0 && f.limit_cycle != 1))
					popc_fuzz_fail(data, size, "facts out of range: exit %d", f.exit_status);
				popc_map_verdict vd = popc_map_verdict_of(crit, &f, tol);
				if (vd != POPC_MAP_OK && vd != POPC_MAP_BAD && vd != POPC_MAP_UNDECIDED)
					popc_fuzz_fail(data, size, "verdict %d of a read row", (int)vd);
				if (id >= 0 && id < N_K)
					v[id] = (unsigned char)vd;
			}
		}
		at += len + 1;
	}
	/* the search from what was read back: twice the same, then driven to
	 * its end, the points it asks for given verdicts from the input's bytes */
	const long n_scan = popc_map_scan_points(N_K, scan);
	long need[N_K], need2[N_K];
	popc_map_search s, s2;
	int batches = 0;
	for (;;) {
		popc_map_search_line(v, N_K, scan, need, &s);
		popc_map_search_line(v, N_K, scan, need2, &s2);
		if (s.outcome != s2.outcome || s.n_need != s2.n_need || s.ok_index != s2.ok_index ||
		    s.bad_index != s2.bad_index || s.last_ok_index != s2.last_ok_index ||
		    s.runs != s2.runs || memcmp(need, need2, (size_t)s.n_need * sizeof *need) != 0)
			popc_fuzz_fail(data, size, "the same verdicts, two answers");
		check_result(data, size, v, &s, n_scan);
		if (s.outcome != POPC_MAP_NEEDS_RUNS)
			break;
		/* the scan, then a bisection of at most scan steps, twice over */
		if (++batches > 2 + 2 * 7)
			popc_fuzz_fail(data, size, "no end after %d batches", batches);
		for (int q = 0; q < s.n_need; q++) {
			uint8_t b = data[(size_t)(s.need[q] + batches) % size];
			v[s.need[q]] = (unsigned char)(b % 5 == 0 ? POPC_MAP_UNDECIDED
						       : b & 1  ? POPC_MAP_OK
								: POPC_MAP_BAD);
		}
	}
	return 0;
}
