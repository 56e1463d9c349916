/* A compiled model and its runs: the core's workspace (see runs.h).
 *
 * The binding hands a model over field by field (FIELDS below, by name, checked against
 * flexmbd/engine/spec.py's declaration of their lengths), then fm_core_init locates the
 * entries of the two square systems in their bands and evaluates the reference terms.
 * Runs and single evaluations follow; every failure is an FmStatus with its details in
 * c->error, and the state it happened at in c->failed.
 */
#include <math.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "runs.h"

#ifndef FLEXMBD_BUILD
#define FLEXMBD_BUILD "C"
#endif
#ifndef FLEXMBD_BINDING
#define FLEXMBD_BINDING "Cython"
#endif

const char *const FM_OUTPUT_NAMES[FM_N_OUT] = {"x", "xd", "xdd", "e", "ed", "edd", "q", "qd",
                                               "qdd", "sigma", "reactions", "driving"};

/* --- the model's fields ------------------------------------------------------------------- */
typedef struct {
    const char *name;
    char type;                     /* 'n' a size (int), 'i' int32 array, 'd' float64 array */
    size_t at;                     /* offset in FmCore */
} Field;

#define MODEL(f) offsetof(FmCore, m.f)
#define CORE(f) offsetof(FmCore, f)
static const Field FIELDS[] = {
    /* sizes */
    {"nx", 'n', MODEL(nx)}, {"ne", 'n', MODEL(ne)}, {"nel", 'n', MODEL(nel)},
    {"nq", 'n', MODEL(nq)}, {"nxm", 'n', MODEL(nxm)}, {"nr", 'n', MODEL(nr)},
    {"nrigid", 'n', MODEL(nrigid)}, {"nfree", 'n', MODEL(nfree)}, {"nmult", 'n', MODEL(nmult)},
    {"nd_dyn", 'n', MODEL(nd_dyn)}, {"ndc", 'n', MODEL(ndc)}, {"total_j", 'n', MODEL(total_j)},
    {"total_b", 'n', MODEL(total_b)}, {"nfixed", 'n', MODEL(nfixed)},
    {"nsupported", 'n', MODEL(nsupported)}, {"nrot", 'n', MODEL(nrot)},
    {"ndc_map", 'n', MODEL(ndc_map)}, {"nsd_a", 'n', MODEL(nsd_a)},
    {"nsd_m", 'n', MODEL(nsd_m)}, {"nsd_c", 'n', MODEL(nsd_c)},
    /* elements */
    {"etype", 'i', MODEL(etype)}, {"c_off", 'i', MODEL(c_off)}, {"c_idx", 'i', MODEL(c_idx)},
    {"d_off", 'i', MODEL(d_off)}, {"d_idx", 'i', MODEL(d_idx)}, {"p_off", 'i', MODEL(p_off)},
    {"j_off", 'i', MODEL(j_off)}, {"b_off", 'i', MODEL(b_off)},
    {"law_off", 'i', MODEL(law_off)}, {"param", 'd', MODEL(param)},
    {"emass", 'd', MODEL(emass)}, {"consistent", 'i', CORE(consistent)},
    {"lumped_diag", 'd', CORE(lumped_diag)}, {"S", 'd', MODEL(S)}, {"C", 'd', MODEL(C)},
    {"elastic", 'i', MODEL(elastic)}, {"sigma0", 'd', MODEL(sigma0)},
    /* classification */
    {"fixed", 'i', MODEL(fixed)}, {"x_fixed", 'd', MODEL(x_fixed)},
    {"q_coord", 'i', MODEL(q_coord)}, {"q_def", 'i', MODEL(q_def)},
    {"q_input", 'i', MODEL(q_input)}, {"q_dyn", 'i', MODEL(q_dyn)}, {"rows", 'i', MODEL(rows)},
    {"row_of_def", 'i', MODEL(row_of_def)}, {"dep", 'i', MODEL(dep)},
    {"free_of", 'i', MODEL(free_of)}, {"dyn_coord", 'i', MODEL(dyn_coord)},
    {"dyn_def", 'i', MODEL(dyn_def)}, {"supported", 'i', MODEL(supported)},
    {"elastic_def", 'i', MODEL(elastic_def)}, {"periodic", 'i', MODEL(periodic)},
    {"rotations", 'i', MODEL(rot)}, {"mult_of_def", 'i', MODEL(mult_of_def)},
    /* masses and loads */
    {"nodal_mass", 'd', MODEL(nodal_mass)}, {"f_const", 'd', MODEL(f_const)},
    {"gravity", 'd', CORE(gravity)},
    /* reference */
    {"x0", 'd', CORE(x0)}, {"coord_scale", 'd', CORE(coord_scale)},
    {"coord_size", 'd', MODEL(coord_size)},
    /* the square systems' entries and orderings */
    {"dc_src", 'i', MODEL(dc_src)}, {"dc_row", 'i', CORE(dc_row)},
    {"dc_col", 'i', CORE(dc_col)}, {"dc_rowband", 'i', MODEL(dc_rowband)},
    {"dc_colband", 'i', MODEL(dc_colband)}, {"dc_colscale", 'd', MODEL(dc_colscale)},
    {"sd_band", 'i', MODEL(sd_band)}, {"sd_a_src", 'i', MODEL(sd_a_src)},
    {"sd_a_u", 'i', CORE(sd_a_u)}, {"sd_a_v", 'i', CORE(sd_a_v)},
    {"sd_m_coord", 'i', MODEL(sd_m_coord)}, {"sd_m_u", 'i', CORE(sd_m_u)},
    {"sd_c_src", 'i', MODEL(sd_c_src)}, {"sd_c_u", 'i', CORE(sd_c_u)},
    {"sd_c_v", 'i', CORE(sd_c_v)},
};
#define N_FIELDS ((int)(sizeof(FIELDS) / sizeof(FIELDS[0])))

