/* One state of a model: positions, rates, inertia, forces, equations of motion.
 *
 * THEORY sections 3-8, for one state at a time; every analysis of flexmbd calls these.
 * Element values live in per-element blocks (deformations, Jacobian rows, element
 * matrices); the square systems are D_c, factorised in its band after scaling rows
 * and angle columns, and the saddle-point matrix [[A, C^T], [C, 0]] over the free
 * coordinates (dependent and dynamic) and the multipliers (rigid and input
 * deformations), with A the mass matrix or the Newton matrix of an integrator.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core.h"

#define SINGULAR_RCOND 1e-13   /* scaled D_c: 1 / ||inverse||_1 below this is singular */
#define ROUND_OFF 1e-6         /* residuals below this share of the tolerance are round-off */
#define SLOW_CHORD 0.1         /* a chord step that reduces less than this gets a new D_c */
#define LARGEST_STEP 0.1       /* an integrator's Newton step, relative to coordinate sizes */

static double *alloc(int n) { return calloc(n > 0 ? n : 1, sizeof(double)); }

int fm_state_init(FmState *s, const FmModel *m)
{
    memset(s, 0, sizeof(*s));
    s->q = alloc(m->nq); s->qd = alloc(m->nq); s->qdd = alloc(m->nq);
    s->x = alloc(m->nx); s->xd = alloc(m->nx); s->xdd = alloc(m->nx);
    s->e = alloc(m->ne); s->ed = alloc(m->ne); s->edd = alloc(m->ne); s->qv = alloc(m->ne);
    s->J = alloc(m->total_j); s->blocks = alloc(m->total_b); s->ablocks = alloc(m->total_b);
    s->hvec = alloc(m->c_off[m->nel]); s->gvec = alloc(m->c_off[m->nel]);
    s->sigma = alloc(m->ne); s->w = alloc(m->ne); s->y = alloc(m->nx);
    int n = m->nx > m->ne ? m->nx : m->ne;
    n = (n > m->ns ? n : m->ns) + 1;
    s->w1 = alloc(n); s->w2 = alloc(n); s->w3 = alloc(n);
    s->w4 = alloc(n); s->w5 = alloc(n); s->w6 = alloc(n);
    if (band_init(&s->dc, m->nr, m->dc_kl, m->dc_ku))
        return FM_NO_MEMORY;
    s->cond_column = -1;
    double *all[] = {s->q, s->qd, s->qdd, s->x, s->xd, s->xdd, s->e, s->ed, s->edd, s->qv,
                     s->J, s->blocks, s->ablocks, s->hvec, s->gvec, s->sigma, s->w, s->y,
                     s->w1, s->w2, s->w3, s->w4, s->w5, s->w6};
    for (size_t k = 0; k < sizeof(all) / sizeof(all[0]); k++)
        if (!all[k])
            return FM_NO_MEMORY;
    return FM_OK;
}

void fm_state_free(FmState *s)
{
    double *all[] = {s->q, s->qd, s->qdd, s->x, s->xd, s->xdd, s->e, s->ed, s->edd, s->qv,
                     s->J, s->blocks, s->ablocks, s->hvec, s->gvec, s->sigma, s->w, s->y,
                     s->w1, s->w2, s->w3, s->w4, s->w5, s->w6};
    for (size_t k = 0; k < sizeof(all) / sizeof(all[0]); k++)
        free(all[k]);
    band_free(&s->dc);
}

void fm_state_copy(FmState *to, const FmState *from, const FmModel *m)
{
    to->t = from->t;
    memcpy(to->q, from->q, sizeof(double) * m->nq);
    memcpy(to->qd, from->qd, sizeof(double) * m->nq);
    memcpy(to->qdd, from->qdd, sizeof(double) * m->nq);
    memcpy(to->x, from->x, sizeof(double) * m->nx);
    memcpy(to->xd, from->xd, sizeof(double) * m->nx);
    memcpy(to->xdd, from->xdd, sizeof(double) * m->nx);
    memcpy(to->e, from->e, sizeof(double) * m->ne);
    memcpy(to->J, from->J, sizeof(double) * m->total_j);
    band_copy(&to->dc, &from->dc);
    to->conditioning = from->conditioning;
    to->has_factor = from->has_factor;
    to->cond_column = from->cond_column;
    to->cond_age = from->cond_age;
    to->cond_reference = from->cond_reference;
}

/* --- element passes ------------------------------------------------------------------ */
static void gather(const FmModel *m, int k, const double *x, double *c)
{
    for (int a = m->c_off[k]; a < m->c_off[k + 1]; a++)
        c[a - m->c_off[k]] = x[m->c_idx[a]];
}

size_t fm_element_values(const FmModel *m, int hessian, const double *x, double *out)
{
    double c[FM_MAX_NC];
    size_t at = 0;
    for (int k = 0; k < m->nel; k++) {
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        const size_t nd = (size_t)kern->nd, nc = (size_t)kern->nc;
        if (out) {
            gather(m, k, x, c);
            (hessian ? kern->hessian : kern->deform_jac)(c, m->param + m->p_off[k], out + at);
        }
        at += hessian ? nd * nc * nc : nd * (1 + nc);
    }
    return at;
}

/* A periodic deformation's `value` (in (-pi, pi]) plus the multiple of 2 pi nearest to its
 * reference (THEORY-SPATIAL 3): the target of its D_c row (0 when rigid, q when input or
 * dynamic), so that the Newton residual is the shortest turn; its last value when
 * released, so that it is continuous through any number of turns. */
static double unwrapped(const FmModel *m, const FmState *s, int d, double value)
{
    const int row = m->row_of_def[d];
    const double reference = row < 0 ? s->e[d]
                             : row < m->nrigid ? 0.0 : s->q[m->nxm + row - m->nrigid];
    const double two_pi = 6.283185307179586;
    return value + two_pi * nearbyint((reference - value) / two_pi);
}

