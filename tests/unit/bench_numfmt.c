/* Benchmark of numfmt.h against the C library on CSV log rows.
 *
 *   bench_numfmt [rows] [runs]      (defaults: 100000 rows, 5 runs)
 *
 * Builds rows of 10 doubles shaped like a popc log (time k * 0.001, positions
 * ~1e-3, velocities ~1e-2, forces ~1, energies ~1e-4, each the result of
 * arithmetic so most need 15 to 17 digits), then on one thread times:
 *
 *   format: popc_format_double  vs  snprintf("%.17g"), both writing the rows
 *           with ',' and '\n' into one buffer;
 *   parse:  popc_parse_double   vs  strtod, both reading the same text (the
 *           one popc writes) back, checking that both give the same bits.
 *
 * Runs alternate A, B, A, B, ... and the median of the runs is reported, so
 * that frequency changes and noisy neighbours hit both sides alike. MB/s is
 * text bytes (each formatter's own output for format, the common input for
 * parse) per second. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "popc/util/clock.h"
#include "popc/util/numfmt.h"

#define COLS 10
#define MAX_RUNS 51

static uint64_t rng_state = UINT64_C(0x853c49e6748fea9b);

static double uniform(void)
{
	/* xorshift64*, top 53 bits as a double in [0, 1) */
	rng_state ^= rng_state >> 12;
	rng_state ^= rng_state << 25;
	rng_state ^= rng_state >> 27;
	return (double)((rng_state * UINT64_C(2685821657736338717)) >> 11) * 0x1p-53;
}

static int cmp_double(const void *a, const void *b)
{
	double x = *(const double *)a, y = *(const double *)b;
	return (x > y) - (x < y);
}