int fm_fields(void) { return N_FIELDS; }
const char *fm_field_name(int k) { return k >= 0 && k < N_FIELDS ? FIELDS[k].name : NULL; }
char fm_field_type(int k) { return k >= 0 && k < N_FIELDS ? FIELDS[k].type : '\0'; }

int fm_core_set(FmCore *c, int k, const void *data, long n)
{
    if (k < 0 || k >= N_FIELDS)
        return FM_NO_MEMORY;
    char *at = (char *)c + FIELDS[k].at;
    if (FIELDS[k].type == 'n') {
        *(int *)at = (int)n;
        return FM_OK;
    }
    void **field = (void **)at;
    const size_t bytes = (size_t)(n > 0 ? n : 0) * (FIELDS[k].type == 'd' ? sizeof(double)
                                                                          : sizeof(int));
    free(*field);
    if (!(*field = malloc(bytes ? bytes : 1)))
        return FM_NO_MEMORY;
    if (bytes)
        memcpy(*field, data, bytes);
    return FM_OK;
}

/* --- compiling: the square systems' entries in their bands ------------------------------ */
/* position of (row, col) in band storage with kl, ku (band.c's layout) */
static int band_at(int row, int col, int kl, int ku)
{
    return kl + ku + row - col + col * (2 * kl + ku + 1);
}

/* The band positions of D_c's entries (rows and columns through their band orderings) and
 * of the saddle-point matrix's (symmetric structure: kl = ku), with the bands they need. */
static int *place(int n, const int *src_u, const int *src_v, const int *band_u,
                  const int *band_v, int kl, int ku)
{
    int *dst = malloc(sizeof(int) * (n ? n : 1));
    for (int k = 0; dst && k < n; k++)
        dst[k] = band_at(band_u[src_u[k]], band_v[src_v[k]], kl, ku);
    return dst;
}

static int build_maps(FmModel *m, const int *dc_row, const int *dc_col, const int *sa_u,
                      const int *sa_v, const int *sm_u, const int *sc_u, const int *sc_v)
{
    const int ndc = m->ndc_map, nsa = m->nsd_a;
    int kl = 0, ku = 0, bw = 0;
    for (int k = 0; k < ndc; k++) {
        const int d = m->dc_rowband[dc_row[k]] - m->dc_colband[dc_col[k]];
        kl = d > kl ? d : kl;
        ku = -d > ku ? -d : ku;
    }
    for (int k = 0; k < nsa + m->nsd_c; k++) {
        const int d = k < nsa ? abs(m->sd_band[sa_u[k]] - m->sd_band[sa_v[k]])
                              : abs(m->sd_band[sc_u[k - nsa]] - m->sd_band[sc_v[k - nsa]]);
        bw = d > bw ? d : bw;
    }
    m->dc_kl = kl;
    m->dc_ku = ku;
    m->sd_kl = m->sd_ku = bw;
    m->dc_dst = place(ndc, dc_row, dc_col, m->dc_rowband, m->dc_colband, kl, ku);
    m->sd_a_dst = place(nsa, sa_u, sa_v, m->sd_band, m->sd_band, bw, bw);
    m->sd_m_dst = place(m->nsd_m, sm_u, sm_u, m->sd_band, m->sd_band, bw, bw);
    m->sd_c_dst = place(m->nsd_c, sc_u, sc_v, m->sd_band, m->sd_band, bw, bw);
    m->sd_c_dstt = place(m->nsd_c, sc_v, sc_u, m->sd_band, m->sd_band, bw, bw);
    m->dc_w = malloc(sizeof(double) * (ndc ? ndc : 1));
    return m->dc_dst && m->sd_a_dst && m->sd_m_dst && m->sd_c_dst && m->sd_c_dstt && m->dc_w
           ? 0 : -1;
}

/* The constant element masses and their weight, and the row scales of D_c from the norms
 * of the D_x rows (angles scaled by the model size) in the reference configuration. */
static void reference_terms(FmCore *c)
{
    FmModel *m = &c->m;
    double cc[FM_MAX_NC], out[FM_MAX_NC * (FM_MAX_NC + 1)];  /* nd <= nc */
    for (int k = 0; k < m->nel; k++) {
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        const int nc = kern->nc, *ci = m->c_idx + m->c_off[k];
        const double *p = m->param + m->p_off[k];
        double *M = m->mconst + m->b_off[k];
        for (int a = 0; a < nc; a++) {
            M[a * nc + a] = c->lumped_diag[m->c_off[k] + a];
            cc[a] = c->x0[ci[a]];
        }
        if (c->consistent[k] && kern->mass && !kern->mass_constant)
            m->varying[k] = 1;
        else if (c->consistent[k] && kern->mass) {
            kern->mass(cc, p, out);
            for (int a = 0; a < nc * nc; a++)
                M[a] += m->emass[k] * out[a];
            if (m->gravity_on && kern->gravity) {   /* rotary inertia has no weight */
                kern->gravity(cc, p, m->gravity, out);
                for (int a = 0; a < nc; a++)
                    m->f_const[ci[a]] += m->emass[k] * out[a];
            }
        }
        kern->deform_jac(cc, p, out);
        for (int i = 0; i < kern->nd; i++) {
            const int row = m->row_of_def[m->d_idx[m->d_off[k] + i]];
            if (row < 0)
                continue;
            double sum = 0.0;
            for (int a = 0; a < nc; a++) {
                const double v = out[kern->nd + i * nc + a] * c->coord_scale[ci[a]];
                sum += v * v;
            }
            m->dc_rowscale[row] = 1.0 / (sqrt(sum) > 1e-300 ? sqrt(sum) : 1e-300);
        }
    }
}