/* e at s->x, and D_x with it when `jacobian`. */
static void element_pass(const FmModel *m, FmState *s, int jacobian)
{
    double c[FM_MAX_NC], out[FM_MAX_ND * (FM_MAX_NC + 1)];
    for (int k = 0; k < m->nel; k++) {
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        const int nd = kern->nd, d0 = m->d_off[k];
        gather(m, k, s->x, c);
        const double *p = m->param + m->p_off[k];
        if (jacobian) {
            kern->deform_jac(c, p, out);
            memcpy(s->J + m->j_off[k], out + nd, sizeof(double) * nd * kern->nc);
        } else {
            kern->deform(c, p, out);
        }
        for (int i = 0; i < nd; i++) {
            const int d = m->d_idx[d0 + i];
            s->e[d] = m->periodic[d] ? unwrapped(m, s, d, out[i]) : out[i];
        }
    }
}

void fm_jacobian_times(const FmModel *m, const double *Jall, const double *v, double *out)
{
    for (int k = 0; k < m->nel; k++) {
        const int nc = m->c_off[k + 1] - m->c_off[k], nd = m->d_off[k + 1] - m->d_off[k];
        const double *J = Jall + m->j_off[k];
        const int *ci = m->c_idx + m->c_off[k];
        for (int i = 0; i < nd; i++) {
            double sum = 0.0;
            for (int a = 0; a < nc; a++)
                sum += J[i * nc + a] * v[ci[a]];
            out[m->d_idx[m->d_off[k] + i]] = sum;
        }
    }
}

void fm_jacobian_t_times(const FmModel *m, const double *Jall, const double *w, double *out)
{
    memset(out, 0, sizeof(double) * m->nx);
    for (int k = 0; k < m->nel; k++) {
        const int nc = m->c_off[k + 1] - m->c_off[k], nd = m->d_off[k + 1] - m->d_off[k];
        const double *J = Jall + m->j_off[k];
        const int *ci = m->c_idx + m->c_off[k];
        for (int i = 0; i < nd; i++) {
            const double wi = w[m->d_idx[m->d_off[k] + i]];
            if (wi == 0.0)
                continue;
            for (int a = 0; a < nc; a++)
                out[ci[a]] += J[i * nc + a] * wi;
        }
    }
}

/* --- D_c --------------------------------------------------------------------------------- */
/* Assemble the scaled D_c into its band and factorise; the conditioning estimate (an
 * extra few solves) only when `estimate`. Returns FM_SINGULAR for a zero pivot. */
static int factor_dc(const FmModel *m, FmState *s, int estimate)
{
    Band *b = &s->dc;
    s->has_factor = 0;
    if (!m->nr) {
        s->conditioning = 1.0;
        s->has_factor = 1;
        return FM_OK;
    }
    memset(b->ab, 0, sizeof(double) * (size_t)b->ldab * b->n);
    for (int k = 0; k < m->ndc_map; k++)
        b->ab[m->dc_dst[k]] = s->J[m->dc_src[k]] * m->dc_w[k];
    if (band_factor(b) || !(band_min_pivot(b) > 0.0) || !isfinite(band_min_pivot(b))) {
        s->conditioning = 0.0;
        return FM_SINGULAR;
    }
    s->has_factor = 1;
    s->conditioning = NAN;
    if (estimate && !(fm_conditioning(m, s) > SINGULAR_RCOND))
        return FM_SINGULAR;
    return FM_OK;
}

/* The scaled conditioning 1 / ||D_c^-1||_1 of the current factorisation, estimated once per
 * factorisation. A full estimate (Hager: about six solves) remembers the column of the
 * inverse it found largest; the next factorisations of the state, along a motion, follow
 * that column alone (one solve) and estimate in full again every CONDITION_EVERY
 * factorisations or as soon as the column's norm has doubled: near a dead point the
 * inverse grows along its null direction, in every column that touches it. */
#define CONDITION_EVERY 16
double fm_conditioning(const FmModel *m, FmState *s)
{
    if (!m->nr)
        return 1.0;
    if (!isnan(s->conditioning))
        return s->conditioning;
    if (s->cond_column >= 0 && s->cond_age < CONDITION_EVERY) {
        const double norm = band_column_norm(&s->dc, s->cond_column);
        if (norm <= 2.0 * s->cond_reference) {
            s->cond_age++;
            return s->conditioning = 1.0 / norm;
        }
    }
    const double norm = band_inverse_norm(&s->dc, &s->cond_column);
    s->cond_age = 0;
    s->cond_reference = norm;
    return s->conditioning = 1.0 / norm;
}

/* D_c at x (the element Jacobians there), factorised; FM_SINGULAR for a zero pivot. */
int fm_factor_at(const FmModel *m, FmState *s, const double *x)
{
    memcpy(s->x, x, sizeof(double) * m->nx);
    element_pass(m, s, 1);
    return factor_dc(m, s, 1);
}

/* x = D_c^-1 r for r over the rows of D_c (in place: r becomes x over the columns). */
static void solve_dc(const FmModel *m, const FmState *s, double *r, double *work)
{
    for (int i = 0; i < m->nr; i++)
        work[m->dc_rowband[i]] = m->dc_rowscale[i] * r[i];
    band_solve(&s->dc, work);
    for (int j = 0; j < m->nr; j++)
        r[j] = m->dc_colscale[j] * work[m->dc_colband[j]];
}

/* w = D_c^-T y for y over the columns (in place: y becomes w over the rows). */
static void solve_dc_t(const FmModel *m, const FmState *s, double *y, double *work)
{
    for (int j = 0; j < m->nr; j++)
        work[m->dc_colband[j]] = m->dc_colscale[j] * y[j];
    band_solve_t(&s->dc, work);
    for (int i = 0; i < m->nr; i++)
        y[i] = m->dc_rowscale[i] * work[m->dc_rowband[i]];
}

/* D_c^-1 r, or D_c^-T r with `transposed`, in place, with the state's factorisation. */
void fm_solve_dc(const FmModel *m, FmState *s, double *r, int transposed)
{
    if (transposed)
        solve_dc_t(m, s, r, s->w2);
    else
        solve_dc(m, s, r, s->w2);
}

