/* INI harnesses: scene files (popc_scene_load), drive register maps
 * (popc_register_map_load) and the line reader under both
 * (popc_ini_read_line, include/popc/scene/ini_lines.h).
 *
 * Properties: an error names the file and, where it names a line, a line of
 * the file; a scene that loads and validates writes a text that loads to the
 * same scene; a map that loads has finite scales and soft limits; the line
 * reader returns every line that fits, blanks stripped, counted as the file
 * counts it, and refuses exactly the lines that do not fit or hold a NUL
 * byte. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz.h"
#include "popc/scene/ini_lines.h"
#ifdef POPC_FUZZ_MODBUS /* a build with the Modbus family (meson option modbus) */
#include "popc/axes/register_map.h"
#endif
#include "popc/scene/scene.h"

/* The error names the file; a "PATH:N:" names a line of the file. */
static void check_error(const uint8_t *data, size_t size, const char *msg, const char *path,
			long long lines)
{
	size_t n = strlen(path);
	if (strncmp(msg, path, n) != 0)
		popc_fuzz_fail(data, size, "error without the path: %s", msg);
	if (msg[n] == ':' && msg[n + 1] >= '0' && msg[n + 1] <= '9' &&
	    !popc_fuzz_names_line(msg, path, lines, NULL))
		popc_fuzz_fail(data, size, "error naming a line not in the file (%lld lines): %s",
			       lines, msg);
}

int popc_fuzz_scene(const uint8_t *data, size_t size)
{
	char path[64];
	int fd = popc_fuzz_file(data, size, path, sizeof path);
	if (fd < 0)
		return 0;
	popc_scene s;
	popc_scene_defaults(&s);
	popc_error err;
	err.msg[0] = '\0';
	if (popc_scene_load(&s, path, &err) != 0) {
		check_error(data, size, err.msg, path, popc_fuzz_count_lines(data, size));
		popc_fuzz_file_close(fd);
		return 0;
	}
	popc_fuzz_file_close(fd);
	if (popc_scene_validate(&s, &err) != 0)
		return 0;
	/* the resolved scene, written and read again, is the same scene */
	char *text = NULL, *again = NULL;
	size_t len = 0, len2 = 0;
	if (popc_scene_to_text(&s, &text, &len, &err) != 0)
		return 0;
	fd = popc_fuzz_file((const uint8_t *)text, len, path, sizeof path);
	popc_scene s2;
	popc_scene_defaults(&s2);
	if (fd >= 0) {
		if (popc_scene_load(&s2, path, &err) != 0)
			popc_fuzz_fail(data, size, "the written scene does not load: %s\n%s", err.msg,
				       text);
		if (popc_scene_validate(&s2, &err) != 0)
			popc_fuzz_fail(data, size, "the written scene does not validate: %s", err.msg);
		if (popc_scene_to_text(&s2, &again, &len2, &err) == 0 &&
		    (len != len2 || memcmp(text, again, len) != 0))
			popc_fuzz_fail(data, size, "the written scene reads back differently:\n%s\n---\n%s",
				       text, again);
		popc_fuzz_file_close(fd);
	}
	free(text);
	free(again);
	return 0;
}

#ifdef POPC_FUZZ_MODBUS
/* Both directions of both conversions (issue 10): one count and every value
 * the position register holds is a finite position, the soft limits lie
 * strictly inside the register's range, +-limit_N goes on the wire as a
 * register value that reads back finite and within limit_N (plus half a unit
 * or float32's rounding), and every command register value reads as a finite
 * force. */
