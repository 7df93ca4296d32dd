#!/usr/bin/env python3
"""The tick of `popc run` as a numba @njit loop: a JIT reference doing popc's work.

    tick_jit.py JIT_CONSTANTS SCENE [--set section.key=value]... [--plain] [--repeat N]

Computes every tick of `popc run SCENE` for the scenes bench/jit_constants.c
covers (the paper's scene: the exact ZOH plant step, the encoder floor, the
wall, ref-energy PO/PC), operation for operation as src/run/run.c,
src/core/controller.c, include/popc/core/*.h and src/axes/sim_axis.c compute
it, in the same order and without fused multiply-adds (popc builds with
-ffp-contract=off; numba without fastmath leaves LLVM no contraction either):

  - the sample: x = x_rest + y, count = floor(x / delta), the divergence and
    2^53-count guards;
  - the controller: v, the wall, the observer's W and E_ref as compensated
    sums (compensated.h), the PC, its NaN guard and bound, the force limit;
  - the run: E_port (port_energy.h), W - E_port, the device port's
    E_dev = E_port + D with D the damping's dissipation form
    (plant_dissipation.h) summed compensated, their minima and maxima;
  - the metrics of the run summary (metrics.c: the whole run and its late
    half, sums of squares, sign changes in contact, the PC's energy, the
    rendered stiffness's sums);
  - the exchange: the operator's input from its cached segment, the exact
    step, and a period split at a breakpoint as the sim axis' advance().

What it takes from popc is what popc computes once before the loop (the
matrices of the exact step and of the dissipation form for the period and
for the parts of a split period, the rest position): jit_constants prints
them as hex floats. Its W, E_ref and E_port at the last tick equal the last
row of popc's log bit for bit (tests/perf/test_tick_jit.sh).

Prints `name value` lines: the end values as float.hex, then the ticks, the
CPU time of the compiled loop (time.process_time around the call; the
compilation, made first on a two-tick run, is printed apart as compile_s),
and ns_per_tick. --plain runs the same Python without numba (slow: for the
test where numba is missing, and to check the JIT against plain Python).
"""
import math
import subprocess
import sys
import time

import numpy as np

try:
    from numba import njit
    HAVE_NUMBA = True
except ImportError:  # the test skips (exit 77) unless --plain
    HAVE_NUMBA = False

    def njit(*args, **kwargs):
        if args and callable(args[0]):
            return args[0]
        return lambda f: f

COUNT_LIMIT = 9007199254740992.0  # 2^53 (encoder.h)
# sum_squares.h's scales: 2^300, 2^-300, 2^600, 2^-600
P300, M300, P600, M600 = 2.0 ** 300, 2.0 ** -300, 2.0 ** 600, 2.0 ** -600

# indices of the constants vector c
(C_T, C_NTICKS, C_DELTA, C_XREST, C_KXREST, C_DIVERGED, C_PCBOUND, C_FLIMIT, C_ENVKIND, C_KE,
 C_BE, C_PE, C_ISFORCE, C_KOP, C_BOP, C_KX0, C_HASDISS, C_DUR, C_N) = range(19)
# a coefficient row: phi (4), gam (8), d (4), u01 u02 u03 u12 u13 u23
R_PHI, R_GAM, R_D, R_U, R_N = 0, 4, 12, 16, 22


@njit(cache=False)
def comp_add(acc, i_sum, i_comp, d):
    """compensated.h's popc_compensated_add on acc[i_sum], acc[i_comp]."""
    s = acc[i_sum]
    t = s + d
    z = t - s
    e = (s - (t - z)) + (d - z)
    acc[i_sum] = t
    acc[i_comp] += e
    return t + acc[i_comp]


@njit(cache=False)
def dissipated(r, y, v, a, b):
    """plant_dissipation.h's popc_plant_dissipated_J for the affine input (n = 4)."""
    r0 = r[R_D + 0] * y + ((r[R_U + 0] * v + r[R_U + 1] * a) + r[R_U + 2] * b)
    r1 = r[R_D + 1] * v + (r[R_U + 3] * a + r[R_U + 4] * b)
    r2 = r[R_D + 2] * a + r[R_U + 5] * b
    r3 = r[R_D + 3] * b
    e = (y * r0 + v * r1) + (a * r2 + b * r3)
    return e if e > 0.0 else 0.0


