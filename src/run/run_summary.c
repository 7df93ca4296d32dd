/* The run summary (run.h): its fields' table, RUN_SUMMARY_FIELDS, and its
 * human text, CSV row and JSON kinds, made from that one table. The loop
 * that fills it: run.c. */
#include "popc/run/run.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "popc/core/controller.h"
#include "popc/util/numfmt.h"
#include "popc/util/text_builder.h"

/* The run summary's fields, in the order of its CSV header and row; the
 * human summary prints the same values. Adding a metric is one line here.
 *
 * FIELD(ID, name, unit, format, value, meaning): value is an expression of
 * sum (the popc_run_summary), s (the scene) and m (sum's metrics); format is
 * TEXT (a name), INT (a decimal integer), REAL (shortest round-trip form,
 * with a decimal point always: "0.0", "5.0") or
 * PORT (REAL for an axis with a true position, sum->has_port_energy; an
 * empty cell otherwise, as the log has no E_port column: never a NaN) or
 * DEVICE (REAL where the axis gave the plant's dissipation at every tick,
 * sum->has_device_energy; an empty cell otherwise). */
#define RUN_SUMMARY_FIELDS(FIELD)                                                                   \
	FIELD(VARIANT, variant, "", TEXT, popc_run_variant_name(s), "controller variant")          \
	FIELD(INTEGRATOR, integrator, "", TEXT, popc_integrator_name(sum->integrator),              \
	      "plant integrator")                                                                   \
	FIELD(SUBSTEPS, substeps, "", INT, sum->substeps, "integrator substeps per tick")           \
	FIELD(STATUS, status, "", INT, sum->status, "0, or the popc_status that stopped the run")  \
	FIELD(TICKS, ticks, "", INT, sum->ticks, "ticks run, t = 0 included")                       \
	FIELD(SIM_TIME, sim_time_s, "s", REAL, sum->sim_time_s, "time of the last tick")            \
	FIELD(WALL_TIME, wall_time_s, "s", REAL, sum->wall_time_s, "wall-clock time of the loop")   \
	FIELD(REALTIME_FACTOR, realtime_factor, "", REAL,                                           \
	      sum->wall_time_s > 0 ? sum->sim_time_s / sum->wall_time_s : 0.0,                      \
	      "simulated over wall time (0 without wall time)")                                     \
	FIELD(NS_PER_TICK, ns_per_tick, "ns", REAL,                                                 \
	      sum->ticks ? 1e9 * sum->wall_time_s / (double)sum->ticks : 0.0,                       \
	      "wall time per tick")                                                                 \
	FIELD(INTEGRATOR_ERROR, integrator_error_m, "m", REAL, sum->integrator_error_m,             \
	      "max |x - x_exact| at the samples (0: exact)")                                        \
	FIELD(PC_ACTIVE, pc_active, "", REAL, popc_metrics_active_fraction(&m->all),                \
	      "share of ticks with f_pc != 0")                                                      \
	FIELD(PC_RMS, pc_rms, "N", REAL, popc_metrics_pc_rms(&m->all), "RMS of f_pc")               \
	FIELD(PC_MAX, pc_max, "N", REAL, m->all.pc_max_N, "max |f_pc|")                             \
	FIELD(PC_RMS_LATE, pc_rms_late, "N", REAL, popc_metrics_pc_rms(&m->late),                   \
	      "RMS of f_pc over the second half of the run")                                        \
	FIELD(PC_ENERGY, pc_energy, "J", REAL, m->pc_energy_J, "energy the PC dissipated")          \
	FIELD(W_MINUS_EREF_MIN, w_minus_eref_min, "J", REAL,                                        \
	      isfinite(m->w_minus_eref_min_J) ? m->w_minus_eref_min_J : 0.0,                        \
	      "minimum of W - E_ref (0 before the first tick)")                                     \
	FIELD(W_MINUS_EREF_END, w_minus_eref_end, "J", REAL, m->w_minus_eref_end_J,                 \
	      "W - E_ref at the last tick")                                                         \
	FIELD(VSIGN_RATE, vsign_rate, "1/s", REAL, popc_metrics_vsign_rate(&m->all, m->period_s),   \
	      "velocity sign changes in contact per second")                                        \
	FIELD(VSIGN_RATE_LATE, vsign_rate_late, "1/s", REAL,                                        \
	      popc_metrics_vsign_rate(&m->late, m->period_s),                                       \
	      "velocity sign changes in contact per second, second half")                           \
	FIELD(PORT_ENERGY_END, port_energy_end, "J", PORT, sum->port_energy_J,                      \
	      "true energy into the VE port at the last tick (E_port)")                             \
	FIELD(PORT_ENERGY_MIN, port_energy_min, "J", PORT, sum->port_energy_min_J,                  \
	      "minimum of E_port over the run (< 0: the port gave out energy)")                     \
	FIELD(PO_ERROR_END, po_error_end, "J", PORT, sum->po_error_end_J,                           \
	      "observer error W - E_port at the last tick")                                         \
	FIELD(PO_ERROR_MAX, po_error_max, "J", PORT, sum->po_error_max_J,                           \
	      "max |W - E_port| over the run")                                                      \
	FIELD(DEVICE_ENERGY_END, device_energy_end, "J", DEVICE, sum->device_energy_J,              \
	      "E_port + the energy the plant's damping dissipated, at the last tick (E_dev)")       \
	FIELD(DEVICE_ENERGY_MIN, device_energy_min, "J", DEVICE, sum->device_energy_min_J,          \
	      "minimum of E_dev over the run (< 0: the device port gave out energy)")               \
	FIELD(RENDERED_STIFFNESS, rendered_stiffness, "N/m", REAL,                                  \
	      popc_metrics_rendered_stiffness(m),                                                   \
	      "least squares f_c / penetration over the ticks in contact")