int fm_core_init(FmCore *c)
{
    FmModel *m = &c->m;
    m->ns = m->nfree + m->nmult;
    memcpy(m->gravity, c->gravity, sizeof(m->gravity));
    m->gravity_on = m->gravity[0] != 0.0 || m->gravity[1] != 0.0 || m->gravity[2] != 0.0;
    /* the position solve's settings are the binding's (flexmbd's defaults are in Python):
     * until it gives them, every solve fails */
    m->tolerance = NAN;
    m->max_iterations = 0;
    m->reference_conditioning = 1.0;
    m->varying = calloc(m->nel ? m->nel : 1, sizeof(int));
    m->mconst = calloc(m->total_b ? m->total_b : 1, sizeof(double));
    m->dc_rowscale = malloc(sizeof(double) * (m->nr ? m->nr : 1));
    const int nq = m->nq > 0 ? m->nq : 1, nx = m->nx > 0 ? m->nx : 1;
    double **vectors[] = {&c->last_x, &c->last_xd, &c->last_xdd, &c->guess, &c->start,
                          &c->found, &c->last_q, &c->last_qd, &c->last_qdd, &c->path};
    int missing = 0;
    for (int k = 0; k < 10; k++)
        missing |= !(*vectors[k] = calloc(k < 6 ? nx : k < 9 ? nq : 2 * nq, sizeof(double)));
    c->op_J = calloc(m->total_j > 0 ? m->total_j : 1, sizeof(double));
    c->law_kind = calloc(nq, sizeof(int));
    c->law_coef = calloc(3 * nq, sizeof(double));
    if (build_maps(m, c->dc_row, c->dc_col, c->sd_a_u, c->sd_a_v, c->sd_m_u, c->sd_c_u,
                   c->sd_c_v)
        || !m->varying || !m->mconst || !m->dc_rowscale || !c->op_J || !c->law_kind
        || !c->law_coef || missing || fm_state_init(&c->eval, m) || fm_state_init(&c->out, m)
        || band_init(&c->sd, m->ns, m->sd_kl, m->sd_ku)
        || band_init(&c->sd_acc, m->ns, m->sd_kl, m->sd_ku) || fm_state_init(&c->stat, m)
        || band_init(&c->sd_static, m->ns, m->sd_kl, m->sd_ku))
        return FM_NO_MEMORY;          /* fm_core_free takes back what was allocated */
    reference_terms(c);
    for (int k = 0; k < m->ndc_map; k++)
        m->dc_w[k] = m->dc_rowscale[c->dc_row[k]] * m->dc_colscale[c->dc_col[k]];
    memcpy(c->eval.x, c->x0, sizeof(double) * m->nx);
    memcpy(c->start, c->x0, sizeof(double) * m->nx);
    int **temporary[] = {&c->dc_row, &c->dc_col, &c->sd_a_u, &c->sd_a_v, &c->sd_m_u,
                         &c->sd_c_u, &c->sd_c_v};
    for (size_t k = 0; k < sizeof(temporary) / sizeof(temporary[0]); k++) {
        free(*temporary[k]);
        *temporary[k] = NULL;
    }
    c->ready = 1;
    return FM_OK;
}

void fm_core_free(FmCore *c)
{
    FmModel *m = &c->m;
    for (int k = 0; k < N_FIELDS; k++)  /* every array handed over, even before init */
        if (FIELDS[k].type != 'n') {
            void **field = (void **)((char *)c + FIELDS[k].at);
            free(*field);
            *field = NULL;
        }
    void *all[] = {m->varying, m->mconst, m->dc_dst, m->dc_w, m->dc_rowscale, m->sd_a_dst,
                   m->sd_c_dst, m->sd_c_dstt, m->sd_m_dst, c->op_J, c->law_kind, c->law_coef,
                   c->last_x, c->last_xd, c->last_xdd, c->last_q, c->last_qd, c->last_qdd,
                   c->guess, c->start, c->path, c->found};
    for (size_t k = 0; k < sizeof(all) / sizeof(all[0]); k++)
        free(all[k]);
    fm_state_free(&c->eval);
    fm_state_free(&c->out);
    band_free(&c->sd);
    band_free(&c->sd_acc);
    fm_state_free(&c->stat);
    band_free(&c->sd_static);
    memset(c, 0, sizeof(*c));
}

int fm_output_size(const FmCore *c, int output)
{
    const FmModel *m = &c->m;
    const int sizes[FM_N_OUT] = {m->nx, m->nx, m->nx, m->ne, m->ne, m->ne, m->nq, m->nq, m->nq,
                                 m->ne, m->nx, m->nq};
    return output >= 0 && output < FM_N_OUT ? sizes[output] : 0;
}

void fm_reset_error(FmCore *c)
{
    memset(&c->error, 0, sizeof(c->error));
    c->error.worst = -1;
    c->error.conditioning = c->error.limit = c->error.time = NAN;
}

/* --- laws, loads, progress ----------------------------------------------------------------- */
/* q, qd and qdd of a state at time t from the laws; the integrated entries from (q_d, qd_d,
 * qdd_d) when given (qdd_d NULL: zero). */
static int compose(FmCore *c, FmState *s, double t, const double *q_d, const double *qd_d,
                   const double *qdd_d)
{
    const FmModel *m = &c->m;
    if (c->laws && c->laws(c->context, t))
        return FM_PYTHON;
    for (int j = 0, d = 0; j < m->nq; j++) {
        const double *k = c->law_kind[j] == FM_LAW_CALLBACK ? c->law_values + 3 * j
                                                              : c->law_coef + 3 * j;
        if (c->law_kind[j] == FM_LAW_INTEGRATED) {
            s->q[j] = q_d[d];
            s->qd[j] = qd_d[d];
            s->qdd[j] = qdd_d ? qdd_d[d] : 0.0;
            d++;
        } else if (c->law_kind[j] == FM_LAW_CALLBACK) {
            s->q[j] = k[0];
            s->qd[j] = k[1];
            s->qdd[j] = k[2];
        } else {
            s->q[j] = k[0] + k[1] * t + 0.5 * k[2] * t * t;
            s->qd[j] = k[1] + k[2] * t;
            s->qdd[j] = k[2];
        }
        if (!isfinite(s->q[j]) || !isfinite(s->qd[j]) || !isfinite(s->qdd[j])) {
            c->error.code = FM_NOT_FINITE;
            c->error.time = t;
            c->error.worst = j;
            return FM_NOT_FINITE;
        }
    }
    return FM_OK;
}