@njit(cache=False)
def step_exact(r, st, u0, u1):
    """plant.h's popc_plant_step_exact (us = uc = 0 for these intents, their
    products kept: 0 x gam is a signed zero)."""
    in_x = (r[R_GAM + 0] * u0 + r[R_GAM + 1] * u1) + (r[R_GAM + 2] * 0.0 + r[R_GAM + 3] * 0.0)
    in_v = (r[R_GAM + 4] * u0 + r[R_GAM + 5] * u1) + (r[R_GAM + 6] * 0.0 + r[R_GAM + 7] * 0.0)
    x = st[0]
    v = st[1]
    st[0] = (r[R_PHI + 0] * x + r[R_PHI + 1] * v) + in_x
    st[1] = (r[R_PHI + 2] * x + r[R_PHI + 3] * v) + in_v


@njit(cache=False)
def segment_index(it, t):
    """intent.c's segment(): -1 before the first point, else the last i with t_i <= t."""
    if t < it[0]:
        return -1
    i = 0
    n = it.shape[0]
    while i + 1 < n and it[i + 1] <= t:
        i += 1
    return i


@njit(cache=False)
def intent_input(c, it, iq, t, u):
    """intent.c's popc_intent_input (pl_value, then the position or force
    input) into u[0] = u0, u[1] = u1; returns the next breakpoint."""
    n = it.shape[0]
    i = segment_index(it, t)
    if i < 0:
        q = iq[0]
        slope = 0.0
        nxt = it[0]
    elif i + 1 >= n:
        q = iq[n - 1]
        slope = 0.0
        nxt = math.inf
    else:
        t0 = it[i]
        t1 = it[i + 1]
        slope = (iq[i + 1] - iq[i]) / (t1 - t0)
        q = iq[i] + slope * (t - t0)
        nxt = t1
    if c[C_ISFORCE] != 0.0:
        u[0] = c[C_KX0] + q
        u[1] = slope
    else:
        u[0] = c[C_KOP] * q + c[C_BOP] * slope
        u[1] = c[C_KOP] * slope
    return nxt


@njit(cache=False)
def segment_at(c, it, iq, t, g):
    """intent.c's popc_intent_segment_at: g = [t_lo, t_next, constant, t_i,
    q_i, slope, b_slope, u1]."""
    n = it.shape[0]
    i = segment_index(it, t)
    slope = 0.0
    if i < 0:
        g[2] = 1.0
        g[3] = 0.0
        g[4] = iq[0]
        g[0] = -math.inf
        g[1] = it[0]
    elif i + 1 >= n:
        g[2] = 1.0
        g[3] = 0.0
        g[4] = iq[n - 1]
        g[0] = it[i]
        g[1] = math.inf
    else:
        g[2] = 0.0
        g[3] = it[i]
        g[4] = iq[i]
        slope = (iq[i + 1] - iq[i]) / (it[i + 1] - it[i])
        g[0] = it[i]
        g[1] = it[i + 1]
    g[5] = slope
    g[6] = c[C_BOP] * slope
    g[7] = slope if c[C_ISFORCE] != 0.0 else c[C_KOP] * slope


@njit(cache=False)
def window_add(w, f_pc, contact, sign_change):
    """metrics.c's window_add: w = [ticks, active, sq_mid, sq_big, sq_small,
    pc_max, vsign_changes, contact_ticks] (sum_squares.h's three sums)."""
    w[0] += 1.0
    if f_pc != 0.0:
        w[1] += 1.0
    a = abs(f_pc)
    if a <= P300:
        if a >= M300:
            w[2] += f_pc * f_pc
        elif a > 0.0:
            w[4] += (a * P600) * (a * P600)
    else:
        w[3] += (a * M600) * (a * M600)
    if a > w[5]:
        w[5] = a
    if contact:
        w[7] += 1.0
        w[6] += sign_change


