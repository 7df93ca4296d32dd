/* Operator intent table harness (intent.h): a table that loads has finite,
 * strictly increasing times, values within their key's range, and gives a
 * finite operator input everywhere, the same bitwise through the segment
 * shortcut (popc_intent_segment_input); a refusal names the table and, where
 * it names a line, a line of the table.
 *
 * Input: byte 0 bit 0 picks the quantity (position or force); the rest is
 * the table. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fuzz.h"
#include "popc/core/intent.h"
#include "popc/scene/scene.h"
#include "popc/scene/from_scene.h"

static uint64_t bits_of(double d)
{
	uint64_t b;
	memcpy(&b, &d, sizeof b);
	return b;
}

static void check_at(const uint8_t *data, size_t size, popc_intent *in, double t)
{
	if (!isfinite(t))
		return;
	popc_plant_input u, w;
	double next;
	popc_intent_input(in, t, &u, &next);
	if (!isfinite(u.u0_N) || !isfinite(u.u1_Nps))
		popc_fuzz_fail(data, size, "at t = %.17g: u0 = %g N, u1 = %g N/s", t, u.u0_N,
			       u.u1_Nps);
	if (!isfinite(popc_intent_xd(in, t)))
		popc_fuzz_fail(data, size, "at t = %.17g: x_d = %g", t, popc_intent_xd(in, t));
	popc_intent_segment g;
	popc_intent_segment_at(in, t, &g);
	if (!g.affine)
		return;
	popc_intent_segment_input(&g, t, &w);
	if (bits_of(u.u0_N) != bits_of(w.u0_N) || bits_of(u.u1_Nps) != bits_of(w.u1_Nps) ||
	    !(next == g.t_next_s))
		popc_fuzz_fail(data, size, "at t = %.17g: input %.17g %.17g (next %g), segment %.17g %.17g (next %g)",
			       t, u.u0_N, u.u1_Nps, next, w.u0_N, w.u1_Nps, g.t_next_s);
}

int popc_fuzz_intent(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	const int force = data[0] & 1;
	char path[64];
	int fd = popc_fuzz_file(data + 1, size - 1, path, sizeof path);
	if (fd < 0)
		return 0;
	popc_scene s;
	popc_scene_defaults(&s);
	s.intent = POPC_INTENT_TABLE;
	s.op_table_quantity = force ? POPC_TABLE_FORCE : POPC_TABLE_POSITION;
	snprintf(s.op_table, sizeof s.op_table, "%s", path);
	popc_intent in;
	popc_error err;
	err.msg[0] = '\0';
	if (popc_intent_from_scene(&in, &s, &err) != 0) {
		size_t n = strlen(path);
		if (strncmp(err.msg, path, n) != 0)
			popc_fuzz_fail(data, size, "error without the path: %s", err.msg);
		if (err.msg[n] == ':' && err.msg[n + 1] >= '0' && err.msg[n + 1] <= '9' &&
		    !popc_fuzz_names_line(err.msg, path, popc_fuzz_count_lines(data + 1, size - 1),
					  NULL))
			popc_fuzz_fail(data, size, "error naming a line not in the table: %s", err.msg);
		popc_fuzz_file_close(fd);
		return 0;
	}
	popc_fuzz_file_close(fd);
	const double q_max = force ? 1e6 : 1e3;
	if (in.n < 1)
		popc_fuzz_fail(data, size, "a table of no points");
	for (size_t i = 0; i < in.n; i++) {
		if (!isfinite(in.t[i]) || !(fabs(in.q[i]) <= q_max) ||
		    (i > 0 && !(in.t[i] > in.t[i - 1])))
			popc_fuzz_fail(data, size, "point %zu: t = %g, q = %g", i, in.t[i], in.q[i]);
	}
	/* before, on, inside and after every segment, in increasing time as a
	 * run reads it, then once more from the start (the cursor goes back) */
	for (int pass = 0; pass < 2; pass++) {
		check_at(data, size, &in, in.t[0] - 1.0);
		for (size_t i = 0; i < in.n && i < 256; i++) {
			check_at(data, size, &in, in.t[i]);
			if (i + 1 < in.n)
				check_at(data, size, &in, in.t[i] * 0.5 + in.t[i + 1] * 0.5);
		}
		check_at(data, size, &in, in.t[in.n - 1] + 1.0);
	}
	popc_intent_free(&in);
	return 0;
}
