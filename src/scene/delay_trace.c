/* Delays in seconds and from trace files (delay_trace.h has the rules). */
#include "popc/scene/delay_trace.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#include "popc/util/parse.h"
#include "popc/util/text.h"

int popc_seconds_to_ticks(double seconds, double rate_Hz, long long *ticks)
{
	const double x = seconds * rate_Hz;
	if (!(x >= 0.0) || !(x <= POPC_CHANNEL_MAX_DELAY_TICKS + 0.5)) {
		*ticks = x >= 0.0 ? POPC_CHANNEL_MAX_DELAY_TICKS + 1 : 0;
		return -1;
	}
	const double whole = nearbyint(x);
	*ticks = (long long)whole;
	if (fabs(x - whole) <= POPC_WHOLE_TICK_TOLERANCE && whole <= POPC_CHANNEL_MAX_DELAY_TICKS)
		return 0;
	*ticks = (long long)floor(x);
	return -1;
}

/* The message for seconds that are no whole ticks: the two nearest that are */
static int not_whole(popc_error *err, const char *where, const char *what, double seconds,
		     double rate_Hz, long long below)
{
	if (below > POPC_CHANNEL_MAX_DELAY_TICKS)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s%s %g s is %.17g ticks at run.rate = %g Hz; allowed at most "
				      "%d ticks (%g s)",
				      where, what, seconds, seconds * rate_Hz, rate_Hz,
				      POPC_CHANNEL_MAX_DELAY_TICKS, POPC_CHANNEL_MAX_DELAY_TICKS / rate_Hz);
	return popc_error_set(err, POPC_ERR_INVALID,
			      "%s%s %g s is %.17g ticks at run.rate = %g Hz, not a whole number "
			      "(within %g); allowed a whole number of periods, e.g. %.17g s (%lld "
			      "ticks) or %.17g s (%lld)",
			      where, what, seconds, seconds * rate_Hz, rate_Hz,
			      POPC_WHOLE_TICK_TOLERANCE, (double)below / rate_Hz, below,
			      (double)(below + 1) / rate_Hz, below + 1);
}

int popc_scene_channel_ticks(const popc_scene *s, const popc_scene_channel *dir, const char *name,
			     int *delay_ticks, int *jitter_ticks, popc_error *err)
{
	*delay_ticks = dir->delay_ticks;
	*jitter_ticks = dir->jitter_ticks;
	const char *src = s->source[0] ? s->source : "scene";
	const struct {
		const char *ticks_key, *s_key;
		int given_ticks;
		double given_s;
		int *out;
	} k[2] = {{"delay_ticks", "delay_s", dir->delay_ticks, dir->delay_s, delay_ticks},
		  {"jitter_ticks", "jitter_s", dir->jitter_ticks, dir->jitter_s, jitter_ticks}};
	for (int i = 0; i < 2; i++) {
		if (k[i].given_s == 0.0)
			continue;
		if (k[i].given_ticks != 0)
			return popc_error_set(err, POPC_ERR_INVALID,
					      "%s: %s.%s = %d and %s.%s = %g s: give one of them", src,
					      name, k[i].ticks_key, k[i].given_ticks, name, k[i].s_key,
					      k[i].given_s);
		long long t;
		if (popc_seconds_to_ticks(k[i].given_s, s->rate_Hz, &t) != 0) {
			char where[POPC_PATH_MAX + 80];
			snprintf(where, sizeof where, "%s: %s.%s =", src, name, k[i].s_key);
			return not_whole(err, where, "", k[i].given_s, s->rate_Hz, t);
		}
		*k[i].out = (int)t;
	}
	return 0;
}