/* D_c^-1 R for `count` right-hand sides r (count, nr), each in place, in one pass of the
 * band through all of them (as fm_solve_dc gives each); FM_NO_MEMORY without room. */
int fm_solve_dc_many(const FmModel *m, FmState *s, double *r, int count)
{
    const size_t n = (size_t)m->nr;
    double *work = malloc(sizeof(double) * (n * (size_t)count + 1));
    if (!work)
        return FM_NO_MEMORY;
    for (int k = 0; k < count; k++)
        for (int i = 0; i < m->nr; i++)
            work[(size_t)m->dc_rowband[i] * count + k] = m->dc_rowscale[i] * r[k * n + i];
    band_solve_many(&s->dc, work, count);
    for (int k = 0; k < count; k++)
        for (int j = 0; j < m->nr; j++)
            r[k * n + j] = m->dc_colscale[j] * work[(size_t)m->dc_colband[j] * count + k];
    free(work);
    return FM_OK;
}

/* --- positions (THEORY 3) -----------------------------------------------------------------
 * Newton-Raphson for x(c) from a guess, in one of two modes:
 * - the integrator's (refresh = 0): D_c from the guess (or from nearby, `use_factor`) serves
 *   chord steps while they converge fast; once the residual is below `near` (at least the
 *   tolerance) D_x is taken there and one more step makes x accurate to second order.
 *   D_x and the rates are then as accurate as `near` relative to the model size, which an
 *   integrator with good guesses uses to solve with one Jacobian per evaluation;
 * - exact (refresh = 1): a fresh D_c at every iterate (full Newton, robust from a poor
 *   guess) and at the solution after the last step, for kinematic and inverse runs and
 *   single configurations;
 * - positions only (refresh = -1): the chord steps to the tolerance and one more, with
 *   no D_x, factor or regularity check at the solution, for outputs of positions next to
 *   a solution that had them. */
static double residual_norm(const FmModel *m, const FmState *s, double *r, int *worst)
{
    double norm = 0.0;
    *worst = -1;
    for (int i = 0; i < m->nr; i++) {
        const int d = m->rows[i];
        const double target = i < m->nrigid ? 0.0 : s->q[m->nxm + i - m->nrigid];
        r[i] = s->e[d] - target;
        if (!isfinite(r[i])) {
            *worst = -1;
            return INFINITY;
        }
        if (fabs(r[i]) > norm || *worst < 0) {
            norm = fabs(r[i]) > norm ? fabs(r[i]) : norm;
            *worst = d;
        }
    }
    return norm;
}

static int fail(FmError *err, int code, double t, int iterations, double residual, int worst)
{
    if (err) {
        err->code = code;
        err->time = t;
        err->iterations = iterations;
        err->residual = residual;
        err->worst = worst;
    }
    return code;
}

/* The largest change of a dependent coordinate in r, relative to the coordinate's size. */
static double largest_move(const FmModel *m, const double *r)
{
    double move = 0.0;
    for (int j = 0; j < m->nr; j++) {
        const double v = fabs(r[j]) / m->coord_size[m->dep[j]];
        move = v > move ? v : move;
    }
    return move;
}

int fm_positions(const FmModel *m, FmState *s, double t, const double *guess, double near,
                 int use_factor, int refresh, FmError *err)
{
    const int nr = m->nr;
    double *r = s->w1, *work = s->w2;
    int code = FM_OK, worst = -1, fresh, iteration;
    double norm = 0.0, previous = -1.0;
    s->t = t;
    memcpy(s->x, guess, sizeof(double) * m->nx);
    for (int k = 0; k < m->nfixed; k++)
        s->x[m->fixed[k]] = m->x_fixed[k];
    for (int k = 0; k < m->nxm; k++)
        s->x[m->q_coord[k]] = s->q[k];
    if (near < m->tolerance)
        near = m->tolerance;
    if (!use_factor || !s->has_factor || !nr) {
        element_pass(m, s, 1);
        fresh = 1;
        if ((code = factor_dc(m, s, 0)))
            goto done;
        if (!nr)
            goto done;
    } else {
        element_pass(m, s, 0);
        fresh = 0;
    }
    for (iteration = 0; iteration <= m->max_iterations; iteration++) {
        norm = residual_norm(m, s, r, &worst);
        if (norm <= near)
            break;
        if (!isfinite(norm) || iteration == m->max_iterations) {
            code = fail(err, FM_NOT_CONVERGED, t, iteration, norm, worst);
            goto done;
        }
        solve_dc(m, s, r, work);
        /* An integrator's step beyond LARGEST_STEP of a coordinate's size is D_c's near-null
         * direction magnified (nearly redundant constraints): from a kept D_c, Newton goes
         * on with a fresh one; a fresh one's step is cut to that size. */
        const double move = refresh <= 0 ? largest_move(m, r) : 0.0;
        if (move > LARGEST_STEP && !fresh) {
            element_pass(m, s, 1);
            fresh = 1;
            previous = -1.0;
            if ((code = factor_dc(m, s, 0)))
                goto done;
            continue;
        }
        const double cut = move > LARGEST_STEP ? LARGEST_STEP / move : 1.0;
        for (int j = 0; j < nr; j++)
            s->x[m->dep[j]] -= cut * r[j];
        const int slow = refresh > 0 || cut < 1.0
                         || (previous >= 0.0 && norm > SLOW_CHORD * previous);
        fresh = slow;
        previous = slow ? -1.0 : norm;
        element_pass(m, s, slow);
        if (slow && factor_dc(m, s, 0)) {    /* lost on the way: Newton failed, not the pose */
            worst = -1;
            norm = residual_norm(m, s, r, &worst);
            code = fail(err, FM_NOT_CONVERGED, t, iteration + 1, norm, worst);
            goto done;
        }
    }
    if (refresh < 0) {                       /* positions only: x to second order, e there */
        if (norm > ROUND_OFF * m->tolerance) {
            solve_dc(m, s, r, work);
            for (int j = 0; j < nr; j++)
                s->x[m->dep[j]] -= r[j];
            element_pass(m, s, 0);
        }
        goto done;
    }
    if (!fresh) {                            /* the Jacobian at the last point */
        element_pass(m, s, 1);
        norm = residual_norm(m, s, r, &worst);
        if ((code = factor_dc(m, s, 0)))
            goto done;
    }
    if (fm_conditioning(m, s) < m->regularity_limit) {
        code = FM_SINGULAR_TOLERANCE;
        if (err) {
            err->conditioning = s->conditioning;
            err->limit = m->regularity_limit;
        }
        goto done;
    }
    if (norm > ROUND_OFF * m->tolerance) {   /* one more step: x to second order */
        double *change = s->w3, *de = s->w4;
        memset(change, 0, sizeof(double) * m->nx);
        solve_dc(m, s, r, work);
        for (int j = 0; j < nr; j++) {
            s->x[m->dep[j]] -= r[j];
            change[m->dep[j]] = -r[j];
        }
        if (refresh > 0) {                   /* D_x and D_c at the solution itself */
            element_pass(m, s, 1);
            if ((code = factor_dc(m, s, 0)))
                goto done;
        } else {                             /* e there, to first order */
            fm_jacobian_times(m, s->J, change, de);
            for (int i = 0; i < m->ne; i++)
                s->e[i] += de[i];
        }
    }
done:
    if (code == FM_SINGULAR && err)
        fail(err, FM_SINGULAR, t, 0, norm, -1);
    else if (code == FM_SINGULAR_TOLERANCE && err)
        err->code = code, err->time = t;
    return code;
}