static double median(double *v, int n)
{
	qsort(v, (size_t)n, sizeof v[0], cmp_double);
	return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Log-like rows: a damped oscillation with noise, in SI units. */
static void make_rows(double *v, size_t rows)
{
	double x = 1e-3, vel = 0.0;
	for (size_t r = 0; r < rows; r++) {
		double t = (double)r * 0.001;
		double force = -40.0 * x - 0.3 * vel + 0.5 * (uniform() - 0.5);
		vel += force * 0.001 / 0.02;
		x += vel * 0.001;
		double *row = v + r * COLS;
		row[0] = t;
		row[1] = x;
		row[2] = x * 0.5 + 1e-4 * uniform();
		row[3] = 2e-3 * (uniform() - 0.5);
		row[4] = vel;
		row[5] = force;
		row[6] = force * 0.98 + 0.01 * uniform();
		row[7] = 0.5 * 0.02 * vel * vel;
		row[8] = 0.5 * 40.0 * x * x;
		row[9] = 1e-4 * (1.0 + uniform());
	}
}

static size_t format_popc(const double *v, size_t n, char *out)
{
	char *p = out;
	for (size_t i = 0; i < n; i++) {
		p += popc_format_double(v[i], p);
		*p++ = (i % COLS == COLS - 1) ? '\n' : ',';
	}
	*p = '\0';
	return (size_t)(p - out);
}

static size_t format_printf(const double *v, size_t n, char *out, size_t cap)
{
	char *p = out, *end = out + cap;
	for (size_t i = 0; i < n; i++) {
		p += snprintf(p, (size_t)(end - p), "%.17g", v[i]);
		*p++ = (i % COLS == COLS - 1) ? '\n' : ',';
	}
	*p = '\0';
	return (size_t)(p - out);
}

static size_t parse_popc(const char *text, size_t len, double *v)
{
	const char *p = text, *end = text + len;
	size_t n = 0;
	while (p < end) {
		size_t used = popc_parse_double(p, end, &v[n]);
		if (!used)
			break;
		n++;
		p += used + 1; /* the ',' or '\n' */
	}
	return n;
}

static size_t parse_strtod(const char *text, size_t len, double *v)
{
	const char *p = text, *end = text + len;
	size_t n = 0;
	while (p < end) {
		char *stop;
		v[n] = strtod(p, &stop);
		if (stop == p)
			break;
		n++;
		p = stop + 1;
	}
	return n;
}

int main(int argc, char **argv)
{
	size_t rows = argc > 1 ? (size_t)strtoul(argv[1], NULL, 10) : 100000;
	int runs = argc > 2 ? atoi(argv[2]) : 5;
	if (rows == 0)
		rows = 1;
	if (runs < 1 || runs > MAX_RUNS)
		runs = 5;
	size_t n = rows * COLS;
	size_t cap = n * (POPC_DOUBLE_TEXT_MAX + 2) + 1;
	double *values = malloc(n * sizeof *values);
	double *back_a = malloc(n * sizeof *back_a);
	double *back_b = malloc(n * sizeof *back_b);
	char *text_a = malloc(cap), *text_b = malloc(cap);
	if (!values || !back_a || !back_b || !text_a || !text_b) {
		fprintf(stderr, "bench_numfmt: out of memory\n");
		return 1;
	}
	make_rows(values, rows);

	double tfa[MAX_RUNS], tfb[MAX_RUNS], tpa[MAX_RUNS], tpb[MAX_RUNS];
	size_t len_a = 0, len_b = 0;
	/* One untimed warm-up of each, then the interleaved timed runs. */
	format_popc(values, n, text_a);
	format_printf(values, n, text_b, cap);
	for (int r = 0; r < runs; r++) {
		double t0 = popc_now_s();
		len_a = format_popc(values, n, text_a);
		double t1 = popc_now_s();
		len_b = format_printf(values, n, text_b, cap);
		double t2 = popc_now_s();
		tfa[r] = t1 - t0;
		tfb[r] = t2 - t1;
	}
	/* Both parsers read popc's text (what the CSV reader sees). */
	size_t na = 0, nb = 0;
	parse_popc(text_a, len_a, back_a);
	parse_strtod(text_a, len_a, back_b);
	for (int r = 0; r < runs; r++) {
		double t0 = popc_now_s();
		na = parse_popc(text_a, len_a, back_a);
		double t1 = popc_now_s();
		nb = parse_strtod(text_a, len_a, back_b);
		double t2 = popc_now_s();
		tpa[r] = t1 - t0;
		tpb[r] = t2 - t1;
	}
	int ok = na == n && nb == n && memcmp(back_a, back_b, n * sizeof *back_a) == 0 &&
		 memcmp(back_a, values, n * sizeof *back_a) == 0;

	double fa = median(tfa, runs), fb = median(tfb, runs);
	double pa = median(tpa, runs), pb = median(tpb, runs);
	printf("numfmt: %zu rows x %d doubles, median of %d interleaved runs, one thread\n", rows,
	       COLS, runs);
	printf("popc text %.2f MB (%.1f bytes/value), %%.17g text %.2f MB (%.1f bytes/value)\n",
	       (double)len_a / 1e6, (double)len_a / (double)n, (double)len_b / 1e6,
	       (double)len_b / (double)n);
	printf("%-8s %-22s %10s %12s %9s\n", "op", "implementation", "MB/s", "ns/value", "speedup");
	printf("%-8s %-22s %10.1f %12.1f %8.2fx\n", "format", "popc_format_double",
	       (double)len_a / fa / 1e6, fa / (double)n * 1e9, fb / fa);
	printf("%-8s %-22s %10.1f %12.1f %8.2fx\n", "format", "snprintf %.17g",
	       (double)len_b / fb / 1e6, fb / (double)n * 1e9, 1.0);
	printf("%-8s %-22s %10.1f %12.1f %8.2fx\n", "parse", "popc_parse_double",
	       (double)len_a / pa / 1e6, pa / (double)n * 1e9, pb / pa);
	printf("%-8s %-22s %10.1f %12.1f %8.2fx\n", "parse", "strtod", (double)len_a / pb / 1e6,
	       pb / (double)n * 1e9, 1.0);
	printf("round trip bitwise: %s\n", ok ? "yes" : "NO");

	free(values);
	free(back_a);
	free(back_b);
	free(text_a);
	free(text_b);
	return ok ? 0 : 1;
}