static int map_conversions_usable(const popc_register_map *m)
{
	static const double range[][2] = {{-32768.0, 32767.0}, {0.0, 65535.0},
					  {-2147483648.0, 2147483647.0}, {0.0, 4294967295.0},
					  {-3.4028234663852886e38, 3.4028234663852886e38},
					  {-1.7976931348623157e308, 1.7976931348623157e308}};
	const double *pr = range[m->pos.type], *cr = range[m->cmd.type];
	double cpm = m->pos.counts_per_m, npu = m->cmd.newton_per_unit;
	if (!(isfinite(1.0 / cpm) && 1.0 / cpm > 0) || !isfinite(pr[0] / cpm) ||
	    !isfinite(pr[1] / cpm) || !(m->pos.soft_min_m * cpm > pr[0]) ||
	    !(m->pos.soft_max_m * cpm < pr[1]))
		return 0;
	/* a position or velocity command (an admittance-type device's servo,
	 * docs/MODBUS.md "Command modes"): its scale and clamp are finite and
	 * positive; the force conversions below are a force command's */
	if (m->cmd.mode == POPC_CMD_POSITION)
		return isfinite(m->cmd.counts_per_m) && m->cmd.counts_per_m > 0;
	if (m->cmd.mode == POPC_CMD_VELOCITY)
		return isfinite(m->cmd.m_per_s_per_unit) && m->cmd.m_per_s_per_unit > 0 &&
		       isfinite(m->cmd.limit_m_per_s) && m->cmd.limit_m_per_s > 0;
	if (!isfinite(cr[0] * npu) || !isfinite(cr[1] * npu))
		return 0;
	int integer = m->cmd.type <= POPC_REG_UINT32;
	double slack = integer ? 0.5 * npu : m->cmd.limit_N * 1.2e-7;
	for (int sign = -1; sign <= 1; sign += 2) {
		uint16_t w[4];
		popc_reg_encode(sign * m->cmd.limit_N / npu, m->cmd.type, m->cmd.order, w);
		double back = popc_reg_decode(w, m->cmd.type, m->cmd.order) * npu;
		if (!(isfinite(back) && fabs(back) <= m->cmd.limit_N + slack))
			return 0;
	}
	return 1;
}

int popc_fuzz_register_map(const uint8_t *data, size_t size)
{
	char path[64];
	int fd = popc_fuzz_file(data, size, path, sizeof path);
	if (fd < 0)
		return 0;
	popc_register_map *m = malloc(sizeof *m);
	if (!m) {
		popc_fuzz_file_close(fd);
		return 0;
	}
	popc_error err;
	err.msg[0] = '\0';
	if (popc_register_map_load(m, path, &err) != 0) {
		check_error(data, size, err.msg, path, popc_fuzz_count_lines(data, size));
	} else {
		if (!map_conversions_usable(m))
			popc_fuzz_fail(data, size,
				       "map accepted whose conversions are not finite or not in range: "
				       "counts_per_m %g (%s), soft [%g, %g] m, newton_per_unit %g (%s), "
				       "limit %g N",
				       m->pos.counts_per_m, popc_reg_type_name(m->pos.type),
				       m->pos.soft_min_m, m->pos.soft_max_m, m->cmd.newton_per_unit,
				       popc_reg_type_name(m->cmd.type), m->cmd.limit_N);
		int first;
		int n = popc_register_map_command_block(m, &first);
		if (!(isfinite(m->pos.counts_per_m) && m->pos.counts_per_m > 0) ||
		    (m->cmd.mode == POPC_CMD_FORCE &&
		     (!(isfinite(m->cmd.newton_per_unit) && m->cmd.newton_per_unit > 0) ||
		      !(isfinite(m->cmd.limit_N) && m->cmd.limit_N >= 0))) ||
		    !(isfinite(m->pos.soft_min_m) && isfinite(m->pos.soft_max_m) &&
		      m->pos.soft_min_m < m->pos.soft_max_m) ||
		    m->slave < 1 || m->slave > 247 || m->enable.n_on < 1 ||
		    m->enable.n_on > POPC_MAP_ENABLE_MAX || n < 1 || n > POPC_MAP_CMD_BLOCK_MAX ||
		    first < 0 || first + n - 1 > 65535)
			popc_fuzz_fail(data, size,
				       "map accepted with counts_per_m %g, newton_per_unit %g, limit %g N, "
				       "soft [%g, %g], slave %d, %d enable words, command block %d at %d",
				       m->pos.counts_per_m, m->cmd.newton_per_unit, m->cmd.limit_N,
				       m->pos.soft_min_m, m->pos.soft_max_m, m->slave, m->enable.n_on, n,
				       first);
	}
	free(m);
	popc_fuzz_file_close(fd);
	return 0;
}
#endif

