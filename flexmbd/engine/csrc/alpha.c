/* Generalized-alpha time stepping (Chung and Hulbert, 1993) for second-order systems.
 *
 * The flexible slider-crank with several beams has bending (and, with a flexible
 * elongation, axial) modes far above the motion of interest. Explicit methods must
 * resolve them for stability; generalized-alpha steps over them with controllable
 * numerical damping (spectral radius rho_inf at infinite frequency) and stays second-
 * order accurate for the slow motion.
 *
 * The state is (q, v); per step the unknown is the acceleration a at the end of the
 * step; the Newmark formulas turn it into q and v there, and Newton's method drives
 * the system's residual to zero with the system's operator (an approximate inverse
 * of its Newton matrix). By default Newton iterates to the tolerance, keeping the
 * operator while it converges fast and renewing it otherwise. With `iterations = 1`
 * the method is linearly implicit: one correction per step with the operator renewed
 * at every step's predictor (or every `renew_every` steps). Because the residual is
 * nearly linear in the step's acceleration and the operator is exact up to terms of
 * order h, the error per step keeps the method's order (a W-method argument). The
 * step is fixed, halved only when Newton fails. Outputs between steps come from the
 * cubic Hermite interpolation of q (with v) and v (with a) over the step.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "alpha.h"

#define MAX_NEWTON 8
#define SLOW_RATE 0.5      /* contraction per Newton iteration above which it has failed */
#define RENEW_AFTER 3      /* Newton iterations after which the operator is renewed next step */
#define MAX_HALVINGS 12
#define PROGRESS_EVERY 256 /* steps between progress reports (and interrupt checks) */

typedef struct {
    AlphaSystem *sys;
    const AlphaOptions *opt;
    int m;
    double alpha_m, alpha_f, gamma, beta;
    double t, t_old;
    double *q, *v, *a, *aa;               /* the state at t and the algorithmic acceleration */
    double *q0, *v0, *a0;                 /* the state at the start of the last step */
    double *qn, *vn, *an, *aan;           /* the trial state of a step */
    double *start_q, *start_v, *start_aa; /* the Newmark predictor of a step (a_new = 0) */
    double *r, *da;
    double operator_step;                 /* step of the operator, 0 when there is none */
    int operator_fresh, renew, since_renewal;
    AlphaResult result;
} Alpha;

static double *vector(int m) { return calloc(m > 0 ? m : 1, sizeof(double)); }

/* dq/da and dv/da of the Newmark update for step h */
static void coefficients(const Alpha *g, double h, double *c_q, double *c_v)
{
    const double c = (1 - g->alpha_f) / (1 - g->alpha_m);
    *c_q = g->beta * h * h * c;
    *c_v = g->gamma * h * c;
}

/* The predictor of a step: q, v at its end for a_new = 0, and aa0 with aa_new = aa0 + k a_new,
 * aa0 = (alpha_f a - alpha_m aa) / (1 - alpha_m). */
static void predictor(Alpha *g, double h)
{
    const double w_a = g->alpha_f / (1 - g->alpha_m), w_aa = -g->alpha_m / (1 - g->alpha_m);
    const double b = g->beta, gm = g->gamma;
    for (int i = 0; i < g->m; i++) {
        g->start_q[i] = g->q[i] + h * g->v[i] + h * h * b * w_a * g->a[i]
                        + h * h * (0.5 - b + b * w_aa) * g->aa[i];
        g->start_v[i] = g->v[i] + h * gm * w_a * g->a[i] + h * (1 - gm + gm * w_aa) * g->aa[i];
        g->start_aa[i] = w_a * g->a[i] + w_aa * g->aa[i];
    }
}

static void update(Alpha *g, double h)
{
    double c_q, c_v;
    const double k = (1 - g->alpha_f) / (1 - g->alpha_m);
    coefficients(g, h, &c_q, &c_v);
    for (int i = 0; i < g->m; i++) {
        g->qn[i] = g->start_q[i] + c_q * g->an[i];
        g->vn[i] = g->start_v[i] + c_v * g->an[i];
        g->aan[i] = g->start_aa[i] + k * g->an[i];
    }
}

static int renew_operator(Alpha *g, double h)
{
    double c_q, c_v;
    coefficients(g, h, &c_q, &c_v);
    int code = g->sys->renew(g->sys->context, c_q, c_v);
    if (code)
        return code;
    g->operator_step = h;
    g->operator_fresh = 1;
    g->renew = 0;
    g->result.njev++;
    g->result.nlu++;
    return FM_OK;
}