/* --- rates (THEORY 4) ------------------------------------------------------------------------ */
void fm_dependent_rates(const FmModel *m, FmState *s, double *rates, const double *targets,
                        const double *extra)
{
    if (!m->nr)
        return;
    double *rhs = s->w1, *work = s->w2, *dv = s->w3;
    for (int j = 0; j < m->nr; j++)
        rates[m->dep[j]] = 0.0;
    fm_jacobian_times(m, s->J, rates, dv);
    for (int i = 0; i < m->nr; i++) {
        const int d = m->rows[i];
        rhs[i] = -dv[d] - (extra ? extra[d] : 0.0);
        if (i >= m->nrigid)
            rhs[i] += targets[i - m->nrigid];
    }
    solve_dc(m, s, rhs, work);
    for (int j = 0; j < m->nr; j++)
        rates[m->dep[j]] = rhs[j];
}

static void quadratic_pass(const FmModel *m, FmState *s)
{
    double c[FM_MAX_NC], v[FM_MAX_NC], out[FM_MAX_ND];
    for (int k = 0; k < m->nel; k++) {
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        gather(m, k, s->x, c);
        gather(m, k, s->xd, v);
        kern->quadratic(c, v, m->param + m->p_off[k], out);
        for (int i = 0; i < kern->nd; i++)
            s->qv[m->d_idx[m->d_off[k] + i]] = out[i];
    }
}

/* conditioning of D_c, relative to the reference configuration's, below which it is nearly
 * singular: positions are solved tighter than asked (fm_kinematics), and an integrator's
 * solutions are checked for the branch they lie on (runs.c) */
#define TIGHTEN_BELOW 1e-2

int fm_nearly_singular(const FmModel *m, FmState *s)
{
    return fm_conditioning(m, s) < TIGHTEN_BELOW * m->reference_conditioning;
}

int fm_kinematics(const FmModel *m, FmState *s, double t, const double *guess, double near,
                  int use_factor, int refresh, FmError *err)
{
    int code = fm_positions(m, s, t, guess, near, use_factor, refresh, err);
    if (code)
        return code;
    /* The rates come from D_c, which magnifies an error of the positions by one over its
     * conditioning: where redundant constraints make it nearly singular (a parallelogram
     * whose bars align), a position loose to `near` would give velocities of the other
     * branch. There the positions are solved to near times the conditioning. */
    if (near > m->tolerance && fm_nearly_singular(m, s)) {
        const double conditioning = fm_conditioning(m, s);
        double *start = s->w6;
        memcpy(start, s->x, sizeof(double) * m->nx);
        const double tight = near * conditioning > m->tolerance ? near * conditioning
                                                                 : m->tolerance;
        if ((code = fm_positions(m, s, t, start, tight, 1, refresh, err)))
            return code;
    }
    memset(s->xd, 0, sizeof(double) * m->nx);
    memset(s->xdd, 0, sizeof(double) * m->nx);
    for (int k = 0; k < m->nxm; k++) {
        s->xd[m->q_coord[k]] = s->qd[k];
        s->xdd[m->q_coord[k]] = s->qdd[k];
    }
    fm_dependent_rates(m, s, s->xd, s->qd + m->nxm, NULL);
    quadratic_pass(m, s);
    fm_dependent_rates(m, s, s->xdd, s->qdd + m->nxm, s->qv);
    fm_jacobian_times(m, s->J, s->xd, s->ed);
    fm_jacobian_times(m, s->J, s->xdd, s->edd);
    for (int i = 0; i < m->ne; i++)
        s->edd[i] += s->qv[i];
    return FM_OK;
}

/* --- forces (THEORY 5, 6) ------------------------------------------------------------------- */
void fm_stresses(const FmModel *m, FmState *s)
{
    memset(s->sigma, 0, sizeof(double) * m->ne);
    for (int k = 0; k < m->nel; k++) {
        if (!m->elastic[k])
            continue;
        const int nd = m->d_off[k + 1] - m->d_off[k];
        const int *di = m->d_idx + m->d_off[k];
        const double *S = m->S + m->law_off[k], *C = m->C + m->law_off[k];
        for (int i = 0; i < nd; i++) {
            double sum = m->sigma0[di[i]];
            for (int j = 0; j < nd; j++)
                sum += S[i * nd + j] * s->e[di[j]] + C[i * nd + j] * s->ed[di[j]];
            s->sigma[di[i]] = m->elastic_def[di[i]] ? sum : 0.0;
        }
    }
}

