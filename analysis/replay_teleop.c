/* popc-analyze replay on a teleoperation log (docs/TELEOPERATION.md,
 * "Replaying a log"): the two ports' PCs again, on or off and with the
 * bounds of the scene (header, then --set), over the recorded channel.
 *
 * What each side received is taken from the log: the master velocity the
 * slave held (vs_rx), the slave force the master held (f_e = -fs_rx), and
 * which packet each held (fwd_age, bwd_age). The received energies are not
 * the log's: they are the replayed other side's E_in, through the packet
 * the log says was held, E_rx(k) = max over received of E_in,remote(k -
 * age(k) - 1) (a packet sent at tick j carries E_in through tick j - 1;
 * none held yet: 0 J), so the replayed ports are coupled through the
 * recorded channel as online. Replaying the log's own setting gives every
 * row bit for bit (tests/cli/test_teleop_analyze.sh).
 *
 * Open loop: the devices do not react. x, v, xs, fs, vs_rx and the ages are
 * the recording's whatever the replayed PCs do, so a replay with the PCs
 * off of a run with them on shows the PCs' outputs and energies, not the
 * oscillation the run without them would have had.
 *
 * The output is the input file with the ports' cells (f_pc, f_c, W, Em_in,
 * Em_out, Em_rx, vs_pc, vs_c, Ws, Es_in, Es_out, Es_rx, and the PC bits 1,
 * 2, 4, 8 of flags) rewritten in the log's own number format, the header's
 * source = replay and [teleop] tdpa and bounds set to the replay's. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "analyze.h"
#include "popc/core/tdpa_drift.h"
#include "popc/core/teleop.h"
#include "popc/util/numfmt.h"

#define RING 131072 /* above the longest packet age (channel delay <= 100,000 ticks) */
#define RING_MASK (RING - 1)

/* The E_in a packet held for age ticks at tick k carries: E_in through
 * k - age - 1 (ring[j] is E_in after tick j), 0 before any. */
static double sent_energy(const double *ring, long long k, double age)
{
	if (age < 0.0 || age > (double)k || age >= RING)
		return 0.0;
	const long long j = k - (long long)age - 1;
	return j < 0 ? 0.0 : ring[j & RING_MASK];
}

static int put_line(FILE *o, const char *line)
{
	return fputs(line, o) < 0 ? -1 : 0;
}