@njit(cache=False)
def run(c, it, iq, full, split_k, split_first, split_n, parts, part_h, part_whole, n_ticks):
    """popc_run of the scene over n_ticks ticks. Returns (status, out), out
    the end values (OUT_* below)."""
    T = c[C_T]
    delta = c[C_DELTA]
    x_rest = c[C_XREST]
    k_x_rest = c[C_KXREST]
    tol = 1e-9 * T  # POPC_INTENT_TICK_TOL_PERIODS
    late_from = 0.5 * c[C_DUR]  # run.c: popc_metrics_init
    has_diss = c[C_HASDISS] != 0.0
    env_wall = c[C_ENVKIND] == 0.0
    K_e = c[C_KE]
    B_e = c[C_BE]
    p_e = c[C_PE]
    bound = c[C_PCBOUND]
    flimit = c[C_FLIMIT]
    st = np.zeros(2)           # y = x - x_rest, v
    acc = np.zeros(10)         # compensated sums: W, E_ref, E_port, D
    g = np.zeros(8)            # the cached intent segment (empty: looked up first)
    u = np.zeros(2)
    w_all = np.zeros(8)
    w_late = np.zeros(8)
    dissipated_J = 0.0 if has_diss else math.nan  # none before tick 0
    # the sample of tick 0
    x_true = x_rest + st[0]
    cf = np.floor(x_true / delta)
    if not (cf > -COUNT_LIMIT and cf < COUNT_LIMIT):
        return 6, np.zeros(16)
    count = np.int64(cf)
    # controller, port, summary and metrics state
    started = False
    x_prev = 0.0
    count_prev = np.int64(0)
    f_e_prev = 0.0
    f_c_prev = 0.0
    W = 0.0
    E_ref = 0.0
    p_started = False
    p_x_prev = 0.0
    p_fc_prev = 0.0
    E_port = 0.0
    port_min = 0.0
    po_end = 0.0
    po_max = 0.0
    has_dev = True
    dev_end = 0.0
    dev_min = 0.0
    m_started = False
    m_x_prev = 0.0
    m_fpc_prev = 0.0
    m_last_sign = 0
    pc_energy = 0.0
    fc_pen = 0.0
    pen_sq = 0.0
    wme_min = math.inf
    wme_end = 0.0
    si = 0                     # next split period
    ticks = 0
    status = 0
    for k in range(n_ticks):
        # -- popc_controller_step
        x = float(count) * delta
        v = (x - x_prev) / T if started else 0.0
        started = True
        pen = x - p_e
        if env_wall:
            if not (pen >= 0.0):
                f_e = 0.0
            else:
                f_e = K_e * pen
                if B_e != 0.0:
                    f_e += B_e * v
                f_e = f_e if f_e > 0.0 else 0.0
        else:
            f_e = K_e * pen
            if B_e != 0.0:
                f_e += B_e * v
        if k == 0:
            x_prev = x
            count_prev = count
            f_e_prev = f_e
            f_c_prev = 0.0
            dx = 0.0
        else:
            dx = x - x_prev
            E_ref = comp_add(acc, 2, 3, (f_e + f_e_prev) * dx / 2.0)
            W = comp_add(acc, 0, 1, f_c_prev * dx)
            x_prev = x
            count_prev = count
            f_e_prev = f_e
        f_pc = (E_ref - W) / dx if (W < E_ref and dx != 0.0) else 0.0
        if math.isnan(f_pc):
            f_pc = 0.0
        if f_pc > bound:
            f_pc = bound
        elif f_pc < -bound:
            f_pc = -bound
        f_c = f_e + f_pc
        if not math.isfinite(f_c):
            f_c = 0.0
        if flimit > 0.0 and abs(f_c) > flimit:
            f_c = flimit if f_c > 0.0 else -flimit
        f_c_prev = f_c
        # -- popc_run: E_port, W - E_port, E_dev
        if p_started:
            E_port = comp_add(acc, 4, 5, p_fc_prev * (x_true - p_x_prev))
        p_started = True
        p_x_prev = x_true
        p_fc_prev = f_c
        e = W - E_port
        if E_port < port_min:
            port_min = E_port
        po_end = e
        if abs(e) > po_max:
            po_max = abs(e)
        if has_dev and math.isfinite(dissipated_J):
            d = comp_add(acc, 6, 7, dissipated_J)
            dev = E_port + d
            dev_end = dev
            if dev < dev_min:
                dev_min = dev
        else:
            has_dev = False
        # -- popc_metrics_add
        t_s = float(k) * T
        sign_change = 0
        if m_started:
            mdx = x - m_x_prev
            pc_energy += m_fpc_prev * mdx
            sgn = 1 if mdx > 0 else (-1 if mdx < 0 else 0)
            if sgn != 0:
                if m_last_sign != 0 and sgn != m_last_sign:
                    sign_change = 1
                m_last_sign = sgn
        contact = (not env_wall) or x >= p_e
        if contact:
            mpen = x - p_e
            fc_pen += f_c * mpen
            pen_sq += mpen * mpen
        window_add(w_all, f_pc, contact, sign_change)
        if t_s >= late_from:
            window_add(w_late, f_pc, contact, sign_change)
        dwe = W - E_ref
        if dwe < wme_min:
            wme_min = dwe
        wme_end = dwe
        m_x_prev = x
        m_fpc_prev = f_pc
        m_started = True
        ticks = k + 1
        if k + 1 >= n_ticks:
            break
        # -- the sim axis' exchange: the plant over the period, f_c held
        dissipated_J = math.nan
        t = float(k) * T
        t_end = float(k + 1) * T
        fast = True
        if not (t >= g[0] and t < g[1] and g[1] >= t_end - tol):
            segment_at(c, it, iq, t, g)
            fast = g[1] >= t_end - tol
        if fast:
            q = g[4] if g[2] != 0.0 else g[4] + g[5] * (t - g[3])
            u0 = c[C_KX0] + q if c[C_ISFORCE] != 0.0 else c[C_KOP] * q + g[6]
            u0 = (u0 - k_x_rest) - f_c
            u1 = g[7]
            dissipated_J = dissipated(full, st[0], st[1], u0, u1) if has_diss else math.nan
            step_exact(full, st, u0, u1)
        else:
            # advance(): the parts of the period jit_constants computed
            if si >= split_k.shape[0] or split_k[si] != k:
                return 3, np.zeros(16)
            dissipated_J = 0.0
            for j in range(split_n[si]):
                p = split_first[si] + j
                nxt = intent_input(c, it, iq, t, u)
                u0 = (u[0] - k_x_rest) - f_c
                inside = nxt < t_end - tol and nxt > t
                h = nxt - t if inside else t_end - t
                if h != part_h[p]:
                    return 4, np.zeros(16)
                r = parts[p]
                if has_diss:
                    dissipated_J += dissipated(r, st[0], st[1], u0, u[1])
                step_exact(r, st, u0, u[1])
                t = nxt
            if not has_diss:
                dissipated_J = math.nan
            si += 1
        # -- the sim axis' sample
        x_true = x_rest + st[0]
        cf = np.floor(x_true / delta)
        if not math.isfinite(x_true) or not math.isfinite(st[1]) or abs(x_true) > c[C_DIVERGED]:
            status = 5
            break
        if not (cf > -COUNT_LIMIT and cf < COUNT_LIMIT):
            status = 6
            break
        count = np.int64(cf)
    out = np.zeros(16)
    out[0] = W
    out[1] = E_ref
    out[2] = E_port
    out[3] = dev_end if has_dev else math.nan
    out[4] = pc_energy
    out[5] = port_min
    out[6] = po_end
    out[7] = po_max
    out[8] = dev_min
    out[9] = wme_min
    out[10] = wme_end
    out[11] = fc_pen
    out[12] = pen_sq
    out[13] = w_all[2]
    out[14] = w_late[2]
    out[15] = float(ticks)
    return status, out