void fm_inertia(const FmModel *m, FmState *s)
{
    double c[FM_MAX_NC], v[FM_MAX_NC];
    for (int k = 0; k < m->nel; k++) {
        const int nc = m->c_off[k + 1] - m->c_off[k];
        double *M = s->blocks + m->b_off[k], *h = s->hvec + m->c_off[k],
               *g = s->gvec + m->c_off[k];
        memcpy(M, m->mconst + m->b_off[k], sizeof(double) * nc * nc);
        memset(h, 0, sizeof(double) * nc);
        memset(g, 0, sizeof(double) * nc);
        if (!m->varying[k])
            continue;
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        const double *p = m->param + m->p_off[k], mass = m->emass[k];
        double out[FM_MAX_NC * FM_MAX_NC];
        gather(m, k, s->x, c);
        gather(m, k, s->xd, v);
        kern->mass(c, p, out);
        for (int a = 0; a < nc * nc; a++)
            M[a] += mass * out[a];
        kern->inertia(c, v, p, out);
        for (int a = 0; a < nc; a++)
            h[a] = mass * out[a];
        if (m->gravity_on && kern->gravity) {   /* rotary inertia has no weight */
            kern->gravity(c, p, m->gravity, out);
            for (int a = 0; a < nc; a++)
                g[a] = mass * out[a];
        }
    }
}

/* out += the elements' M xdd + h (less their gravity g with `gravity`), with the element
 * matrices of fm_inertia. */
static void add_element_inertia(const FmModel *m, const FmState *s, int gravity, double *out)
{
    for (int k = 0; k < m->nel; k++) {
        const int nc = m->c_off[k + 1] - m->c_off[k], *ci = m->c_idx + m->c_off[k];
        const double *M = s->blocks + m->b_off[k], *h = s->hvec + m->c_off[k],
                     *g = s->gvec + m->c_off[k];
        for (int a = 0; a < nc; a++) {
            double sum = gravity ? h[a] - g[a] : h[a];
            for (int b = 0; b < nc; b++)
                sum += M[a * nc + b] * s->xdd[ci[b]];
            out[ci[a]] += sum;
        }
    }
}

/* The inertia forces M xdd + h (nx) then the deformation rates ed (ne) of the state in s,
 * with the element matrices of fm_inertia, into out. */
static void inertia_forces_and_rates(const FmModel *m, const FmState *s, double *out)
{
    for (int i = 0; i < m->nx; i++)
        out[i] = m->nodal_mass[i] * s->xdd[i];
    add_element_inertia(m, s, 0, out);
    memcpy(out + m->nx, s->ed, sizeof(double) * m->ne);
}

int fm_inertia_slopes(const FmModel *m, FmState *s, const double *x, const double *q,
                      const double *qd, const double *qdd, const double *step, int rates,
                      double *out, FmError *err)
{
    const int n = m->nx + m->ne, nq = m->nq;
    double *plus = alloc(n), *minus = alloc(n);
    int code = plus && minus ? FM_OK : FM_NO_MEMORY;
    for (int j = 0; !code && j < nq; j++) {
        for (int side = 0; !code && side < 2; side++) {
            memcpy(s->q, q, sizeof(double) * nq);
            memcpy(s->qd, qd, sizeof(double) * nq);
            memcpy(s->qdd, qdd, sizeof(double) * nq);
            (rates ? s->qd : s->q)[j] += side ? -step[j] : step[j];
            code = fm_kinematics(m, s, NAN, x, m->tolerance, 0, 1, err);
            if (!code) {
                fm_inertia(m, s);
                inertia_forces_and_rates(m, s, side ? minus : plus);
            }
        }
        for (int r = 0; !code && r < n; r++)
            out[(size_t)r * nq + j] = (plus[r] - minus[r]) / (2.0 * step[j]);
    }
    free(plus);
    free(minus);
    return code;
}

/* y = M xdd + h - f + D_x^T sigma with the element matrices of fm_inertia and the
 * stresses in s->sigma; `user` are applied loads (nx) or NULL. */
void fm_nodal_force(const FmModel *m, FmState *s, const double *user)
{
    fm_jacobian_t_times(m, s->J, s->sigma, s->y);
    for (int i = 0; i < m->nx; i++)
        s->y[i] += m->nodal_mass[i] * s->xdd[i] - m->f_const[i] - (user ? user[i] : 0.0);
    /* on a spatial rotational node the loads of lam1..lam3 are a global moment M, whose
     * generalized force 2 E(lam)^T M turns with the node (the spatial theory, section 5) */
    for (int r = 0; r < m->nrot; r++) {
        const int *at = m->rot + 4 * r;
        double lam[4], moment[3], force[4];
        for (int a = 0; a < 4; a++)
            lam[a] = s->x[at[a]];
        for (int a = 0; a < 3; a++)
            moment[a] = m->f_const[at[a + 1]] + (user ? user[at[a + 1]] : 0.0);
        fm_moment_load(lam, moment, force);
        s->y[at[0]] -= force[0];
        for (int a = 1; a < 4; a++)
            s->y[at[a]] += moment[a - 1] - force[a];
    }
    add_element_inertia(m, s, 1, s->y);
}

/* --- gravity that turns with an element ------------------------------------------------------ */
/* Whether element k's gravity load depends on its coordinates (a consistent mass that
 * varies with the configuration, under gravity). */
static int turning_gravity(const FmModel *m, int k)
{
    return m->gravity_on && m->varying[k] && FM_KERNELS[m->etype[k]].gravity_jac != NULL;
}

size_t fm_gravity_slopes(const FmModel *m, const double *x, double *out)
{
    double c[FM_MAX_NC];
    size_t at = 0;
    for (int k = 0; k < m->nel; k++) {
        const size_t nc = (size_t)(m->c_off[k + 1] - m->c_off[k]);
        if (out && turning_gravity(m, k)) {
            gather(m, k, x, c);
            FM_KERNELS[m->etype[k]].gravity_jac(c, m->param + m->p_off[k], m->gravity,
                                                out + at);
            for (size_t a = 0; a < nc * nc; a++)
                out[at + a] *= m->emass[k];
        } else if (out) {
            memset(out + at, 0, sizeof(double) * nc * nc);
        }
        at += nc * nc;
    }
    return at;
}