/* The applied loads of the binding's callback at the state, or NULL without one. */
static int user_loads(FmCore *c, FmState *s, const double **loads)
{
    *loads = NULL;
    if (!c->loads)
        return FM_OK;
    memcpy(c->force_x, s->x, sizeof(double) * c->m.nx);
    memcpy(c->force_xd, s->xd, sizeof(double) * c->m.nx);
    if (c->loads(c->context, s->t))
        return FM_PYTHON;
    for (int i = 0; i < c->m.nx; i++)
        if (!isfinite(c->force_f[i])) {
            c->error.code = FM_NOT_FINITE;
            c->error.time = s->t;
            c->error.worst = -2 - i;         /* -2 - coordinate: a load that is not finite */
            return FM_NOT_FINITE;
        }
    *loads = c->force_f;
    return FM_OK;
}

/* The progress callback (which also lets Ctrl-C through). */
static int report(void *context, double t)
{
    FmCore *c = context;
    return c->progress && c->progress(c->context, t) ? FM_PYTHON : FM_OK;
}

/* --- outputs ---------------------------------------------------------------------------------- */
/* Row k of the output arrays `outs` (NULL: not kept) from a state (reactions and driving
 * loads are written in place by forces_of). */
static void store(const FmCore *c, double *const outs[FM_N_OUT], int k, FmState *s)
{
    const double *rows[FM_N_OUT] = {s->x, s->xd, s->xdd, s->e, s->ed, s->edd, s->q, s->qd,
                                    s->qdd, s->sigma, NULL, NULL};
    for (int o = 0; o < FM_N_OUT; o++)
        if (outs[o] && rows[o]) {
            const size_t size = (size_t)fm_output_size(c, o);
            memcpy(outs[o] + (size_t)k * size, rows[o], sizeof(double) * size);
        }
}

/* Stresses of every deformation, reactions and driving loads of a state (THEORY 8) with
 * the applied `loads` (nx, or NULL) besides the constant ones, its dynamic accelerations
 * solved first (`solve`); with `free_dynamic` (a simulation) the dynamic entries move
 * freely, so their driving load is zero. Stores row k of `outs`. */
static int forces_of(FmCore *c, FmState *s, const double *loads, double *const outs[FM_N_OUT],
                     int k, int free_dynamic, int solve)
{
    const FmModel *m = &c->m;
    int code;
    if (solve) {
        if ((code = fm_accelerations(m, s, &c->sd_acc, loads, &c->error)))
            return code;
    } else {
        fm_stresses(m, s);
        fm_inertia(m, s);
        fm_nodal_force(m, s, loads);
    }
    double *r = outs[FM_OUT_REACTIONS], *drive = outs[FM_OUT_DRIVING];
    r = r ? r + (size_t)k * m->nx : NULL;
    drive = drive ? drive + (size_t)k * m->nq : NULL;
    fm_equilibrium(m, s, free_dynamic, r, drive);
    for (int n = 0; r && n < m->nrot; n++) {   /* a rotational node's reaction is a moment */
        const int *at = m->rot + 4 * n;
        double lam[4], force[4], moment[3];
        for (int a = 0; a < 4; a++) {
            lam[a] = s->x[at[a]];
            force[a] = r[at[a]];
        }
        fm_moment_of(lam, force, moment);
        r[at[0]] = 0.0;
        for (int a = 0; a < 3; a++)
            r[at[a + 1]] = moment[a];
    }
    if (drive && free_dynamic)
        for (int j = 0; j < m->nd_dyn; j++)
            drive[m->q_dyn[j]] = 0.0;
    store(c, outs, k, s);
    return FM_OK;
}

/* forces_of with the loads of the run's callback, into the run's output k. */
static int dynamics_of(FmCore *c, FmState *s, int k, int free_dynamic, int solve)
{
    const double *loads;
    const int code = user_loads(c, s, &loads);
    return code ? code : forces_of(c, s, loads, c->outs, k, free_dynamic, solve);
}


/* --- the kinematic and inverse runs ---------------------------------------------------------- */
/* Largest move of one coordinate the first-order predictor may make between two position
 * solves: an angle in rad, a translation relative to the model's size. From farther away
 * Newton can converge to another solution (a rod angle 2 pi off, a mirrored linkage), and
 * the answer would depend on the output grid the user asked for. */
#define MAX_PREDICTED_MOVE 0.1
#define MAX_INTERNAL_STEPS 1000000

/* The state at t of the run's laws, its positions solved from the run's start (`first`) or
 * from the solution in `s` by the first-order predictor x + F_q dq (THEORY 3). */
static int solve_at(FmCore *c, FmState *s, double t, int first)
{
    const FmModel *m = &c->m;
    int code = compose(c, s, t, NULL, NULL, NULL);
    if (code)
        return code;
    for (int i = 0; i < m->nx; i++)
        c->guess[i] = first ? c->start[i] : s->x[i] + (t - s->t) * s->xd[i];
    return fm_kinematics(m, s, t, c->guess, m->tolerance, 0, 1, &c->error);
}

/* Internal position solves from the solution `s` at t0 towards t, where the predictor would
 * move a coordinate by more than MAX_PREDICTED_MOVE; `s` ends at the last of them. */