enum summary_field_id {
#define FIELD_ID(ID, name, unit, format, value, meaning) SUMMARY_##ID,
	RUN_SUMMARY_FIELDS(FIELD_ID)
#undef FIELD_ID
	SUMMARY_N_FIELDS
};

typedef enum summary_format {
	SUMMARY_TEXT,
	SUMMARY_INT,
	SUMMARY_REAL,
	SUMMARY_PORT,
	SUMMARY_DEVICE
} summary_format;

static const struct summary_field {
	const char *name, *unit, *meaning;
	summary_format format;
} summary_fields[SUMMARY_N_FIELDS] = {
#define FIELD_ENTRY(ID, name, unit, format, value, meaning)                                         \
	[SUMMARY_##ID] = {#name, unit, meaning, SUMMARY_##format},
	RUN_SUMMARY_FIELDS(FIELD_ENTRY)
#undef FIELD_ENTRY
};

/* One field's value: the member its format names. */
typedef struct summary_value {
	const char *text;
	long long integer;
	double real;
} summary_value;

/* Field i's value alone: a sweep row takes some fields, not all. */
static summary_value summary_value_of(const popc_run_summary *sum, const popc_scene *s, int i)
{
	const popc_metrics *m = &sum->metrics;
#define VALUE_TEXT(e) .text = (e)
#define VALUE_INT(e) .integer = (e)
#define VALUE_REAL(e) .real = (e)
#define VALUE_PORT(e) .real = (e)
#define VALUE_DEVICE(e) .real = (e)
#define FIELD_VALUE(ID, name, unit, format, value, meaning)                                         \
	case SUMMARY_##ID: return (summary_value){VALUE_##format(value)};
	switch ((enum summary_field_id)i) {
	RUN_SUMMARY_FIELDS(FIELD_VALUE)
	case SUMMARY_N_FIELDS: break;
	}
#undef FIELD_VALUE
	return (summary_value){.text = ""};
}

static void summary_values(const popc_run_summary *sum, const popc_scene *s,
			   summary_value v[SUMMARY_N_FIELDS])
{
	for (int i = 0; i < SUMMARY_N_FIELDS; i++)
		v[i] = summary_value_of(sum, s, i);
}

const char *popc_run_variant_name(const popc_scene *s)
{
	/* a teleoperation scene runs the network's PCs, not controller.variant */
	if (s->tele_arch != POPC_TELEOP_OFF)
		return popc_teleop_variant_name(s->tele_tdpa, s->tele_drift);
	return s->causality == POPC_CAUSALITY_ADMITTANCE ? popc_admittance_variant_name(s->adm_variant)
							 : popc_variant_name(s->variant);
}

void popc_run_summary_print(const popc_run_summary *sum, const popc_scene *s, FILE *f)
{
	summary_value v[SUMMARY_N_FIELDS];
	summary_values(sum, s, v);
	/* no wall time reads as infinitely fast here, as 0 in the CSV row */
	double rtf = sum->wall_time_s > 0 ? v[SUMMARY_REALTIME_FACTOR].real : (double)INFINITY;
	fprintf(f, "popc run: %s, variant %s, %lld ticks at %g Hz\n", sum->stop_reason,
		v[SUMMARY_VARIANT].text, v[SUMMARY_TICKS].integer, s->rate_Hz);
	fprintf(f, "  simulated %.6g s in %.6g s wall: %.4g x real time, %.4g ns per tick\n",
		v[SUMMARY_SIM_TIME].real, v[SUMMARY_WALL_TIME].real, rtf, v[SUMMARY_NS_PER_TICK].real);
	if (sum->integrator == POPC_INTEGRATOR_EXACT)
		fprintf(f, "  integrator: exact (ZOH/FOH discretization)\n");
	else
		fprintf(f, "  integrator: %s, %lld substeps; max position error against exact: %.3g m\n",
			v[SUMMARY_INTEGRATOR].text, v[SUMMARY_SUBSTEPS].integer,
			v[SUMMARY_INTEGRATOR_ERROR].real);
	if (s->variant == POPC_VARIANT_ENERGY_BOUNDING) {
		/* its f_pc = f_c - f_e is the force the bound withheld, not one
		 * it applied: say what it rendered (issue 23) */
		double k_b = (1.0 - s->eb_margin) * 2.0 * (s->op_damping_Nspm + s->dev_damping_Nspm) *
			     s->rate_Hz;
		fprintf(f, "  energy bound: rendered stiffness %.4g N/m in contact (K_b = (1 - %g) 2 b / T "
			   "= %.4g N/m, the wall %.4g N/m); the bound held |f_c| below |f_e| on %.4g %% of "
			   "ticks (f_e - f_c RMS %.4g N, withheld, not applied)\n",
			v[SUMMARY_RENDERED_STIFFNESS].real, s->eb_margin, k_b, s->env_stiffness_Npm,
			100.0 * v[SUMMARY_PC_ACTIVE].real, v[SUMMARY_PC_RMS].real);
	} else
		fprintf(f, "  PC active %.4g %% of ticks; f_pc RMS %.4g N, max %.4g N; late half RMS %.4g N\n",
			100.0 * v[SUMMARY_PC_ACTIVE].real, v[SUMMARY_PC_RMS].real, v[SUMMARY_PC_MAX].real,
			v[SUMMARY_PC_RMS_LATE].real);
	fprintf(f, "  W - E_ref: final %.4g J, minimum %.4g J; velocity sign changes in contact %.4g /s\n",
		v[SUMMARY_W_MINUS_EREF_END].real, v[SUMMARY_W_MINUS_EREF_MIN].real,
		v[SUMMARY_VSIGN_RATE].real);
	if (sum->has_admittance)
		fprintf(f, "  parallel PC active %.4g %% of ticks; v_pc RMS %.4g m/s, max %.4g m/s; late half "
			"RMS %.4g m/s\n",
			100.0 * sum->adm_active, sum->adm_v_pc_rms_mps, sum->adm_v_pc_max_mps,
			sum->adm_v_pc_rms_late_mps);
	if (sum->has_teleop)
		fprintf(f, "  teleoperation (the lines above are the master's): two-port condition broken "
			"on %lld ticks, smallest margin master %.3g J, slave %.3g J; PCs active %lld, %lld "
			"ticks, clamped %lld, %lld; largest |f_c| %.4g N, %s %.4g %s\n",
			sum->tele_violations, sum->tele_margin_min_J[0], sum->tele_margin_min_J[1],
			sum->tele_active[0], sum->tele_active[1], sum->tele_clamped[0],
			sum->tele_clamped[1], sum->tele_f_c_max_N,
			sum->tele_pp ? "|F_S|" : "|v_c|", sum->tele_v_c_max_mps,
			sum->tele_pp ? "N" : "m/s");
	if (sum->has_port_energy)
		fprintf(f, "  true port energy E_port: final %.4g J; observer error W - E_port: final %.4g J, "
			"largest |.| %.4g J\n",
			v[SUMMARY_PORT_ENERGY_END].real, v[SUMMARY_PO_ERROR_END].real,
			v[SUMMARY_PO_ERROR_MAX].real);
	if (sum->has_device_energy)
		fprintf(f, "  device port E_dev = E_port + damping's dissipation: final %.4g J, "
			"minimum %.4g J\n",
			v[SUMMARY_DEVICE_ENERGY_END].real, v[SUMMARY_DEVICE_ENERGY_MIN].real);
}

/* Whether field i has a value for this run (PORT and DEVICE fields may not). */
static int summary_field_known(const popc_run_summary *sum, int i)
{
	if (summary_fields[i].format == SUMMARY_PORT)
		return sum->has_port_energy;
	if (summary_fields[i].format == SUMMARY_DEVICE)
		return sum->has_device_energy;
	return 1;
}

void popc_run_summary_csv_header(FILE *f)
{
	for (int i = 0; i < SUMMARY_N_FIELDS; i++) {
		if (i > 0)
			fputc(',', f);
		fputs(summary_fields[i].name, f);
	}
	fputc('\n', f);
}

/* Field i's cell of the CSV row, value v, appended to t. */
static void put_cell(popc_text_builder *t, const popc_run_summary *sum, int i, const summary_value *v)
{
	switch (summary_fields[i].format) {
	case SUMMARY_TEXT: popc_text_put(t, v->text, strlen(v->text)); break;
	case SUMMARY_INT: popc_text_put_integer(t, v->integer); break;
	case SUMMARY_PORT:   /* no true position: an empty cell */
	case SUMMARY_DEVICE: /* no dissipation: an empty cell */
	case SUMMARY_REAL: {
		if (!summary_field_known(sum, i))
			break;
		/* with a point ("0.0"): readers type the column floating point */
		popc_text_put_double_point(t, v->real);
		break;
	}
	}
}

/* Into a char buffer, not a FILE: stdio per cell (fputs, fprintf,
 * fmemopen's overflow) was a tenth of a sweep's own CPU when a sweep made
 * its rows from this one (docs/BENCHMARKS.md section 6). */
size_t popc_run_summary_csv_row_text(const popc_run_summary *sum, const popc_scene *s, char *buf,
				     size_t cap)
{
	summary_value v[SUMMARY_N_FIELDS];
	summary_values(sum, s, v);
	popc_text_builder t = {.buf = buf, .cap = cap, .len = 0};
	for (int i = 0; i < SUMMARY_N_FIELDS; i++) {
		if (i > 0)
			popc_text_put(&t, ",", 1);
		put_cell(&t, sum, i, &v[i]);
	}
	popc_text_put(&t, "\n", 1);
	if (cap > 0)
		buf[t.len < cap ? t.len : cap - 1] = '\0';
	return t.len;
}

int popc_run_summary_field(const char *name)
{
	for (int i = 0; i < SUMMARY_N_FIELDS; i++)
		if (strcmp(summary_fields[i].name, name) == 0)
			return i;
	return -1;
}

void popc_run_summary_put_cell(popc_text_builder *t, const popc_run_summary *sum,
			       const popc_scene *s, int field)
{
	if (field < 0 || field >= SUMMARY_N_FIELDS)
		return;
	summary_value v = summary_value_of(sum, s, field);
	put_cell(t, sum, field, &v);
}

void popc_run_summary_csv_row(const popc_run_summary *sum, const popc_scene *s, FILE *f)
{
	char text[2048];
	size_t n = popc_run_summary_csv_row_text(sum, s, text, sizeof text);
	if (n < sizeof text) {
		fwrite(text, 1, n, f);
		return;
	}
	/* longer than any row popc makes today (26 cells of at most 32 bytes) */
	char *big = malloc(n + 1);
	if (big && popc_run_summary_csv_row_text(sum, s, big, n + 1) == n)
		fwrite(big, 1, n, f);
	free(big);
}

popc_json_kind popc_run_summary_json_kind(const char *name)
{
	int i = popc_run_summary_field(name);
	if (i < 0)
		return POPC_JSON_AUTO;
	return summary_fields[i].format == SUMMARY_TEXT ? POPC_JSON_TEXT : POPC_JSON_NUMBER;
}