/* --- the saddle-point system (THEORY 7, 8) ---------------------------------------------------- */
static int band_index(const Band *b, int row, int col)   /* band.c's layout */
{
    return b->kl + b->ku + row - col + col * b->ldab;
}

/* A of [[A, C^T], [C, 0]] into sd (zeroed first): A = c_m M + c_q (D^T S D + sum_i sigma_i
 * D_xx,i) + c_v D^T C D - c_g dg/dx, with the stresses sigma = sigma_el - w of the state (w
 * the multipliers of its reduced residual, or minus the constraint stresses of a static
 * one) and g the gravity loads of the elements whose gravity turns with them. */
static void saddle_matrix(const FmModel *m, FmState *s, Band *sd, double c_m, double c_q,
                          double c_v, double c_g)
{
    double H[FM_MAX_ND * FM_MAX_NC * FM_MAX_NC], c[FM_MAX_NC];
    const int stiff = c_q != 0.0 || c_v != 0.0 || c_m != 1.0 || c_g != 0.0;
    const double *blocks = s->blocks;
    if (stiff) {
        for (int a = 0; a < m->total_b; a++)
            s->ablocks[a] = c_m * s->blocks[a];
        blocks = s->ablocks;
        for (int k = 0; k < m->nel; k++) {
            const int nc = m->c_off[k + 1] - m->c_off[k], nd = m->d_off[k + 1] - m->d_off[k];
            const int *di = m->d_idx + m->d_off[k];
            double *A = s->ablocks + m->b_off[k];
            const double *J = s->J + m->j_off[k];
            if (m->elastic[k] && (c_q != 0.0 || c_v != 0.0)) {
                const double *S = m->S + m->law_off[k], *C = m->C + m->law_off[k];
                double LJ[FM_MAX_ND * FM_MAX_NC];
                for (int i = 0; i < nd; i++)          /* (c_q S + c_v C) D */
                    for (int b = 0; b < nc; b++) {
                        double sum = 0.0;
                        for (int j = 0; j < nd; j++)
                            sum += (c_q * S[i * nd + j] + c_v * C[i * nd + j]) * J[j * nc + b];
                        LJ[i * nc + b] = sum;
                    }
                for (int a = 0; a < nc; a++)          /* D^T (c_q S + c_v C) D */
                    for (int b = 0; b < nc; b++) {
                        double sum = 0.0;
                        for (int i = 0; i < nd; i++)
                            sum += J[i * nc + a] * LJ[i * nc + b];
                        A[a * nc + b] += sum;
                    }
            }
            int stressed = 0;
            for (int i = 0; i < nd; i++)
                stressed |= s->sigma[di[i]] - s->w[di[i]] != 0.0;
            if (stressed && c_q != 0.0) {            /* sum_i sigma_i D_xx,i */
                gather(m, k, s->x, c);
                FM_KERNELS[m->etype[k]].hessian(c, m->param + m->p_off[k], H);
                for (int i = 0; i < nd; i++) {
                    const double weight = c_q * (s->sigma[di[i]] - s->w[di[i]]);
                    for (int a = 0; a < nc * nc; a++)
                        A[a] += weight * H[i * nc * nc + a];
                }
            }
            if (c_g != 0.0 && turning_gravity(m, k)) {     /* - dg/dx */
                gather(m, k, s->x, c);
                FM_KERNELS[m->etype[k]].gravity_jac(c, m->param + m->p_off[k], m->gravity, H);
                for (int a = 0; a < nc * nc; a++)
                    A[a] -= c_g * m->emass[k] * H[a];
            }
        }
    }
    memset(sd->ab, 0, sizeof(double) * (size_t)sd->ldab * sd->n);
    for (int e = 0; e < m->nsd_a; e++)
        sd->ab[m->sd_a_dst[e]] += blocks[m->sd_a_src[e]];
    for (int e = 0; e < m->nsd_m; e++)
        sd->ab[m->sd_m_dst[e]] += c_m * m->nodal_mass[m->sd_m_coord[e]];
}

/* The constraint rows C of sd, scaled to the size of A; returns the scale, and the size
 * of the matrix that its pivots are judged against in *biggest. The scale makes the
 * pivot test judge the system in the same way whatever the units of mass (kg or tonnes)
 * and length; a multiplier solved is the scale times its unknown. */
static double saddle_constraints(const FmModel *m, const FmState *s, Band *sd, double *biggest)
{
    double big = 0.0, biggest_c = 0.0;
    for (size_t a = 0; a < (size_t)sd->ldab * sd->n; a++)
        if (fabs(sd->ab[a]) > big)
            big = fabs(sd->ab[a]);
    for (int e = 0; e < m->nsd_c; e++)
        if (fabs(s->J[m->sd_c_src[e]]) > biggest_c)
            biggest_c = fabs(s->J[m->sd_c_src[e]]);
    const double scale = big > 0.0 && biggest_c > 0.0 && isfinite(big / biggest_c)
                         ? big / biggest_c : 1.0;
    for (int e = 0; e < m->nsd_c; e++) {
        const double v = scale * s->J[m->sd_c_src[e]];
        sd->ab[m->sd_c_dst[e]] = v;
        sd->ab[m->sd_c_dstt[e]] = v;
    }
    *biggest = big > 0.0 ? big : scale * biggest_c;
    return scale;
}

/* [[A, C^T], [C, 0]] over the free coordinates and the multipliers, factorised in sd. A is
 * the mass matrix, and for a Newton matrix (c_q, c_v not both zero) A = M + c_q (D^T S D
 * + sum_i sigma_i D_xx,i) + c_v D^T C D: the element stiffness and damping, and the
 * geometric stiffness of every stress of the state, elastic and of the constraints (sigma
 * = sigma_el - w, with w the multipliers of its reduced residual). This is the derivative
 * of the reduced residual but for the velocity terms of the inertia, which are of order h
 * relative to the rest. */