static int approach(FmCore *c, FmState *s, double t0, double t)
{
    const FmModel *m = &c->m;
    double move = 0.0;
    for (int i = 0; i < m->nx; i++) {
        const double step = fabs((t - t0) * s->xd[i]) / c->m.coord_size[i];
        move = step > move ? step : move;
    }
    if (!(move > MAX_PREDICTED_MOVE))
        return isfinite(move) ? FM_OK : FM_NOT_FINITE;
    const double wanted = ceil(move / MAX_PREDICTED_MOVE);
    const int steps = wanted < MAX_INTERNAL_STEPS ? (int)wanted : MAX_INTERNAL_STEPS;
    for (int j = 1; j < steps; j++) {
        const int code = solve_at(c, s, t0 + (t - t0) * j / steps, 0);
        if (code)
            return code;
    }
    return FM_OK;
}


/* --- the mechanical system for generalized-alpha --------------------------------------------- */
static void remember(FmCore *c, const FmState *s, int zero_xdd)
{
    const FmModel *m = &c->m;
    c->have_last = 1;
    c->last_t = s->t;
    memcpy(c->last_x, s->x, sizeof(double) * m->nx);
    memcpy(c->last_xd, s->xd, sizeof(double) * m->nx);
    if (zero_xdd)
        memset(c->last_xdd, 0, sizeof(double) * m->nx);
    else
        memcpy(c->last_xdd, s->xdd, sizeof(double) * m->nx);
    memcpy(c->last_q, s->q, sizeof(double) * m->nq);
    memcpy(c->last_qd, s->qd, sizeof(double) * m->nq);
    memcpy(c->last_qdd, s->qdd, sizeof(double) * m->nq);
}

/* Start of the position solve: the last solution extrapolated to t to second order, plus
 * F_q times what that extrapolation misses of q (THEORY 3's predictor): the motion of the
 * dynamic entries is not smooth in time when stiff modes ring. */
static void predict(FmCore *c, FmState *s, double t)
{
    const FmModel *m = &c->m;
    if (!c->have_last) {
        memcpy(c->guess, c->start, sizeof(double) * m->nx);
        return;
    }
    const double dt = t - c->last_t;
    double *change = c->out.w6, *missed = c->out.w5;  /* scratch of the other state */
    memset(change, 0, sizeof(double) * m->nx);
    for (int j = 0; j < m->nq; j++)
        missed[j] = s->q[j] - (c->last_q[j] + dt * c->last_qd[j] + 0.5 * dt * dt * c->last_qdd[j]);
    for (int k = 0; k < m->nxm; k++)
        change[m->q_coord[k]] = missed[k];
    fm_dependent_rates(m, &c->eval, change, missed + m->nxm, NULL);
    for (int i = 0; i < m->nx; i++)
        c->guess[i] = c->last_x[i] + dt * c->last_xd[i] + 0.5 * dt * dt * c->last_xdd[i]
                      + change[i];
}

/* Near redundant constraints (D_c nearly singular: a parallelogram whose bars align) two
 * branches of solutions cross, as close to each other as the configuration is to the
 * crossing. A solution from a predicted guess that is farther off than that may lie on
 * either, and the velocities of the other branch differ from the motion's by as much as
 * the motion itself: a solution whose dependent velocities are off the last ones continued
 * to its time by more than OFF_BRANCH of their size has left the branch of the motion. */
#define OFF_BRANCH 0.5
#define SAME_SOLUTION 1e3      /* two solutions this many tolerances apart are one */
static int off_branch(FmCore *c, FmState *s)
{
    const FmModel *m = &c->m;
    if (!c->have_last || !m->nr)
        return 0;
    const double dt = s->t - c->last_t;
    double gap = 0.0, speed = 0.0;
    for (int j = 0; j < m->nr; j++) {
        const int i = m->dep[j];
        const double continued = c->last_xd[i] + dt * c->last_xdd[i];
        const double off = fabs(s->xd[i] - continued) / c->m.coord_size[i];
        const double size = fabs(continued) / c->m.coord_size[i];
        gap = off > gap ? off : gap;
        speed = size > speed ? size : speed;
    }
    return gap > OFF_BRANCH * speed;
}

/* The state of `s` at t (integrated entries q_d, qd_d, qdd_d) solved again by continuation
 * from the last solution along the straight path in q to it, in `steps` exact solves each
 * from the one before by the path's tangent: close steps keep the branch the last solution
 * lies on, whose tangent leads through the crossing. */
static int along_path(FmCore *c, FmState *s, double t, const double *q_d, const double *qd_d,
                      const double *qdd_d, int steps)
{
    const FmModel *m = &c->m;
    const double span = t - c->last_t;
    double *at = c->path, *rate = c->path + m->nq;
    int code;
    if (!(span != 0.0))
        return FM_OK;
    for (int j = 0; j < m->nd_dyn; j++)
        rate[j] = (q_d[j] - c->last_q[m->q_dyn[j]]) / span;
    memcpy(s->x, c->last_x, sizeof(double) * m->nx);
    memcpy(s->xd, c->last_xd, sizeof(double) * m->nx);
    s->t = c->last_t;
    for (int k = 1; k <= steps; k++) {
        const double tk = k < steps ? c->last_t + span * k / steps : t;
        for (int j = 0; j < m->nd_dyn; j++)
            at[j] = c->last_q[m->q_dyn[j]] + rate[j] * (tk - c->last_t);
        if ((code = compose(c, s, tk, k < steps ? at : q_d, k < steps ? rate : qd_d,
                            k < steps ? NULL : qdd_d)))
            return code;
        for (int i = 0; i < m->nx; i++)
            c->guess[i] = s->x[i] + (tk - s->t) * s->xd[i];
        if ((code = fm_kinematics(m, s, tk, c->guess, m->tolerance, 0, 1, &c->error)))
            return code;
    }
    return FM_OK;
}

/* Keep the solution in `s` on the branch of the motion (see off_branch): when it seems to
 * have left it, solve it again along the path from the last solution in ever closer steps,
 * until two agree (the velocities may simply have changed fast). A path that cannot be
 * followed leaves the solution as it was found. */