OUT_NAMES = ["W", "E_ref", "E_port", "device_energy_end", "pc_energy", "port_energy_min",
             "po_error_end", "po_error_max", "device_energy_min", "w_minus_eref_min",
             "w_minus_eref_end", "fc_pen_sum", "pen_sq_sum", "pc_sq_all", "pc_sq_late"]


def load_constants(lines):
    """jit_constants' output as the arrays run() takes."""
    c = np.zeros(C_N)
    it = iq = full = None
    split_k, split_first, split_n, parts, part_h, part_whole = [], [], [], [], [], []
    fx = float.fromhex
    for line in lines:
        f = line.split()
        if not f:
            continue
        key = f[0]
        scalar = {"period": C_T, "delta": C_DELTA, "x_rest": C_XREST, "k_x_rest": C_KXREST,
                  "diverged": C_DIVERGED, "duration": C_DUR, "pc_bound": C_PCBOUND, "force_limit": C_FLIMIT}
        if key in scalar:
            c[scalar[key]] = fx(f[1])
        elif key == "ticks":
            c[C_NTICKS] = float(int(f[1]))
        elif key == "env":
            c[C_ENVKIND] = float(int(f[1]))
            c[C_KE], c[C_BE], c[C_PE] = fx(f[2]), fx(f[3]), fx(f[4])
        elif key == "intent":
            c[C_ISFORCE] = float(int(f[1]))
            c[C_KOP], c[C_BOP], c[C_KX0] = fx(f[2]), fx(f[3]), fx(f[4])
            n = int(f[5])
            it = np.array([fx(f[6 + 2 * i]) for i in range(n)])
            iq = np.array([fx(f[7 + 2 * i]) for i in range(n)])
        elif key == "full":
            full = np.array([fx(x) for x in f[1:1 + R_N]])
            c[C_HASDISS] = float(int(f[1 + R_N]))
        elif key == "split":
            split_k.append(int(f[1]))
            split_first.append(len(parts))
            split_n.append(int(f[2]))
        elif key == "part":
            part_h.append(fx(f[1]))
            part_whole.append(int(f[2]))
            parts.append([fx(x) for x in f[3:3 + R_N]])
    parts_a = np.array(parts, dtype=np.float64).reshape(len(parts), R_N)
    return (c, it, iq, full, np.array(split_k, dtype=np.int64),
            np.array(split_first, dtype=np.int64), np.array(split_n, dtype=np.int64), parts_a,
            np.array(part_h, dtype=np.float64), np.array(part_whole, dtype=np.int64))