int fm_saddle(const FmModel *m, FmState *s, Band *sd, double c_q, double c_v, FmError *err)
{
    double biggest;
    saddle_matrix(m, s, sd, 1.0, c_q, c_v, 0.0);
    saddle_constraints(m, s, sd, &biggest);
    if (band_factor(sd) || !(band_min_pivot(sd) > 1e-14 * biggest)) {
        /* where D_c is nearly singular the constraints are dependent, not the mass missing */
        const int dependent = s->has_factor && fm_nearly_singular(m, s);
        return fail(err, dependent ? FM_SINGULAR : FM_MASSLESS, s->t, 0, 0.0, -1);
    }
    return FM_OK;
}

/* --- static equilibrium in all coordinates ------------------------------------------------ */
/* At the configuration s->x with the constraint stresses mu (nmult) under the applied loads
 * `user` (nx, or NULL), with s->q holding the targets of the input deformations and the
 * references of the periodic ones: the residual of the static equilibrium over the
 * saddle-point unknowns into r (ns): D^T (sigma_el + mu) - f on the free coordinates, then
 * e - target on the multipliers' deformations; and its tangent [[K, C^T], [C, 0]],
 * factorised in sd, with K = D^T S D + sum_i (sigma_el,i + mu_i) D_xx,i - df/dx (df/dx: the
 * turning generalized force 2 E(lam)^T M of a global moment, and the gravity of elements
 * whose mass turns with them). The scale of sd's constraint
 * rows goes to *scale. FM_OK, or FM_MASSLESS when the tangent is singular (a mechanism,
 * buckling) or FM_NOT_FINITE. */
int fm_static_saddle(const FmModel *m, FmState *s, Band *sd, const double *user,
                     const double *mu, double *r, double *scale, FmError *err)
{
    double *stress = s->w1, *pulled = s->w2;
    memset(s->xd, 0, sizeof(double) * m->nx);
    memset(s->xdd, 0, sizeof(double) * m->nx);
    memset(s->ed, 0, sizeof(double) * m->ne);
    memset(s->edd, 0, sizeof(double) * m->ne);
    element_pass(m, s, 1);
    fm_stresses(m, s);
    fm_inertia(m, s);
    fm_nodal_force(m, s, user);
    for (int d = 0; d < m->ne; d++) {
        const int j = m->mult_of_def[d];
        stress[d] = j >= 0 ? mu[j] : 0.0;
        s->w[d] = -stress[d];
    }
    fm_jacobian_t_times(m, s->J, stress, pulled);
    int finite = 1;
    for (int i = 0; i < m->nx; i++)
        if (m->free_of[i] >= 0) {
            r[m->free_of[i]] = s->y[i] + pulled[i];
            finite &= isfinite(r[m->free_of[i]]);
        }
    for (int d = 0; d < m->ne; d++) {
        const int j = m->mult_of_def[d], row = m->row_of_def[d];
        if (j < 0)
            continue;
        const double target = row < m->nrigid ? 0.0 : s->q[m->nxm + row - m->nrigid];
        r[m->nfree + j] = s->e[d] - target;
        finite &= isfinite(r[m->nfree + j]);
    }
    if (!finite)
        return fail(err, FM_NOT_FINITE, s->t, 0, 0.0, -1);
    saddle_matrix(m, s, sd, 0.0, 1.0, 0.0, 1.0);
    for (int k = 0; k < m->nrot; k++) {
        const int *at = m->rot + 4 * k;
        double moment[3], unit[4] = {0.0, 0.0, 0.0, 0.0}, force[4];
        int loaded = 0;
        for (int a = 0; a < 3; a++) {
            moment[a] = m->f_const[at[a + 1]] + (user ? user[at[a + 1]] : 0.0);
            loaded |= moment[a] != 0.0;
        }
        for (int b = 0; loaded && b < 4; b++) {
            const int col = m->free_of[at[b]];
            unit[b] = 1.0;
            fm_moment_load(unit, moment, force);   /* linear in lam: column b of df/dlam */
            unit[b] = 0.0;
            for (int a = 0; col >= 0 && a < 4; a++)
                if (m->free_of[at[a]] >= 0)
                    sd->ab[band_index(sd, m->sd_band[m->free_of[at[a]]], m->sd_band[col])]
                        -= force[a];
        }
    }
    double biggest;
    *scale = saddle_constraints(m, s, sd, &biggest);
    if (band_factor(sd) || !(band_min_pivot(sd) > 1e-14 * biggest))
        return fail(err, FM_MASSLESS, s->t, 0, 0.0, -1);
    return FM_OK;
}

/* out = M v over the free coordinates (nfree each), for `count` vectors v (row-major), with
 * the element masses of the state's last fm_inertia. */
void fm_free_mass_times(const FmModel *m, const FmState *s, const double *v, int count,
                        double *out)
{
    memset(out, 0, sizeof(double) * (size_t)m->nfree * count);
    for (int k = 0; k < m->nel; k++) {
        const int nc = m->c_off[k + 1] - m->c_off[k], *ci = m->c_idx + m->c_off[k];
        const double *M = s->blocks + m->b_off[k];
        for (int a = 0; a < nc; a++) {
            const int ia = m->free_of[ci[a]];
            if (ia < 0)
                continue;
            for (int b = 0; b < nc; b++) {
                const int ib = m->free_of[ci[b]];
                const double mab = M[a * nc + b];
                if (ib < 0 || mab == 0.0)
                    continue;
                for (int j = 0; j < count; j++)
                    out[(size_t)j * m->nfree + ia] += mab * v[(size_t)j * m->nfree + ib];
            }
        }
    }
    for (int i = 0; i < m->nx; i++)
        if (m->free_of[i] >= 0 && m->nodal_mass[i] != 0.0)
            for (int j = 0; j < count; j++)
                out[(size_t)j * m->nfree + m->free_of[i]] +=
                    m->nodal_mass[i] * v[(size_t)j * m->nfree + m->free_of[i]];
}

/* dq = -Q z with [[A, C^T], [C, 0]] [z; lambda] = [Q^T rhs; 0]: the change of the dynamic
 * entries of q for a residual `rhs` over them (Q: dynamic coordinates directly, dynamic
 * deformations through their rows of D_x). `J` are the element Jacobians the saddle-point
 * matrix was assembled with: a kept operator is applied as a whole, from its own state. */
