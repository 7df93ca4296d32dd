/* libpopc: the controller port and the observer alone (popc/popc.h), over
 * the core's popc_controller, popc_admittance_controller and popc_observer:
 * the calls of popc run's loops (src/run/run.c, run_admittance.c) and of
 * popc-analyze energy (analysis/cmd_energy.c). */
#include <stdlib.h>
#include <string.h>

#include "lib_private.h"
#include "popc/core/admittance.h"
#include "popc/core/encoder.h"
#include "popc/scene/from_scene.h"

struct popc_lib_observer {
	popc_observer obs;
	double period_s;
};

POPC_API int popc_lib_port_create_impedance(const popc_lib_scene *s, double force_limit_N,
					    popc_lib_port **out, popc_lib_error *err)
{
	*out = NULL;
	int st = popc_lib_scene_validate(s, err);
	if (st)
		return st;
	/* the impedance controller on an admittance scene would run, and give
	 * none of the rows popc run logs for it */
	if (s->scene.causality != POPC_CAUSALITY_IMPEDANCE)
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_port_create_impedance: the scene's device.causality "
					  "is admittance; allowed: impedance (an admittance port: "
					  "popc_lib_port_create_admittance)");
	if (!(force_limit_N >= 0.0 && force_limit_N < (double)INFINITY))
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_port_create_impedance: force_limit_N must be "
					  "finite and >= 0 (0: none)");
	popc_lib_port *p = malloc(sizeof *p);
	if (!p)
		return popc_lib_error_set(err, POPC_LIB_ERR_NOMEM,
					  "popc_lib_port_create_impedance: out of memory");
	popc_controller_config cfg;
	popc_controller_config_from_scene(&cfg, &s->scene);
	cfg.force_limit_N = force_limit_N;
	popc_error ierr;
	if ((st = popc_controller_create(&cfg, &p->u.ctl, &ierr)) != 0) {
		free(p);
		return popc_lib_fail(err, st, &ierr);
	}
	p->causality = POPC_LIB_CAUSALITY_IMPEDANCE;
	p->period_s = popc_scene_period_s(&s->scene);
	p->resolution_m = s->scene.enc_resolution_m;
	p->k = 0;
	*out = p;
	return 0;
}

POPC_API popc_lib_causality popc_lib_port_causality(const popc_lib_port *p)
{
	return p->causality;
}

POPC_API int popc_lib_port_create_admittance(const popc_lib_scene *s, popc_lib_port **out,
					     popc_lib_error *err)
{
	*out = NULL;
	int st = popc_lib_scene_validate(s, err);
	if (st)
		return st;
	if (s->scene.causality != POPC_CAUSALITY_ADMITTANCE)
		return popc_lib_error_set(err, POPC_LIB_ERR_INVALID,
					  "popc_lib_port_create_admittance: the scene's device.causality "
					  "is impedance; allowed: admittance");
	popc_lib_port *p = malloc(sizeof *p);
	if (!p)
		return popc_lib_error_set(err, POPC_LIB_ERR_NOMEM,
					  "popc_lib_port_create_admittance: out of memory");
	popc_admittance_config_from_scene(&p->u.adm.cfg, &s->scene);
	p->causality = POPC_LIB_CAUSALITY_ADMITTANCE;
	p->period_s = popc_scene_period_s(&s->scene);
	p->resolution_m = s->scene.enc_resolution_m;
	p->k = 0;
	*out = p;
	return 0;
}

/* The answer to a step of the other causality: no motion, no force. */
static void zero_out(popc_lib_tick *out, popc_lib_admittance_tick *adm)
{
	memset(out, 0, sizeof *out);
	if (adm)
		memset(adm, 0, sizeof *adm);
}

POPC_API void popc_lib_port_step_admittance(popc_lib_port *p, long long count,
					    long long force_count, popc_lib_tick *out,
					    popc_lib_admittance_tick *adm)
{
	if (p->causality != POPC_LIB_CAUSALITY_ADMITTANCE) {
		zero_out(out, adm);
		return;
	}
	/* the fields as popc_run_admittance logs them (run_admittance.c): the
	 * VE starts at rest at tick 0's measured position */
	const double x_m = popc_encoder_position(count, p->resolution_m);
	if (p->k == 0)
		popc_admittance_init(&p->u.adm.ctl, &p->u.adm.cfg, x_m);
	popc_admittance_tick a;
	popc_admittance_step(&p->u.adm.ctl, force_count, &a);
	out->t_s = (double)p->k * p->period_s;
	out->x_m = x_m;
	out->count = count;
	out->v_mps = a.v_c_mps;
	out->f_e_N = a.f_env_N;
	out->f_pc_N = 0.0;
	out->f_c_N = 0.0;
	out->W_J = a.W_J;
	out->E_ref_J = 0.0;
	out->flags = a.flags;
	p->k++;
	if (adm) {
		adm->f_count = a.n;
		adm->f_meas_N = a.f_N;
		adm->x_ve_m = a.x_ve_m;
		adm->v_ve_mps = a.v_ve_mps;
		adm->v_pc_mps = a.v_pc_mps;
		adm->v_c_mps = a.v_c_mps;
	}
}

POPC_API void popc_lib_port_step(popc_lib_port *p, long long count, popc_lib_tick *out)
{
	if (p->causality != POPC_LIB_CAUSALITY_IMPEDANCE) {
		zero_out(out, NULL);
		return;
	}
	popc_lib_port_step_impedance(p, count, out);
}

POPC_API void popc_lib_port_free(popc_lib_port *p)
{
	if (p && p->causality == POPC_LIB_CAUSALITY_IMPEDANCE)
		popc_controller_free(p->u.ctl);
	free(p);
}

POPC_API int popc_lib_observer_create(const popc_lib_scene *s, popc_lib_observer **out,
				      popc_lib_error *err)
{
	*out = NULL;
	int st = popc_lib_scene_validate(s, err);
	if (st)
		return st;
	popc_lib_observer *o = malloc(sizeof *o);
	if (!o)
		return popc_lib_error_set(err, POPC_LIB_ERR_NOMEM,
					  "popc_lib_observer_create: out of memory");
	popc_observer_init(&o->obs, s->scene.variant, s->scene.ignore_mode);
	o->period_s = popc_scene_period_s(&s->scene);
	*out = o;
	return 0;
}

POPC_API void popc_lib_observer_step(popc_lib_observer *o, const popc_lib_tick *in, double *W_J,
				     double *E_ref_J)
{
	/* update with tick k's position and f_e, then commit the f_c sent: the
	 * order of the online controller and of popc-analyze energy */
	popc_observation ob;
	popc_observer_update(&o->obs, in->x_m, in->count, in->v_mps, o->period_s, in->f_e_N, &ob);
	popc_observer_commit(&o->obs, &ob, in->f_e_N, in->f_c_N);
	if (W_J)
		*W_J = o->obs.W_J;
	if (E_ref_J)
		*E_ref_J = o->obs.E_ref_J;
}

POPC_API void popc_lib_observer_free(popc_lib_observer *o)
{
	free(o);
}