static int keep_branch(FmCore *c, FmState *s, double t, const double *q_d, const double *qd_d,
                       const double *qdd_d)
{
    const FmModel *m = &c->m;
    int code = FM_OK;
    for (int steps = 8; steps <= 512 && off_branch(c, s); steps *= 8) {
        memcpy(c->found, s->x, sizeof(double) * m->nx);
        if ((code = along_path(c, s, t, q_d, qd_d, qdd_d, steps))) {
            if (code != FM_PYTHON && !(code = compose(c, s, t, q_d, qd_d, qdd_d)))
                code = fm_kinematics(m, s, t, c->found, m->tolerance, 0, 1, &c->error);
            break;
        }
        double change = 0.0;
        for (int i = 0; i < m->nx; i++) {
            const double d = fabs(s->x[i] - c->found[i]);
            change = d > change ? d : change;
        }
        if (change <= SAME_SOLUTION * m->tolerance)
            break;
    }
    return code;
}

static int mech_accelerations(void *context, double t, const double *q, const double *v,
                              double *a)
{
    FmCore *c = context;
    FmState *s = &c->eval;
    const double *loads;
    int code;
    c->nfev++;
    c->failed = s;
    if ((code = compose(c, s, t, q, v, NULL)))
        return code;
    predict(c, s, t);
    if ((code = fm_kinematics(&c->m, s, t, c->guess, c->near, 0, 0, &c->error))
        || (code = keep_branch(c, s, t, q, v, NULL))
        || (code = user_loads(c, s, &loads)))
        return code;
    remember(c, s, 1);                       /* xdd lacks qdd_d until the accelerations */
    if ((code = fm_accelerations(&c->m, s, &c->sd_acc, loads, &c->error)))
        return code;
    memcpy(c->last_xdd, s->xdd, sizeof(double) * c->m.nx);
    memcpy(c->last_qdd, s->qdd, sizeof(double) * c->m.nq);
    for (int j = 0; j < c->m.nd_dyn; j++)
        a[j] = s->qdd[c->m.q_dyn[j]];
    return FM_OK;
}

static int mech_residual(void *context, double t, const double *q, const double *v,
                         const double *a, double *r)
{
    FmCore *c = context;
    FmState *s = &c->eval;
    const double *loads;
    int code;
    c->nfev++;
    c->failed = s;
    if ((code = compose(c, s, t, q, v, a)))
        return code;
    predict(c, s, t);
    if ((code = fm_kinematics(&c->m, s, t, c->guess, c->near, 0, 0, &c->error))
        || (code = keep_branch(c, s, t, q, v, a))) {
        c->trial = code != FM_PYTHON;        /* a smaller step may get past it */
        return code;
    }
    remember(c, s, 0);
    if ((code = user_loads(c, s, &loads)))
        return code;
    fm_stresses(&c->m, s);
    fm_inertia(&c->m, s);
    fm_nodal_force(&c->m, s, loads);
    fm_reduced_residual(&c->m, s, r);
    return FM_OK;
}

static int mech_renew(void *context, double c_q, double c_v)
{
    FmCore *c = context;
    memcpy(c->op_J, c->eval.J, sizeof(double) * c->m.total_j);
    return fm_saddle(&c->m, &c->eval, &c->sd, c_q, c_v, &c->error);
}

static int mech_apply(void *context, const double *r, double *da)
{
    FmCore *c = context;
    fm_saddle_apply(&c->m, &c->eval, &c->sd, c->op_J, r, da);
    for (int j = 0; j < c->m.nd_dyn; j++)
        if (!isfinite(da[j]))
            return FM_MASSLESS;
    return FM_OK;
}

/* The state at output k from the integrated (q_d, qd_d), as far as the run's outputs
 * need it: positions from the last evaluation's solution by chord steps with its D_c;
 * for rates, D_c at the solution and the velocities; for all, the accelerations,
 * stresses and reactions. */
static int mech_output(void *context, int k, double t, const double *q, const double *v,
                       const double *a)
{
    FmCore *c = context;
    FmState *s = &c->out;
    int code;
    (void)a;
    c->failed = s;
    fm_state_copy(s, &c->eval, &c->m);
    if ((code = compose(c, s, t, q, v, NULL)))
        return code;
    /* from the last evaluation extrapolated to t (before any, the run's start): near a
     * configuration where branches of solutions meet, only a prediction this close keeps
     * the output on the branch the integration follows */
    predict(c, s, t);
    const int factored = c->have_last && c->eval.has_factor;
    code = c->level ? fm_kinematics(&c->m, s, t, c->guess, c->m.tolerance, factored, 0,
                                    &c->error)
                    : fm_positions(&c->m, s, t, c->guess, c->m.tolerance, factored, -1,
                                   &c->error);
    if (!code && c->level)
        code = keep_branch(c, s, t, q, v, NULL);
    if (code || c->level < 2) {
        if (!code)
            store(c, c->outs, k, s);
        return code;
    }
    return dynamics_of(c, s, k, 1, 1);
}

/* A free rotation (three dynamic Euler parameters) whose calculable one has dropped below
 * PARTITION_LIMIT in magnitude (the sum of the dynamic ones' squares above 1 - limit^2):
 * its D_c turns singular at 0, so the run stops for another partition. */
#define PARTITION_LIMIT 0.5
static int mech_leave(void *context, double t, const double *q)
{
    FmCore *c = context;
    for (int r = 0; r < c->n_watch; r++) {
        const int *w = c->watch + 3 * r;
        const double squares = q[w[0]] * q[w[0]] + q[w[1]] * q[w[1]] + q[w[2]] * q[w[2]];
        if (squares > 1.0 - PARTITION_LIMIT * PARTITION_LIMIT) {
            c->error.code = FM_PARTITION;
            c->error.time = t;
            return 1;
        }
    }
    return 0;
}