void fm_saddle_apply(const FmModel *m, FmState *s, const Band *sd, const double *J,
                     const double *rhs, double *dq)
{
    double *u = s->w1, *z = s->w3, *rates = s->w4, *pulled = s->w5, *w = s->w6;
    memset(u, 0, sizeof(double) * sd->n);
    memset(w, 0, sizeof(double) * m->ne);
    for (int k = 0; k < m->ndc; k++)
        u[m->sd_band[m->free_of[m->dyn_coord[k]]]] += rhs[k];
    for (int k = 0; k < m->nd_dyn - m->ndc; k++)
        w[m->dyn_def[k]] = rhs[m->ndc + k];
    fm_jacobian_t_times(m, J, w, pulled);
    for (int i = 0; i < m->nx; i++)
        if (m->free_of[i] >= 0)
            u[m->sd_band[m->free_of[i]]] += pulled[i];
    band_solve(sd, u);
    for (int i = 0; i < m->nx; i++)
        z[i] = m->free_of[i] >= 0 ? u[m->sd_band[m->free_of[i]]] : 0.0;
    for (int k = 0; k < m->ndc; k++)
        dq[k] = -z[m->dyn_coord[k]];
    fm_jacobian_times(m, J, z, rates);
    for (int k = 0; k < m->nd_dyn - m->ndc; k++)
        dq[m->ndc + k] = -rates[m->dyn_def[k]];
}

/* The accelerations of a state evaluated with the dynamic entries of qdd at zero: the
 * saddle-point system with A = M gives the change z of the free coordinates'
 * accelerations; the dynamic entries of qdd, xdd and edd are completed (THEORY 7). */
int fm_accelerations(const FmModel *m, FmState *s, Band *sd, const double *user, FmError *err)
{
    int code;
    fm_stresses(m, s);
    fm_inertia(m, s);
    fm_nodal_force(m, s, user);
    if ((code = fm_saddle(m, s, sd, 0.0, 0.0, err)))
        return code;
    double *u = s->w1, *z = s->w3, *rates = s->w4;
    memset(u, 0, sizeof(double) * sd->n);
    memset(z, 0, sizeof(double) * m->nx);
    for (int i = 0; i < m->nx; i++)
        if (m->free_of[i] >= 0)
            u[m->sd_band[m->free_of[i]]] = s->y[i];
    band_solve(sd, u);
    int finite = 1;
    for (int i = 0; i < m->nx; i++)
        if (m->free_of[i] >= 0) {
            z[i] = u[m->sd_band[m->free_of[i]]];
            finite &= isfinite(z[i]);
            s->xdd[i] -= z[i];
        }
    fm_jacobian_times(m, s->J, z, rates);
    for (int k = 0; k < m->ndc; k++)
        s->qdd[m->q_dyn[k]] = -z[m->dyn_coord[k]];
    for (int k = 0; k < m->nd_dyn - m->ndc; k++)
        s->qdd[m->q_dyn[m->ndc + k]] = -rates[m->dyn_def[k]];
    for (int i = 0; i < m->ne; i++)
        s->edd[i] -= rates[i];
    if (!finite)
        return fail(err, FM_MASSLESS, s->t, 0, 0.0, -1);
    fm_nodal_force(m, s, user);              /* at the accelerations found */
    return FM_OK;
}

/* R = F_q^T y on the dynamic entries of q (nd_dyn), with w = D_c^-T y(c) over the rows
 * of D_c (kept in s->w, ne entries, zero off the rows) (THEORY 4, 7). */
void fm_reduced_residual(const FmModel *m, FmState *s, double *r)
{
    double *w = s->w;
    double *col = s->w1, *work = s->w2, *pulled = s->w3;
    memset(w, 0, sizeof(double) * m->ne);
    for (int j = 0; j < m->nr; j++)
        col[j] = s->y[m->dep[j]];
    if (m->nr)
        solve_dc_t(m, s, col, work);
    for (int i = 0; i < m->nr; i++)
        w[m->rows[i]] = col[i];
    if (r) {
        fm_jacobian_t_times(m, s->J, w, pulled);
        for (int k = 0; k < m->ndc; k++)
            r[k] = s->y[m->dyn_coord[k]] - pulled[m->dyn_coord[k]];
        for (int k = 0; k < m->nd_dyn - m->ndc; k++)
            r[m->ndc + k] = w[m->dyn_def[k]];
    }
}

/* Stresses of the constrained deformations from the nodal equilibrium of the dependent
 * coordinates, then the loads of supports and drives (THEORY 8): with y the nodal force
 * of the elastic stresses and w = D_c^-T y(c), sigma = sigma_el - w on the rows of D_c
 * (with `free_dynamic`, a simulation's state, only on the rigid and input rows: w vanishes
 * on the dynamic ones, whose stress is the elastic law); the load on a fixed or input
 * coordinate is y - D_x^T w there; `driving` is F_q^T y on every entry of q. */
void fm_equilibrium(const FmModel *m, FmState *s, int free_dynamic, double *reactions,
                    double *driving)
{
    double *w = s->w, *pulled = s->w5;
    fm_reduced_residual(m, s, NULL);
    fm_jacobian_t_times(m, s->J, w, pulled);
    for (int i = 0; i < m->nr; i++)
        if (!free_dynamic || m->mult_of_def[m->rows[i]] >= 0)
            s->sigma[m->rows[i]] -= w[m->rows[i]];
    if (reactions) {
        memset(reactions, 0, sizeof(double) * m->nx);
        for (int k = 0; k < m->nsupported; k++) {
            const int i = m->supported[k];
            reactions[i] = s->y[i] - pulled[i];
        }
    }
    if (driving) {
        for (int k = 0; k < m->nxm; k++)
            driving[k] = s->y[m->q_coord[k]] - pulled[m->q_coord[k]];
        for (int k = 0; k < m->nq - m->nxm; k++)
            driving[m->nxm + k] = w[m->q_def[k]];
    }
}
