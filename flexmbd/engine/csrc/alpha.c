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
 * order h, the error per step keeps the method's order (a W-method argument).
 *
 * Steps are fixed (halved only when Newton fails) or, with `adaptive`, follow the
 * local error of q. Expanding the Newmark update of q with the algorithmic accelerations
 * a(t + delta h), delta = alpha_m - alpha_f, against the Taylor series of q leaves
 *     q_err = (beta + delta / 2 - 1/6) h^3 q''' ~ (beta + delta / 2 - 1/6) h^2 (a_new - a),
 * (Zienkiewicz and Xie's estimate for Newmark, generalized); its weighted root mean
 * square against atol + rtol |q| must stay below 1, as in SciPy's solvers, and the next
 * step is h (0.9 / err)^(1/3), limited to a change by 0.2 .. 5 per step. A mode that
 * numerical damping (rho_inf < 1) has taken out stops contributing to a_new - a, so the
 * stiff modes that the step does not resolve do not set it.
 *
 * Outputs between steps come from the cubic Hermite interpolation of q (with v) and v
 * (with a) over the step.
 */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "alpha.h"

#define MAX_NEWTON 8
#define SLOW_RATE 0.5      /* contraction per Newton iteration above which it has failed */
#define RENEW_AFTER 3      /* Newton iterations after which the operator is renewed next step */
#define MAX_HALVINGS 12
#define PROGRESS_EVERY 256 /* steps between progress reports (and interrupt checks) */
#define SAFETY 0.9         /* the adaptive step's margin on the error estimate */
#define LEAST_FACTOR 0.2   /* the adaptive step changes at most by these factors per step */
#define MOST_FACTOR 5.0
#define PI_BEFORE 0.067    /* exponents of the PI step control for an estimate of order 3 */
#define PI_NOW (1.0 / 3 - 0.75 * PI_BEFORE)
#define MIN_ERROR 1e-4     /* the error estimate's floor in the control (a zero estimate) */
#define KEEP_BELOW 1.25    /* a step that would grow by less keeps its size: and its operator */
#define OPERATOR_SPAN 0.3  /* relative change of the step within which the operator is kept */

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
    double h;                             /* the adaptive run's next step */
    double error_before;                  /* the error estimate of the last accepted step */
    double error_weight;                  /* |beta + delta / 2 - 1/6|: q's error estimate */
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
    const double span = g->opt->adaptive ? OPERATOR_SPAN : 1e-9;
    return g->operator_step == 0.0 || g->renew || fabs(g->operator_step - h) > span * h;
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

/* The first iterate of the step's acceleration: the last one or, with adaptive steps,
 * its linear extrapolation from the last step (the Newton iterations it saves pay for the
 * renewals that changing steps cost). */
static void guess(Alpha *g, double h)
{
    const double h_last = g->t - g->t_old;
    if (!g->opt->adaptive || g->result.nsteps == 0 || h_last <= 0.0) {
        memcpy(g->an, g->a, sizeof(double) * g->m);
        return;
    }
    const double ratio = h / h_last;
    for (int i = 0; i < g->m; i++)
        g->an[i] = g->a[i] + ratio * (g->a[i] - g->a0[i]);
}

/* Newton to the tolerances; 1 when the step converged, 0 when it failed, < 0 ... */
static int newton(Alpha *g, double h, int *fatal)
{
    const int m = g->m;
    double c_q, c_v, previous = -1.0;
    coefficients(g, h, &c_q, &c_v);
    predictor(g, h);
    guess(g, h);
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

/* Newton for a step of h, halving it while Newton fails: the step that converged in *h,
 * FM_OK, or the code that ends the run. */
static int converge(Alpha *g, double *h)
{
    int outcome = 0, trial_failed = 0, fatal = FM_OK;
    for (int attempt = 0; attempt < MAX_HALVINGS; attempt++) {
        outcome = g->opt->iterations ? fixed_newton(g, *h, &fatal) : newton(g, *h, &fatal);
        if (fatal)
            return fatal;
        if (outcome == 1)
            return FM_OK;
        trial_failed = outcome < 0;
        if (!trial_failed && !g->operator_fresh) {
            g->renew = 1;                   /* a stale operator may be to blame: renew it */
            continue;
        }
        *h /= 2;
        g->renew = 1;
    }
    if (trial_failed)
        return g->sys->error->code ? g->sys->error->code : FM_NOT_CONVERGED;
    g->sys->error->code = FM_STEP_FAILED;
    g->sys->error->time = g->t;
    g->sys->error->step = *h;
    return FM_STEP_FAILED;
}

/* The converged trial state becomes the state at t + h (t_bound when within round-off). */
static void accept(Alpha *g, double t_bound, double h)
{
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
}

/* One fixed step; FM_OK or the code that ends the run. */
static int fixed_step(Alpha *g, double t_bound, double h_nominal)
{
    double h = h_nominal < t_bound - g->t ? h_nominal : t_bound - g->t;
    int code = converge(g, &h);
    if (!code)
        accept(g, t_bound, h);
    return code;
}

/* The weighted root mean square of the local error estimate of q over the trial step. The
 * velocities' (from the change of a's change, h^3 a'') is left out: it would follow the
 * modes that the step does not resolve, whose accelerations numerical damping leaves
 * noisy long after their positions have settled, and hold the steps to their periods. */
static double error_norm(const Alpha *g, double h)
{
    const double c = g->error_weight * h * h;
    double sum = 0.0;
    for (int i = 0; i < g->m; i++) {
        const double scale = g->opt->atol + g->opt->rtol * fmax(fabs(g->q[i]), fabs(g->qn[i]));
        const double e = c * (g->an[i] - g->a[i]) / scale;
        sum += e * e;
    }
    return g->m ? sqrt(sum / g->m) : 0.0;
}

static double clamp(double x, double low, double high) { return x < low ? low : x > high ? high : x; }

/* One error-controlled step of about g->h; FM_OK or the code that ends the run. */
static int adaptive_step(Alpha *g, double t_bound)
{
    for (;;) {
        const double left = t_bound - g->t;
        double h = g->h < left ? g->h : left;
        if (h < 16 * DBL_EPSILON * fmax(fabs(g->t), fabs(t_bound))) {
            g->sys->error->code = FM_STEP_TOO_SMALL;
            g->sys->error->time = g->t;
            g->sys->error->step = h;
            return FM_STEP_TOO_SMALL;
        }
        int code = converge(g, &h);
        if (code)
            return code;
        const double err = error_norm(g, h);
        if (!isfinite(err) || err > 1.0) {  /* rejected: retry smaller */
            g->h = h * (isfinite(err) ? clamp(SAFETY * pow(err, -1.0 / 3), LEAST_FACTOR, SAFETY)
                                      : LEAST_FACTOR);
            g->result.nrejected++;
            continue;
        }
        accept(g, t_bound, h);
        /* Gustafsson's PI control: the error before damps the step's swings */
        const double last = fmax(err, MIN_ERROR);
        double factor = clamp(SAFETY * pow(last, -PI_NOW) * pow(g->error_before, PI_BEFORE),
                              LEAST_FACTOR, MOST_FACTOR);
        g->error_before = last;
        if (factor >= 1.0 && factor < KEEP_BELOW)
            factor = 1.0;
        if (h < g->h && h == left)          /* the last step was cut short by the end */
            factor = fmax(factor, g->h / h);
        g->h = fmin(h * factor, g->opt->max_step);
        return FM_OK;
    }
}

/* The first step of an adaptive run when none is given: as SciPy chooses it, from the
 * sizes of (q, v) and their rates (v, a) in the tolerance's weights, then bounded. */
static double first_step(const Alpha *g, double span)
{
    double d0 = 0.0, d1 = 0.0;
    for (int i = 0; i < g->m; i++) {
        const double sq = g->opt->atol + g->opt->rtol * fabs(g->q[i]);
        const double sv = g->opt->atol + g->opt->rtol * fabs(g->v[i]);
        d0 += (g->q[i] / sq) * (g->q[i] / sq) + (g->v[i] / sv) * (g->v[i] / sv);
        d1 += (g->v[i] / sq) * (g->v[i] / sq) + (g->a[i] / sv) * (g->a[i] / sv);
    }
    double h = d0 < 1e-10 || d1 < 1e-10 ? 1e-6 * span : 0.01 * sqrt(d0 / d1);
    return fmin(fmin(h, span), g->opt->max_step);
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
    g.error_weight = fabs(g.beta + 0.5 * (g.alpha_m - g.alpha_f) - 1.0 / 6);
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
    g.error_before = MIN_ERROR;
    if (opt->adaptive)
        g.h = opt->step > 0.0 ? fmin(opt->step, opt->max_step) : first_step(&g, t_bound - g.t);
    while (!code && k < n && g.t < t_bound) {
        if ((code = opt->adaptive ? adaptive_step(&g, t_bound) : fixed_step(&g, t_bound, opt->step)))
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
