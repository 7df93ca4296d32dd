/* The chatter columns' detector (src/sweep/sweep_chatter.c): chatter.h with
 * its default thresholds and the scene's encoder resolution, as popc-analyze
 * compare runs it, fed online by a sweep's run or offline from a run's log. */
#ifndef POPC_SWEEP_CHATTER_H
#define POPC_SWEEP_CHATTER_H

#include "popc/core/chatter.h"
#include "popc/core/controller.h"
#include "popc/scene/scene.h"
#include "popc/util/error.h"

/* The detector for a run of scene s (ccfg: its controller configuration). */
int popc_sweep_chatter_init(popc_chatter *det, const popc_scene *s,
			    const popc_controller_config *ccfg, popc_error *err);

/* The scale the detector's PC thresholds are shares of, for a run of scene
 * s: controller.pc_bound (N) in impedance causality; in admittance causality
 * POPC_ADMITTANCE_CHATTER_COUNTS times the velocity of one force count
 * (popc_admittance_count_velocity_mps, docs/ANALYSIS.md). */
double popc_sweep_chatter_pc_scale(const popc_scene *s);

/* The detector over a popc log (its header's scene; an admittance log's v_pc
 * in the place of f_pc). */
int popc_sweep_chatter_from_log(const char *log_path, popc_chatter_result *res, popc_error *err);

#endif