int popc_delay_trace_load(const char *path, double rate_Hz, popc_delay_trace *out,
			  popc_error *err)
{
	memset(out, 0, sizeof *out);
	FILE *f = fopen(path, "r");
	if (!f) /* bad input, as a missing table is (exit 2) */
		return popc_error_set(err, POPC_ERR_INVALID, "%s: cannot open delay trace: %s", path,
				      strerror(errno));
	uint64_t h = 0xcbf29ce484222325u; /* FNV-1a 64: offset basis, prime */
	size_t cap = 256, n = 0;
	int *d = malloc(cap * sizeof *d);
	char *line = NULL;
	size_t line_cap = 0;
	ssize_t len;
	int lineno = 0, status = 0, in_seconds = -1; /* -1: no header yet */
	while (d && (len = getline(&line, &line_cap, f)) >= 0) {
		lineno++;
		for (ssize_t i = 0; i < len; i++)
			h = (h ^ (unsigned char)line[i]) * 0x100000001b3u;
		while (len > 0 && (line[len - 1] == '\n' || line[len - 1] == '\r'))
			line[--len] = '\0';
		if (memchr(line, '\0', (size_t)len)) {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: a NUL byte in the line (a trace is a text file)",
						path, lineno);
			break;
		}
		const char *p = line, *end = line + len;
		if (lineno == 1 && strncmp(p, "\xEF\xBB\xBF", 3) == 0)
			p += 3; /* a UTF-8 byte order mark */
		popc_trim_blanks(&p, &end);
		if (p == end || *p == '#')
			continue;
		if (in_seconds < 0) {
			size_t hl = (size_t)(end - p);
			if (hl == 11 && memcmp(p, "delay_ticks", 11) == 0)
				in_seconds = 0;
			else if (hl == 7 && memcmp(p, "delay_s", 7) == 0)
				in_seconds = 1;
			else {
				status = popc_error_set(err, POPC_ERR_INVALID,
							"%s:%d: '%.*s': expected the header delay_ticks or "
							"delay_s (the unit of the delays below it)",
							path, lineno, (int)(end - p), p);
				break;
			}
			continue;
		}
		long long t = 0;
		if (in_seconds) {
			double v;
			if (popc_parse_double_span(p, end, &v) != POPC_PARSE_OK || !(v >= 0.0)) {
				status = popc_error_set(err, POPC_ERR_INVALID,
							"%s:%d: '%.*s': expected a delay in seconds, a finite "
							"number >= 0; allowed [0, %g] s at run.rate = %g Hz",
							path, lineno, (int)(end - p), p,
							POPC_CHANNEL_MAX_DELAY_TICKS / rate_Hz, rate_Hz);
				break;
			}
			if (popc_seconds_to_ticks(v, rate_Hz, &t) != 0) {
				char where[POPC_PATH_MAX + 40];
				snprintf(where, sizeof where, "%s:%d: delay_s", path, lineno);
				status = not_whole(err, where, "", v, rate_Hz, t);
				break;
			}
		} else if (popc_parse_ll_span(p, end, 0, POPC_CHANNEL_MAX_DELAY_TICKS, 0, &t) !=
			   POPC_PARSE_OK) {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: '%.*s': expected a delay in ticks, a whole number; "
						"allowed [0, %d]",
						path, lineno, (int)(end - p), p, POPC_CHANNEL_MAX_DELAY_TICKS);
			break;
		}
		if (n == POPC_DELAY_TRACE_MAX_LINES) {
			status = popc_error_set(err, POPC_ERR_INVALID,
						"%s:%d: more than %d delays; allowed at most %d", path,
						lineno, POPC_DELAY_TRACE_MAX_LINES,
						POPC_DELAY_TRACE_MAX_LINES);
			break;
		}
		if (n == cap) {
			int *nd = realloc(d, 2 * cap * sizeof *d);
			if (!nd) {
				status = popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
				break;
			}
			d = nd;
			cap *= 2;
		}
		d[n++] = (int)t;
	}
	/* a read error (a directory: EISDIR) must not read as an empty trace */
	int read_failed = ferror(f), read_errno = errno;
	free(line);
	fclose(f);
	if (!status && !d)
		status = popc_error_set(err, POPC_ERR_NOMEM, "%s: out of memory", path);
	if (!status && read_failed)
		status = popc_error_set(err, POPC_ERR_INVALID, "%s: cannot read delay trace: %s",
					path, strerror(read_errno));
	if (!status && in_seconds < 0)
		status = popc_error_set(err, POPC_ERR_INVALID,
					"%s: no header: expected a line delay_ticks or delay_s, then one "
					"delay a line",
					path);
	if (!status && n == 0)
		status = popc_error_set(err, POPC_ERR_INVALID,
					"%s: no delays after the header (one a line)", path);
	if (status) {
		free(d);
		return status;
	}
	out->n = (int)n;
	out->ticks = d;
	out->fnv1a = h;
	return 0;
}

void popc_delay_trace_free(popc_delay_trace *t)
{
	free(t->ticks);
	t->ticks = NULL;
	t->n = 0;
}
