// Reference reader for docs/BENCHMARKS.md section 3: reads a popc log the way
// a fast hand-written C++ reader would (block fread, memchr for line ends,
// fast_float::from_chars for every cell), and runs the same kind of recompute
// as popc-analyze energy: the passivity observer W (seed eq. 3, held force:
// W += f_c(k-1) dx) and the reference energy E_ref (trapezoid of f_e over dx).
// It parses every cell of every row (t..E_port), so the bytes it handles are
// the bytes popc-analyze handles. Comment lines ('#') and the header are
// skipped; no other checks (this is the speed reference, not a validator).
//
// usage: fastfloat_reader LOG
// prints rows, cells, bytes, W_J, E_ref_J, the last logged W and E_ref.
#include <fast_float/fast_float.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct columns {
	int x = -1, f_e = -1, f_c = -1, W = -1, E_ref = -1, n = 0;
};

columns parse_header(const char *b, const char *e)
{
	columns c;
	int i = 0;
	while (b <= e) {
		const char *comma = static_cast<const char *>(std::memchr(b, ',', static_cast<size_t>(e - b)));
		const char *end = comma ? comma : e;
		std::string name(b, end);
		if (name == "x") c.x = i;
		else if (name == "f_e") c.f_e = i;
		else if (name == "f_c") c.f_c = i;
		else if (name == "W") c.W = i;
		else if (name == "E_ref") c.E_ref = i;
		i++;
		if (!comma) break;
		b = comma + 1;
	}
	c.n = i;
	return c;
}

} // namespace

int main(int argc, char **argv)
{
	if (argc != 2) {
		std::fprintf(stderr, "usage: fastfloat_reader LOG\n");
		return 2;
	}
	std::FILE *f = std::fopen(argv[1], "rb");
	if (!f) {
		std::perror(argv[1]);
		return 2;
	}
	const size_t block = 1 << 20;
	std::vector<char> buf(block + 4096);
	size_t have = 0;
	bool header_done = false;
	columns col;
	std::vector<double> v;
	double x_prev = 0, fc_prev = 0, fe_prev = 0, W = 0, E = 0, W_log = 0, E_log = 0;
	long long rows = 0, cells = 0, bytes = 0;
	for (;;) {
		if (have == buf.size()) buf.resize(buf.size() * 2); // a line longer than the buffer
		size_t got = std::fread(buf.data() + have, 1, buf.size() - have, f);
		bytes += static_cast<long long>(got);
		size_t end = have + got;
		bool eof = got == 0;
		if (eof && end > 0 && buf[end - 1] != '\n') buf[end++] = '\n'; // last line without newline
		const char *p = buf.data(), *stop = buf.data() + end;
		for (;;) {
			const char *nl = static_cast<const char *>(std::memchr(p, '\n', static_cast<size_t>(stop - p)));
			if (!nl) break;
			const char *le = nl;
			if (le > p && le[-1] == '\r') le--;
			if (p == le || *p == '#') {
			} else if (!header_done) {
				col = parse_header(p, le);
				if (col.x < 0 || col.f_e < 0 || col.f_c < 0) {
					std::fprintf(stderr, "%s: no x, f_e or f_c column\n", argv[1]);
					return 2;
				}
				v.resize(static_cast<size_t>(col.n));
				header_done = true;
			} else {
				const char *q = p;
				for (int i = 0; i < col.n; i++) {
					auto r = fast_float::from_chars(q, le, v[static_cast<size_t>(i)]);
					if (r.ec != std::errc() || (i + 1 < col.n ? *r.ptr != ',' : r.ptr != le)) {
						std::fprintf(stderr, "%s: row %lld cell %d: not a number\n", argv[1], rows + 1, i + 1);
						return 2;
					}
					q = r.ptr + 1;
				}
				cells += col.n;
				const double x = v[static_cast<size_t>(col.x)], fe = v[static_cast<size_t>(col.f_e)];
				if (rows > 0) {
					const double dx = x - x_prev;
					W += fc_prev * dx;
					E += 0.5 * (fe + fe_prev) * dx;
				}
				x_prev = x;
				fe_prev = fe;
				fc_prev = v[static_cast<size_t>(col.f_c)];
				if (col.W >= 0) W_log = v[static_cast<size_t>(col.W)];
				if (col.E_ref >= 0) E_log = v[static_cast<size_t>(col.E_ref)];
				rows++;
			}
			p = nl + 1;
		}
		have = static_cast<size_t>(stop - p);
		std::memmove(buf.data(), p, have);
		if (eof) break;
	}
	std::fclose(f);
	std::printf("rows %lld\ncells %lld\nbytes %lld\nW_J %.17g\nE_ref_J %.17g\nW_logged_J %.17g\nE_ref_logged_J %.17g\n",
		    rows, cells, bytes, W, E, W_log, E_log);
	return 0;
}