/* Whether the operator must be renewed before a step of size h: a step shorter only by the
 * round-off of t (the last one) keeps it. */
static int stale(const Alpha *g, double h)
{
    return g->operator_step == 0.0 || g->renew || fabs(g->operator_step - h) > 1e-9 * h;
}

/* A trial residual: FM_OK, -1 when the system rejects the trial state (retry smaller),
 * or a fatal error code. */
static int trial_residual(Alpha *g, double t)
{
    *g->sys->trial = 0;
    int code = g->sys->residual(g->sys->context, t, g->qn, g->vn, g->an, g->r);
    if (code && *g->sys->trial)
        return -1;
    return code;
}

/* Newton to the tolerances; 1 when the step converged, 0 when it failed, < 0 ... */
static int newton(Alpha *g, double h, int *fatal)
{
    const int m = g->m;
    double c_q, c_v, previous = -1.0;
    coefficients(g, h, &c_q, &c_v);
    predictor(g, h);
    memcpy(g->an, g->a, sizeof(double) * m);
    for (int iteration = 1; iteration <= MAX_NEWTON; iteration++) {
        update(g, h);
        int code = trial_residual(g, g->t + h);
        if (code < 0)
            return -1;
        if (code) {
            *fatal = code;
            return 0;
        }
        if (stale(g, h) && (code = renew_operator(g, h))) {
            *fatal = code;
            return 0;
        }
        if ((code = g->sys->apply(g->sys->context, g->r, g->da))) {
            *fatal = code;
            return 0;
        }
        double size = 0.0;
        for (int i = 0; i < m; i++) {
            g->an[i] += g->da[i];
            const double dq = c_q * g->da[i] / (g->opt->atol + g->opt->rtol * fabs(g->qn[i]));
            const double dv = c_v * g->da[i] / (g->opt->atol + g->opt->rtol * fabs(g->vn[i]));
            size += dq * dq + dv * dv;
        }
        size = m ? sqrt(size / (2 * m)) : 0.0;
        if (size < 0.1) {
            g->renew = iteration > RENEW_AFTER;
            update(g, h);
            return 1;
        }
        if (previous >= 0.0 && size > SLOW_RATE * previous && size > 1.0)
            return 0;
        if (!isfinite(size))
            return 0;
        previous = size;
    }
    return 0;
}

/* `iterations` corrections with the operator renewed at the predictor every renew_every
 * steps. */
static int fixed_newton(Alpha *g, double h, int *fatal)
{
    predictor(g, h);
    memcpy(g->an, g->a, sizeof(double) * g->m);
    g->since_renewal++;
    for (int iteration = 0; iteration < g->opt->iterations; iteration++) {
        update(g, h);
        int code = trial_residual(g, g->t + h);
        if (code < 0)
            return -1;
        if (code) {
            *fatal = code;
            return 0;
        }
        if (iteration == 0 && (stale(g, h) || g->since_renewal >= g->opt->renew_every)) {
            if ((code = renew_operator(g, h))) {
                *fatal = code;
                return 0;
            }
            g->since_renewal = 0;
        }
        if ((code = g->sys->apply(g->sys->context, g->r, g->da))) {
            *fatal = code;
            return 0;
        }
        for (int i = 0; i < g->m; i++)
            g->an[i] += g->da[i];
    }
    for (int i = 0; i < g->m; i++)
        if (!isfinite(g->an[i]))
            return 0;
    update(g, h);
    return 1;
}

/* One step; FM_OK or the code that ends the run. */
static int step(Alpha *g, double t_bound, double h_nominal)
{
    double h = h_nominal < t_bound - g->t ? h_nominal : t_bound - g->t;
    int outcome = 0, trial_failed = 0, fatal = FM_OK;
    for (int attempt = 0; attempt < MAX_HALVINGS; attempt++) {
        outcome = g->opt->iterations ? fixed_newton(g, h, &fatal) : newton(g, h, &fatal);
        if (fatal)
            return fatal;
        if (outcome == 1)
            break;
        trial_failed = outcome < 0;
        if (!trial_failed && !g->operator_fresh) {
            g->renew = 1;                   /* a stale operator may be to blame: renew it */
            continue;
        }
        h /= 2;
        g->renew = 1;
    }
    if (outcome != 1) {
        if (trial_failed)
            return g->sys->error->code ? g->sys->error->code : FM_NOT_CONVERGED;
        g->sys->error->code = FM_STEP_FAILED;
        g->sys->error->time = g->t;
        g->sys->error->step = h;
        return FM_STEP_FAILED;
    }
    memcpy(g->q0, g->q, sizeof(double) * g->m);
    memcpy(g->v0, g->v, sizeof(double) * g->m);
    memcpy(g->a0, g->a, sizeof(double) * g->m);
    g->t_old = g->t;
    g->t = t_bound - (g->t + h) < 1e-12 * h ? t_bound : g->t + h;
    memcpy(g->q, g->qn, sizeof(double) * g->m);
    memcpy(g->v, g->vn, sizeof(double) * g->m);
    memcpy(g->a, g->an, sizeof(double) * g->m);
    memcpy(g->aa, g->aan, sizeof(double) * g->m);
    g->operator_fresh = 0;
    g->result.nsteps++;
    return FM_OK;
}

