/* The simulated slave of a teleoperation scene (docs/TELEOPERATION.md, "The
 * slave"): an admittance-type device, its position or velocity servo
 * tracking the velocity command v_c(k) held over the period and the position
 * command that follows it, x_c(k+1) = x_c(k) + v_c(k) T (admittance_plant.h,
 * the same lumped plant and exact step as the admittance device of
 * sim_admittance_axis.c), against the environment of the scene
 * (environment.h: the wall or spring, K_e (x - p) + B_e v).
 *
 * The environment's force is evaluated at the tick, from the true position
 * and velocity there, and held over the period as the plant's input: a
 * zero-order hold of the contact (a wall entered within a period pushes
 * from the next tick; at 1 kHz and K_e = 20 kN/m this adds up to one
 * period's K_e v T of force error per tick). It takes the hand's place in
 * admittance_plant.h (no hand: its mass, damping and stiffness are 0), so
 * the force sensor between device and environment reads exactly that held
 * force, f_s = -f_env (the force the environment puts on the slave).
 * Left out: contact dynamics within a period, the environment's own mass,
 * friction, the sensor's noise.
 *
 * With teleop.architecture = position-position the slave is commanded a
 * force instead (docs/TELEOPERATION.md, "Position-position"): the coupling
 * controller F_S (core/teleop.h) takes the servo's place, held over the
 * period beside the contact force, on the slave's mass and damping alone
 * (the plant built with no servo gains; slave.servo* are not used). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "popc/axes/sim_axis.h"
#include "popc/core/admittance.h"
#include "popc/core/admittance_plant.h"
#include "popc/core/encoder.h"
#include "popc/core/environment.h"
#include "popc/scene/from_scene.h"

/* the slave is called diverged beyond 10 x the scene's positions + 1 m
 * (sim_axis.c's rule) */
typedef struct slave_axis {
	popc_admittance_plant plant;
	popc_environment env;
	popc_force_sensor sensor;
	popc_plant_state st;  /* y = x - x0, v */
	double x0_m, x_cmd_m;
	double f_s_N;         /* the environment's force on the slave, held over the period */
	double period_s, delta_m, diverged_m; /* period_s: the sub-tick's, T / n_sub */
	int n_sub;            /* sub-ticks a tick (slave.rate / run.rate; 1: none) */
	long long k;          /* sub-ticks so far */
	int force_cmd;        /* position-position: the command is a force (N) */
} slave_axis;

static int slave_start(popc_axis *a, popc_error *err)
{
	(void)a;
	(void)err;
	return 0;
}

/* The sample of the current tick: the contact force evaluated here (and
 * held over the coming period), its count, the position's count. */
/* inlined into both clones of the axis' sample and exchange (POPC_FLOOR_CLONES,
 * encoder.h: the encoder's floor one instruction with SSE4.1) */
static inline __attribute__((always_inline)) int fill_sample(slave_axis *s, popc_axis_sample *out,
							  popc_error *err)
{
	const double x = s->x0_m + s->st.x_m;
	if (!isfinite(x) || !isfinite(s->st.v_mps))
		return popc_error_set(err, POPC_ERR_NUMERIC, "slave: the state is not finite at t = %g s",
				      (double)s->k * s->period_s);
	if (!(fabs(x) <= s->diverged_m))
		return popc_error_set(err, POPC_ERR_DIVERGED, "slave: x = %g m at t = %g s, beyond %g m",
				      x, (double)s->k * s->period_s, s->diverged_m);
	int ok = 1;
	out->count = popc_encoder_count(x, s->delta_m, &ok);
	s->f_s_N = -popc_environment_force(&s->env, x, s->st.v_mps);
	if (!ok || !isfinite(s->f_s_N))
		return popc_error_set(err, POPC_ERR_NUMERIC,
				      "slave: x = %g m or contact force %g N out of range at t = %g s", x,
				      -s->f_s_N, (double)s->k * s->period_s);
	out->force_count = popc_force_sensor_read(&s->sensor, s->f_s_N);
	out->x_true_m = x;
	out->x_cmd_m = s->x_cmd_m;
	out->dissipated_J = (double)NAN;
	out->dt_s = 0.0;
	out->rtt_s = 0.0;
	return 0;
}