static AlphaSystem mechanical(FmCore *c)
{
    AlphaSystem sys = {.m = c->m.nd_dyn, .context = c, .accelerations = mech_accelerations,
                       .residual = mech_residual, .renew = mech_renew, .apply = mech_apply,
                       .output = mech_output, .leave = c->n_watch ? mech_leave : NULL,
                       .error = &c->error, .trial = &c->trial};
    return sys;
}

/* --- a run --------------------------------------------------------------------------------- */
void fm_core_prepare(FmCore *c, const int *law_kind, const double *law_coef,
                     double *const outs[FM_N_OUT], int n_outputs, int dynamics)
{
    memcpy(c->law_kind, law_kind, sizeof(int) * c->m.nq);
    memcpy(c->law_coef, law_coef, sizeof(double) * 3 * c->m.nq);
    memcpy(c->outs, outs, sizeof(c->outs));
    c->n_outputs = n_outputs;
    c->dynamics = dynamics;
    c->level = 0;
    for (int o = 0; o < FM_N_OUT; o++)
        if (c->outs[o] && o != FM_OUT_X && o != FM_OUT_E && o != FM_OUT_Q) {
            const int rates = o == FM_OUT_XD || o == FM_OUT_ED || o == FM_OUT_QD;
            c->level = rates && c->level < 2 ? 1 : 2;
        }
    c->have_last = 0;
}

void fm_core_reset(FmCore *c, const double *start)
{
    memcpy(c->start, start ? start : c->x0, sizeof(double) * c->m.nx);
    c->have_last = 0;
    c->nfev = 0;
}

int fm_core_kinematic_run(FmCore *c, const double *times, int n, int *reached)
{
    FmState *s = &c->eval;
    int code = FM_OK, k;
    fm_reset_error(c);
    c->failed = s;
    for (k = 0; k < n && !code; k++) {
        const double t = times[k];
        if (k && (code = approach(c, s, times[k - 1], t)))
            break;
        if ((code = solve_at(c, s, t, k == 0)))
            break;
        if (c->dynamics)
            code = dynamics_of(c, s, k, 0, 0);
        else
            store(c, c->outs, k, s);
        if (!code && (k + 1) % 256 == 0)
            code = report(c, t);
        if (code)
            break;
    }
    if (!code)
        code = report(c, n ? times[n - 1] : 0.0);
    *reached = k;
    return code;
}

AlphaResult fm_core_alpha_run(FmCore *c, const double *times, int n, const double *q0,
                              const double *v0, AlphaOptions *options)
{
    fm_reset_error(c);
    c->have_last = 0;
    c->nfev = 0;
    AlphaSystem sys = mechanical(c);
    options->progress = report;
    options->progress_context = c;
    AlphaResult result = alpha_run(&sys, times, n, q0, v0, options);
    result.nfev = c->nfev;
    return result;
}

/* --- single evaluations -------------------------------------------------------------------- */
int fm_core_accelerations(FmCore *c, double t, const double *y, double *out)
{
    fm_reset_error(c);
    return mech_accelerations(c, t, y, y + c->m.nd_dyn, out);
}

int fm_core_residual(FmCore *c, double t, const double *y, const double *a, double *r)
{
    fm_reset_error(c);
    return mech_residual(c, t, y, y + c->m.nd_dyn, a, r);
}

int fm_core_correction(FmCore *c, double c_q, double c_v, const double *r, double *da)
{
    fm_reset_error(c);
    const int code = mech_renew(c, c_q, c_v);
    return code ? code : mech_apply(c, r, da);
}

int fm_core_output(FmCore *c, int k, double t, const double *y)
{
    fm_reset_error(c);
    return mech_output(c, k, t, y, y + c->m.nd_dyn, NULL);
}

/* The kinematics of one state, exact position solve (full Newton, D_c refreshed at the
 * solution), into x, xd, xdd, e, ed, edd. */
int fm_core_state(FmCore *c, double t, const double *q, const double *qd, const double *qdd,
                  const double *guess, double *const kinematics[6])
{
    const FmModel *m = &c->m;
    FmState *s = &c->out;
    fm_reset_error(c);
    c->failed = s;
    memcpy(s->q, q, sizeof(double) * m->nq);
    memcpy(s->qd, qd, sizeof(double) * m->nq);
    memcpy(s->qdd, qdd, sizeof(double) * m->nq);
    const int code = fm_kinematics(m, s, t, guess, m->tolerance, 0, 1, &c->error);
    const double *from[6] = {s->x, s->xd, s->xdd, s->e, s->ed, s->edd};
    const int sizes[6] = {m->nx, m->nx, m->nx, m->ne, m->ne, m->ne};
    for (int k = 0; !code && k < 6; k++)
        memcpy(kinematics[k], from[k], sizeof(double) * sizes[k]);
    return code;
}

/* Inverse dynamics at one state, as a run's output at t (the static Newton iterations
 * and the linearizations): the kinematics of (q, qd, qdd) by an exact position solve from
 * `guess`, stresses, reactions and driving loads with the applied `loads` (nx) besides
 * the constant ones, into row 0 of each of `outs` that is not NULL. */
int fm_core_equilibrium(FmCore *c, double t, const double *q, const double *qd,
                        const double *qdd, const double *guess, const double *loads,
                        double *const outs[FM_N_OUT])
{
    const FmModel *m = &c->m;
    FmState *s = &c->out;
    fm_reset_error(c);
    c->failed = s;
    for (int i = 0; i < m->nx; i++)
        if (!isfinite(loads[i])) {
            c->error.time = t;
            c->error.worst = -2 - i;         /* as user_loads: a load that is not finite */
            return FM_NOT_FINITE;
        }
    memcpy(s->q, q, sizeof(double) * m->nq);
    memcpy(s->qd, qd, sizeof(double) * m->nq);
    memcpy(s->qdd, qdd, sizeof(double) * m->nq);
    const int code = fm_kinematics(m, s, t, guess, m->tolerance, 0, 1, &c->error);
    return code ? code : forces_of(c, s, loads, outs, 0, 0, 0);
}