def main(argv):
    plain = "--plain" in argv
    argv = [a for a in argv if a != "--plain"]
    repeat = 1
    if "--repeat" in argv:
        i = argv.index("--repeat")
        repeat = int(argv[i + 1])
        del argv[i:i + 2]
    if len(argv) < 3:
        sys.stderr.write("usage: tick_jit.py JIT_CONSTANTS SCENE [--set section.key=value]... "
                         "[--plain] [--repeat N]\n")
        return 2
    if not HAVE_NUMBA and not plain:
        sys.stderr.write("tick_jit.py: numba is not installed (Debian: python3-numba); "
                         "--plain runs without it\n")
        return 77
    p = subprocess.run(argv[1:], stdout=subprocess.PIPE, universal_newlines=True)
    if p.returncode != 0:
        return p.returncode
    args = load_constants(p.stdout.splitlines())
    n_ticks = int(args[0][C_NTICKS])
    fn = run.py_func if (plain and HAVE_NUMBA) else run
    # compile (and warm) on two ticks: its CPU time is printed, not counted
    c0 = time.process_time()
    fn(*args, 2)
    compile_s = time.process_time() - c0
    best = math.inf
    for _ in range(repeat):
        c0 = time.process_time()
        status, out = fn(*args, n_ticks)
        best = min(best, time.process_time() - c0)
    if status != 0:
        sys.stderr.write("tick_jit.py: the reference stopped (status %d) at tick %d\n"
                         % (status, int(out[15])))
        return 1
    for name, v in zip(OUT_NAMES, out):
        print(name, float(v).hex())
    print("ticks", int(out[15]))
    print("jit", "numba" if (HAVE_NUMBA and not plain) else "none")
    print("compile_s %.6f" % compile_s)
    print("cpu_s %.6f" % best)
    print("ns_per_tick %.4f" % (1e9 * best / out[15]))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
