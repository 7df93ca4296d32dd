/* The element tree of a MAT v5 file, checked before libmatio reads it: every
 * array, nested or not, declares no more elements than the bytes that follow
 * it can hold (read_mat_check.c has the format and the reason). */
#ifndef POPC_ANALYZE_READ_MAT_CHECK_H
#define POPC_ANALYZE_READ_MAT_CHECK_H

#include "popc/util/error.h"

/* 0 when PATH's v5 element tree is sound, or when PATH is not a v5 file (v4
 * and v7.3 are libmatio's to check); otherwise POPC_ERR_INVALID, naming the
 * file, the variable and what is damaged (POPC_ERR_IO when it cannot be read). */
int ana_mat_check_v5(const char *path, popc_error *err);

#endif