/* The dense mass matrix M (nx x nx, row-major), the velocity-dependent inertia h and the
 * constant loads with gravity f (nx each) at (x, xd). */
void fm_core_mass_matrix(FmCore *c, const double *x, const double *xd, double *M, double *h,
                         double *f)
{
    const FmModel *m = &c->m;
    FmState *s = &c->out;
    memcpy(s->x, x, sizeof(double) * m->nx);
    memcpy(s->xd, xd, sizeof(double) * m->nx);
    fm_inertia(m, s);
    memset(M, 0, sizeof(double) * m->nx * m->nx);
    memset(h, 0, sizeof(double) * m->nx);
    memcpy(f, m->f_const, sizeof(double) * m->nx);
    for (int i = 0; i < m->nx; i++)
        M[i * m->nx + i] += m->nodal_mass[i];
    for (int k = 0; k < m->nel; k++) {
        const int nc = m->c_off[k + 1] - m->c_off[k], *ci = m->c_idx + m->c_off[k];
        for (int a = 0; a < nc; a++) {
            h[ci[a]] += s->hvec[m->c_off[k] + a];
            f[ci[a]] += s->gvec[m->c_off[k] + a];
            for (int b = 0; b < nc; b++)
                M[ci[a] * m->nx + ci[b]] += s->blocks[m->b_off[k] + a * nc + b];
        }
    }
}

int fm_core_inertia_slopes(FmCore *c, const double *x, const double *q, const double *qd,
                           const double *qdd, const double *step, int rates, double *out)
{
    fm_reset_error(c);
    c->failed = &c->out;
    return fm_inertia_slopes(&c->m, &c->out, x, q, qd, qdd, step, rates, out, &c->error);
}

double fm_core_factor(FmCore *c, const double *x)
{
    FmState *s = &c->out;
    fm_reset_error(c);
    s->cond_column = -1;                     /* a configuration of its own: estimate in full */
    return fm_factor_at(&c->m, s, x) ? 0.0 : fm_conditioning(&c->m, s);
}

/* D_c^-1 (or D_c^-T) of `count` right-hand sides (count, nr) in place, with the last
 * fm_core_factor: FM_OK, FM_SINGULAR without a factor, or FM_NO_MEMORY. */
int fm_core_solve(FmCore *c, double *rhs, int count, int transposed)
{
    if (!c->out.has_factor)
        return FM_SINGULAR;
    if (!transposed && count > 1)
        return fm_solve_dc_many(&c->m, &c->out, rhs, count) ? FM_NO_MEMORY : FM_OK;
    for (int k = 0; k < count; k++)
        fm_solve_dc(&c->m, &c->out, rhs + (size_t)k * c->m.nr, transposed);
    return FM_OK;
}

int fm_core_static_saddle(FmCore *c, const double *x, const double *q, const double *mu,
                          const double *loads, double *r)
{
    FmState *s = &c->stat;
    fm_reset_error(c);
    c->has_static = 0;
    memcpy(s->x, x, sizeof(double) * c->m.nx);
    memcpy(s->q, q, sizeof(double) * c->m.nq);
    const int code = fm_static_saddle(&c->m, s, &c->sd_static, loads, mu, r, &c->static_scale,
                                      &c->error);
    if (code) {
        c->failed = s;
        return code;
    }
    c->has_static = 1;
    return FM_OK;
}

int fm_core_static_solve(FmCore *c, double *rhs, int count, int transposed)
{
    const FmModel *m = &c->m;
    if (!c->has_static)
        return FM_SINGULAR;
    double *u = malloc(sizeof(double) * (size_t)(m->ns > 0 ? m->ns : 1));
    if (!u)
        return FM_NO_MEMORY;
    const double scale = c->static_scale;
    for (int k = 0; k < count; k++) {
        double *v = rhs + (size_t)k * m->ns;
        for (int a = 0; a < m->ns; a++)
            u[m->sd_band[a]] = a < m->nfree ? v[a] : scale * v[a];
        /* the factorised matrix is P A P with P = diag(I, scale): A^-1 = P (P A P)^-1 P,
         * and A^-T alike with the transposed factors */
        if (transposed)
            band_solve_t(&c->sd_static, u);
        else
            band_solve(&c->sd_static, u);
        for (int a = 0; a < m->ns; a++)
            v[a] = a < m->nfree ? u[m->sd_band[a]] : scale * u[m->sd_band[a]];
    }
    free(u);
    return FM_OK;
}

int fm_core_mass_regular(FmCore *c, const double *x)
{
    FmState *s = &c->stat;
    const FmModel *m = &c->m;
    fm_reset_error(c);
    c->has_static = 0;                       /* the static tangent's band is reused here */
    memcpy(s->x, x, sizeof(double) * m->nx);
    memset(s->xd, 0, sizeof(double) * m->nx);
    memset(s->q, 0, sizeof(double) * m->nq);
    fm_factor_at(m, s, x);                   /* e and D_x at x (and D_c, for the message) */
    fm_inertia(m, s);
    memset(s->sigma, 0, sizeof(double) * m->ne);
    memset(s->w, 0, sizeof(double) * m->ne);
    return fm_saddle(m, s, &c->sd_static, 0.0, 0.0, &c->error);
}

int fm_core_free_mass_times(FmCore *c, const double *v, int count, double *out)
{
    if (!c->has_static)
        return FM_SINGULAR;
    fm_free_mass_times(&c->m, &c->stat, v, count, out);
    return FM_OK;
}

void fm_core_configuration(const FmCore *c, double *x)
{
    memcpy(x, (c->failed ? c->failed : &c->eval)->x, sizeof(double) * c->m.nx);
}

const char *fm_build(void) { return FLEXMBD_BUILD " (" __VERSION__ "), " FLEXMBD_BINDING " binding"; }