POPC_FLOOR_CLONES
static int slave_sample(popc_axis *a, popc_axis_sample *out, popc_error *err)
{
	return fill_sample(a->priv, out, err);
}

POPC_FLOOR_CLONES
static int slave_exchange(popc_axis *a, double v_c_mps, popc_axis_sample *next_out,
			  popc_error *err)
{
	slave_axis *s = a->priv;
	/* slave.rate = n_sub x run.rate: the command held over the tick, the
	 * contact force evaluated and held, the position command advanced and
	 * the plant stepped each sub-tick of T / n_sub; the sample is the last
	 * sub-tick's, the next tick's (n_sub = 1: one step of T) */
	for (int j = 0; j < s->n_sub; j++) {
		if (j > 0) {
			int st = fill_sample(s, next_out, err);
			if (st)
				return st;
		}
		popc_plant_input u;
		if (s->force_cmd) {
			/* position-position: the command is the coupling's force, held
			 * with the contact's; no servo gains in the plant, so its input
			 * is the two forces */
			const popc_plant_input held = {.u0_N = s->f_s_N + v_c_mps};
			popc_admittance_plant_input(&s->plant, &held, s->x_cmd_m, 0.0, 0.0, &u);
		} else {
			const popc_plant_input held = {.u0_N = s->f_s_N};
			popc_admittance_plant_input(&s->plant, &held, s->x_cmd_m, v_c_mps, 0.0, &u);
		}
		popc_plant_step(&s->plant.plant, &s->st, &u);
		s->k++;
		if (!s->force_cmd)
			s->x_cmd_m += v_c_mps * s->period_s;
	}
	return fill_sample(s, next_out, err);
}

static int slave_stop(popc_axis *a, popc_error *err)
{
	(void)a;
	(void)err;
	return 0;
}

static void slave_destroy(popc_axis *a)
{
	free(a->priv);
	free(a);
}

static const popc_axis_ops slave_ops = {
	.name = "sim",
	.log_columns = 0,
	.start = slave_start,
	.sample = slave_sample,
	.exchange = slave_exchange,
	.stop = slave_stop,
	.destroy = slave_destroy,
};

int popc_sim_slave_axis_create(popc_axis **out, const popc_scene *sc, double x0_m, popc_error *err)
{
	*out = NULL;
	popc_axis *a = calloc(1, sizeof *a);
	slave_axis *s = calloc(1, sizeof *s);
	if (!a || !s) {
		free(a);
		free(s);
		return popc_error_set(err, POPC_ERR_NOMEM, "out of memory");
	}
	s->n_sub = popc_scene_slave_substeps(sc);
	if (s->n_sub < 1)
		s->n_sub = 1; /* popc_scene_validate refuses such a slave.rate */
	s->period_s = popc_scene_period_s(sc) / (double)s->n_sub;
	s->delta_m = sc->enc_resolution_m;
	s->x0_m = x0_m;
	s->x_cmd_m = x0_m;
	s->diverged_m = 10.0 * fmax(fabs(x0_m), fabs(sc->env_position_m)) + 1.0;
	popc_environment_from_scene(&s->env, sc);
	popc_admittance_plant_config pc;
	popc_teleop_slave_plant_config_from_scene(&pc, sc, x0_m);
	s->force_cmd = sc->tele_arch == POPC_TELEOP_POSITION_POSITION;
	if (s->force_cmd) {
		/* no servo: K_p = 0 (a velocity servo) and K_v = 0 */
		pc.servo = POPC_SERVO_VELOCITY;
		pc.servo_damping_Nspm = 0.0;
	}
	int st = popc_admittance_plant_init(&s->plant, &pc, err);
	if (st) {
		free(s);
		free(a);
		return st;
	}
	popc_force_sensor_init(&s->sensor, sc->slave_force_resolution_N, 0.0, 0);
	a->ops = &slave_ops;
	a->priv = s;
	*out = a;
	return 0;
}