/* One replay of path with the PCs pc_on into out. */
static int replay_one(const char *path, const popc_scene *sc, int pc_on, const char *out,
		      popc_error *err)
{
	/* the drift laws' v_dc would be replayed from xm_rx and xs_cmd, which
	 * an open-loop replay keeps as recorded: not built */
	if (sc->tele_drift != POPC_DRIFT_OFF)
		return popc_error_set(err, POPC_ERR_INVALID,
				      "%s: teleop.drift = %s: replay runs the PCs without drift "
				      "compensation only (docs/TELEOPERATION.md, \"Next\")",
				      path, popc_drift_law_names[sc->tele_drift]);
	ana_tele_log l;
	int st = ana_tele_open(&l, path, sc, err);
	if (st)
		return st;
	FILE *in = fopen(path, "r");
	FILE *o = fopen(out, "w");
	double *em_in = malloc(RING * sizeof *em_in), *es_in = malloc(RING * sizeof *es_in);
	char *line = NULL;
	size_t cap = 0;
	if (!in || !o || !em_in || !es_in) {
		st = popc_error_set(err, POPC_ERR_IO, "%s: cannot open (or out of memory)",
				    !in ? path : out);
		goto done;
	}
	const double T = l.period_s;
	popc_tdpa_side m, s;
	popc_tdpa_side_init_excess(&m, sc->tele_master_bound_N, sc->tele_excess_J);
	popc_tdpa_side_init_excess(&s, sc->tele_slave_bound_mps, sc->tele_excess_J);
	long long lineno = 0, k = 0;
	int in_teleop = 0, in_header = 1, in_section = 0;
	ana_tele_row row;
	while ((st = ana_tele_next(&l, &row, err)) == 1) {
		/* the lines before this row: header, column names, comments */
		ssize_t n;
		while (lineno + 1 < row.line && (n = getline(&line, &cap, in)) >= 0) {
			lineno++;
			char buf[160];
			const char *text = line;
			if (in_header && line[0] == '#') {
				if (strncmp(line, "# [", 3) == 0) {
					in_section = 1;
					in_teleop = strncmp(line, "# [teleop]", 10) == 0;
				}
				char num[POPC_DOUBLE_TEXT_MAX + 1];
				if (strncmp(line, "# source = ", 11) == 0) {
					text = "# source = replay\n";
				} else if (!in_section && strncmp(line, "# variant = ", 12) == 0) {
					/* the top line names what ran (teleop.h) */
					snprintf(buf, sizeof buf, "# variant = %s\n",
						 popc_teleop_variant_name(pc_on, sc->tele_drift));
					text = buf;
				} else if (in_teleop && strncmp(line, "# tdpa = ", 9) == 0) {
					snprintf(buf, sizeof buf, "# tdpa = %s\n", pc_on ? "on" : "off");
					text = buf;
				} else if (in_teleop && strncmp(line, "# master_pc_bound = ", 20) == 0) {
					popc_format_double(sc->tele_master_bound_N, num);
					snprintf(buf, sizeof buf, "# master_pc_bound = %s\n", num);
					text = buf;
				} else if (in_teleop && strncmp(line, "# slave_pc_bound = ", 19) == 0) {
					popc_format_double(sc->tele_slave_bound_mps, num);
					snprintf(buf, sizeof buf, "# slave_pc_bound = %s\n", num);
					text = buf;
				}
			} else {
				in_header = 0;
			}
			if (put_line(o, text) != 0)
				goto write_failed;
		}
		if ((n = getline(&line, &cap, in)) < 0) {
			st = popc_error_set(err, POPC_ERR_IO, "%s:%lld: changed while read", path,
					    row.line);
			goto done;
		}
		lineno++;
		in_header = 0;
		double *c = row.c;
		const double rx_m = sent_energy(es_in, k, c[ANA_TC_bwd_age]);
		const double rx_s = sent_energy(em_in, k, c[ANA_TC_fwd_age]);
		popc_tdpa_step pm = popc_teleop_port(&m, rx_m, c[ANA_TC_f_e], -c[ANA_TC_v], T, pc_on);
		popc_tdpa_step ps = popc_teleop_port(&s, rx_s, c[ANA_TC_vs_rx], -c[ANA_TC_fs], T, pc_on);
		em_in[k & RING_MASK] = popc_energy_flow_in(&m.flow);
		es_in[k & RING_MASK] = popc_energy_flow_in(&s.flow);
		unsigned flags = (unsigned)c[ANA_TC_flags] & ~15u;
		flags |= (pm.flags & POPC_TDPA_ACTIVE ? POPC_TELEOP_FLAG_M_ACTIVE : 0u) |
			 (pm.flags & POPC_TDPA_CLAMPED ? POPC_TELEOP_FLAG_M_CLAMPED : 0u) |
			 (ps.flags & POPC_TDPA_ACTIVE ? POPC_TELEOP_FLAG_S_ACTIVE : 0u) |
			 (ps.flags & POPC_TDPA_CLAMPED ? POPC_TELEOP_FLAG_S_CLAMPED : 0u);
		const int idx[] = {ANA_TC_f_pc, ANA_TC_f_c, ANA_TC_W, ANA_TC_Em_in, ANA_TC_Em_out,
				   ANA_TC_Em_rx, ANA_TC_vs_pc, ANA_TC_vs_c, ANA_TC_Ws, ANA_TC_Es_in,
				   ANA_TC_Es_out, ANA_TC_Es_rx};
		const double val[] = {pm.d, pm.u, pm.W_J, popc_energy_flow_in(&m.flow),
				      popc_energy_flow_out(&m.flow), m.remote_in_J, ps.d, ps.u, ps.W_J,
				      popc_energy_flow_in(&s.flow), popc_energy_flow_out(&s.flow),
				      s.remote_in_J};
		/* the file's columns, each cell the log's or the replay's */
		char *save = NULL, *cellp = strtok_r(line, ",\n", &save);
		for (int col = 0; cellp; col++, cellp = strtok_r(NULL, ",\n", &save)) {
			char num[POPC_DOUBLE_TEXT_MAX + 8];
			const char *text = cellp;
			for (size_t i = 0; i < sizeof idx / sizeof idx[0]; i++)
				if (l.col[idx[i]] == col) {
					popc_format_double_point(val[i] + 0.0, num);
					text = num;
				}
			if (l.col[ANA_TC_flags] == col) {
				snprintf(num, sizeof num, "%u", flags);
				text = num;
			}
			if (fprintf(o, "%s%s", col ? "," : "", text) < 0)
				goto write_failed;
		}
		if (fputc('\n', o) == EOF)
			goto write_failed;
		k++;
	}
	if (st < 0)
		goto done;
	/* what follows the rows: the stop line */
	while (getline(&line, &cap, in) >= 0)
		if (put_line(o, line) != 0)
			goto write_failed;
	st = 0;
	goto done;
write_failed:
	st = popc_error_set(err, POPC_ERR_IO, "%s: write failed", out);
done:
	free(line);
	free(em_in);
	free(es_in);
	if (in)
		fclose(in);
	if (o && fclose(o) != 0 && st == 0)
		st = popc_error_set(err, POPC_ERR_IO, "%s: write failed", out);
	ana_tele_close(&l);
	return st;
}

int ana_replay_teleop(const char *path, const popc_scene *sc, unsigned mask,
		      char (*out_paths)[1100], int quiet)
{
	static const char *const names[2] = {"tdpa-off", "tdpa-on"};
	for (int on = 0; on < 2; on++) {
		if (!(mask & (1u << on)))
			continue;
		popc_error err;
		int st = replay_one(path, sc, on, out_paths[on], &err);
		if (st)
			return ana_fail("replay", st, &err);
		if (!quiet)
			printf("%s (%s)\n", out_paths[on], names[on]);
	}
	return 0;
}