/* libinih's buffer in Debian's build (INI_MAX_LINE); byte 0 of the input
 * picks a smaller one too, so that short inputs reach the limit */
int popc_fuzz_ini_lines(const uint8_t *data, size_t size)
{
	if (size < 1)
		return 0;
	const int num = data[0] & 1 ? 200 : 2 + (data[0] >> 1) % 16;
	data++;
	size--;
	char path[64];
	int fd = popc_fuzz_file(data, size, path, sizeof path);
	if (fd < 0)
		return 0;
	FILE *f = fopen(path, "r");
	if (!f) {
		popc_fuzz_file_close(fd);
		return 0;
	}
	char *str = malloc((size_t)num);
	int line = 0, too_long = 0;
	size_t pos = 0; /* start of the next line in data */
	long long expect_line = 0;
	while (str) {
		char *got = popc_ini_read_line(str, num, f, &line, &too_long);
		if (pos < size)
			expect_line++;
		/* the file's next line: content without "\n" and one "\r" before it */
		const uint8_t *nl = pos < size ? memchr(data + pos, '\n', size - pos) : NULL;
		size_t raw = nl ? (size_t)(nl - (data + pos)) + 1 : size - pos;
		size_t content = raw - (nl ? 1 : 0);
		if (content > 0 && data[pos + content - 1] == '\r')
			content--;
		const int has_nul = pos < size && memchr(data + pos, '\0', raw) != NULL;
		if (!got) {
			if (too_long == 2) {
				if (!has_nul || line != expect_line)
					popc_fuzz_fail(data - 1, size + 1,
						       "line %d (real %lld) refused for a NUL byte", line,
						       expect_line);
			} else if (too_long) {
				if (pos >= size || content <= (size_t)num - 1 || line != expect_line)
					popc_fuzz_fail(data - 1, size + 1,
						       "line %d (real %lld, %zu characters, limit %d) "
						       "refused as too long",
						       line, expect_line, content, num - 1);
			} else if (pos < size) {
				popc_fuzz_fail(data - 1, size + 1, "end of file at line %d, %zu bytes left",
					       line, size - pos);
			}
			break;
		}
		if (pos >= size)
			popc_fuzz_fail(data - 1, size + 1, "a line past the end of the file");
		if (line != expect_line)
			popc_fuzz_fail(data - 1, size + 1, "line %lld counted as %d", expect_line, line);
		if (has_nul)
			popc_fuzz_fail(data - 1, size + 1, "line %d with a NUL byte accepted", line);
		if (content > (size_t)num - 1)
			popc_fuzz_fail(data - 1, size + 1, "line %d of %zu characters accepted (limit %d)",
				       line, content, num - 1);
		/* the text, blanks stripped; the reader may keep the end of line */
		size_t lead = 0;
		while (lead < content && (data[pos + lead] == ' ' || data[pos + lead] == '\t'))
			lead++;
		size_t n = strlen(got);
		if (n > 0 && got[n - 1] == '\n')
			n--;
		if (n > 0 && got[n - 1] == '\r' && n > content - lead)
			n--;
		if (n != content - lead || memcmp(got, data + pos + lead, n) != 0)
			popc_fuzz_fail(data - 1, size + 1, "line %d read as '%.*s'", line, (int)n, got);
		pos += raw;
	}
	free(str);
	fclose(f);
	popc_fuzz_file_close(fd);
	return 0;
}