/* q, v at time t inside the last step by cubic Hermite interpolation: q with v as its
 * slope, v with a. */
static void hermite(const Alpha *g, double t, double *q, double *v)
{
    const double h = g->t - g->t_old, s = (t - g->t_old) / h;
    const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
    const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
    for (int i = 0; i < g->m; i++) {
        q[i] = h00 * g->q0[i] + h10 * h * g->v0[i] + h01 * g->q[i] + h11 * h * g->v[i];
        v[i] = h00 * g->v0[i] + h10 * h * g->a0[i] + h01 * g->v[i] + h11 * h * g->a[i];
    }
}

AlphaResult alpha_run(AlphaSystem *sys, const double *times, int n, const double *q0,
                      const double *v0, const AlphaOptions *opt)
{
    Alpha g;
    memset(&g, 0, sizeof(g));
    const int m = sys->m;
    double **all[] = {&g.q, &g.v, &g.a, &g.aa, &g.q0, &g.v0, &g.a0, &g.qn, &g.vn, &g.an,
                      &g.aan, &g.start_q, &g.start_v, &g.start_aa, &g.r, &g.da};
    const int count = sizeof(all) / sizeof(all[0]);
    int ok = 1;
    for (int k = 0; k < count; k++)
        ok &= (*all[k] = vector(m)) != NULL;
    g.sys = sys;
    g.opt = opt;
    g.m = m;
    const double rho = opt->rho_inf;       /* Chung-Hulbert: second order, damping by rho_inf */
    g.alpha_m = (2 * rho - 1) / (rho + 1);
    g.alpha_f = rho / (rho + 1);
    g.gamma = 0.5 - g.alpha_m + g.alpha_f;
    g.beta = 0.25 * (1 - g.alpha_m + g.alpha_f) * (1 - g.alpha_m + g.alpha_f);
    g.t = times[0];
    g.result.t = g.t;
    int code = ok ? FM_OK : FM_NO_MEMORY;
    if (!code) {
        memcpy(g.q, q0, sizeof(double) * m);
        memcpy(g.v, v0, sizeof(double) * m);
        code = sys->accelerations(sys->context, g.t, g.q, g.v, g.a);
        memcpy(g.aa, g.a, sizeof(double) * m);
    }
    if (!code)
        code = sys->output(sys->context, 0, g.t, g.q, g.v, g.a);
    int k = code ? 0 : 1;
    g.result.reached = k;
    const double t_bound = times[n - 1];
    double *qk = g.qn, *vk = g.vn;
    while (!code && k < n && g.t < t_bound) {
        if ((code = step(&g, t_bound, opt->step)))
            break;
        /* an output within round-off of the step's end is this step's: fixed steps
         * accumulate round-off in t */
        const double round_off = 1e-9 * (g.t - g.t_old);
        while (!code && k < n && times[k] <= g.t + round_off) {
            if (times[k] >= g.t - round_off) {
                code = sys->output(sys->context, k, times[k], g.q, g.v, g.a);
            } else {
                hermite(&g, times[k], qk, vk);
                code = sys->output(sys->context, k, times[k], qk, vk, NULL);
            }
            if (!code)
                k++;
        }
        g.result.reached = k;
        if (!code && k < n && sys->leave && sys->leave(sys->context, g.t, g.q))
            code = FM_PARTITION;
        if (!code && opt->progress && g.result.nsteps % PROGRESS_EVERY == 0)
            code = opt->progress(opt->progress_context, g.t);
    }
    if (!code && opt->progress)
        opt->progress(opt->progress_context, g.t);
    g.result.status = code;
    g.result.t = g.t;
    if (opt->end && ok) {
        memcpy(opt->end, g.q, sizeof(double) * m);
        memcpy(opt->end + m, g.v, sizeof(double) * m);
    }
    for (int j = 0; j < count; j++)
        free(*all[j]);
    return g.result;
}
