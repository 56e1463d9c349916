/* flexmbd._core: the Python face of the compiled core.
 *
 * Core(spec) takes the flat arrays of flexmbd/engine.py (any object with the buffer
 * protocol: numpy arrays) and keeps its own copies. A run is prepared once (laws, loads,
 * output arrays, progress) and then driven entirely here: kinematic and inverse runs over
 * a time grid, generalized-alpha integration with its outputs, or single evaluations for
 * scipy's integrators and the per-state functions. Python is called back only for laws
 * and loads that are Python callables, and for progress (which also lets Ctrl-C through).
 * Failures come back as a status dict (runs) or as CoreError (single evaluations);
 * flexmbd/engine.py turns both into flexmbd's exceptions with names and partial results.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "alpha.h"
#include "core.h"
#include "text.h"

#ifndef FLEXMBD_BUILD
#define FLEXMBD_BUILD "C"
#endif

static PyObject *CoreError;

/* --- buffers ------------------------------------------------------------------------------ */
typedef struct {
    Py_buffer view[16];
    int n;
} Views;

/* A C-contiguous float64 array of at least `need` entries (writable when asked), held in `v`
 * until release(v); NULL with a Python exception otherwise. */
static double *array(Views *v, PyObject *object, Py_ssize_t need, int write, const char *name)
{
    Py_buffer *b = &v->view[v->n];
    const int flags = PyBUF_FORMAT | PyBUF_C_CONTIGUOUS | (write ? PyBUF_WRITABLE : 0);
    if (PyObject_GetBuffer(object, b, flags) < 0)
        return NULL;
    if (b->itemsize != sizeof(double) || strcmp(b->format, "d")
        || b->len < need * (Py_ssize_t)sizeof(double)) {
        PyErr_Format(PyExc_ValueError, "%s: a float64 array of %zd entries is needed", name,
                     need);
        PyBuffer_Release(b);
        return NULL;
    }
    v->n++;
    return b->buf;
}

static void release(Views *v)
{
    while (v->n)
        PyBuffer_Release(&v->view[--v->n]);
}

/* A copy of the spec's array `name` (float64 'd' or int32 'i'); its length in *n. */
static int copy(PyObject *spec, const char *name, char type, void **out, Py_ssize_t *n)
{
    PyObject *item = PyDict_GetItemString(spec, name);
    Py_buffer b;
    *out = NULL;
    if (!item) {
        PyErr_Format(PyExc_KeyError, "core spec: %s is missing", name);
        return -1;
    }
    if (PyObject_GetBuffer(item, &b, PyBUF_FORMAT | PyBUF_C_CONTIGUOUS) < 0)
        return -1;
    const size_t size = type == 'd' ? sizeof(double) : sizeof(int);
    if (b.itemsize != (Py_ssize_t)size || strcmp(b.format, type == 'd' ? "d" : "i")) {
        PyErr_Format(PyExc_TypeError, "core spec: %s must be %s", name,
                     type == 'd' ? "float64" : "int32");
        PyBuffer_Release(&b);
        return -1;
    }
    *out = malloc(b.len > 0 ? b.len : 1);
    if (*out)
        memcpy(*out, b.buf, b.len);
    if (n)
        *n = b.len / (Py_ssize_t)size;
    PyBuffer_Release(&b);
    return *out ? 0 : (PyErr_NoMemory(), -1);
}

/* --- the Core object ------------------------------------------------------------------------ */
enum { OUT_X, OUT_XD, OUT_XDD, OUT_E, OUT_ED, OUT_EDD, OUT_Q, OUT_QD, OUT_QDD, OUT_SIGMA,
       OUT_REACTIONS, OUT_DRIVING, N_OUT };
static const char *OUT_NAMES[N_OUT] = {"x", "xd", "xdd", "e", "ed", "edd", "q", "qd", "qdd",
                                       "sigma", "reactions", "driving"};

typedef struct {
    PyObject_HEAD
    FmModel m;
    double *x0, *coord_scale, *lumped_diag;
    int *consistent;
    FmState eval, out;             /* the integrator's evaluations; outputs and single states */
    FmState *failed;               /* the state of the last failure */
    Band sd;                       /* the saddle-point matrix of the Newton operator */
    double *op_J;                  /* the element Jacobians of the operator's state */
    Band sd_acc;                   /* and of the accelerations (an output between two steps
                                      must not replace the operator) */
    FmError error;
    int trial;
    /* the prepared run */
    Views held;                    /* its arrays */
    int *law_kind;                 /* per q entry: 0 polynomial, 1 Python, 2 integrated */
    double *law_coef;              /* x0, v0, a0 per q entry */
    PyObject *law_callback;        /* fills law_values for the Python entries */
    double *law_values;
    PyObject *forces;              /* forces(t): reads force_x, force_xd, fills force_f */
    double *force_x, *force_xd, *force_f;
    PyObject *progress;
    double *outs[N_OUT];
    int n_outputs, dynamics;
    int level;                     /* outputs of a simulation: 0 positions, 1 rates, 2 all */
    double near;
    /* the integrator's predictor memory: the last evaluation */
    int have_last;
    double *start;                 /* the first guess of a run (the reference pose continued) */
    double last_t, *last_x, *last_xd, *last_xdd, *last_q, *last_qd, *last_qdd, *guess;
    double *path;                  /* 2 nq: q and its rate along a path from the last solution */
    double *found;                 /* nx: a solution to compare with (keep_branch) */
    long nfev;
    const int *watch;              /* during alpha_run: the q_d positions of free rotations'
                                      dynamic Euler parameters, three per rotation */
    int n_watch;                   /* rotations watched */
} Core;

static void release_run(Core *c)
{
    Py_CLEAR(c->law_callback);
    Py_CLEAR(c->forces);
    Py_CLEAR(c->progress);
    release(&c->held);
    c->law_values = c->force_x = c->force_xd = c->force_f = NULL;
    memset(c->outs, 0, sizeof(c->outs));
}

static void Core_dealloc(Core *c)
{
    release_run(c);
    FmModel *m = &c->m;
    void *all[] = {m->etype, m->c_off, m->c_idx, m->d_off, m->d_idx, m->p_off, m->j_off,
                   m->b_off, m->param, m->emass, m->varying, m->S, m->C, m->law_off,
                   m->elastic, m->sigma0, m->mconst, m->fixed, m->x_fixed,
                   m->q_coord, m->q_def, m->q_input, m->q_dyn, m->rows, m->row_of_def, m->dep,
                   m->free_of, m->dyn_coord, m->dyn_def, m->supported, m->elastic_def, m->periodic,
                   m->rot,
                   m->nodal_mass, m->f_const, m->dc_src, m->dc_dst, m->dc_rowband,
                   m->dc_colband, m->dc_w, m->dc_colscale, m->dc_rowscale, m->sd_band,
                   m->sd_a_src, m->sd_a_dst, m->sd_c_src, m->sd_c_dst, m->sd_c_dstt,
                   m->sd_m_coord, m->sd_m_dst, m->mult_of_def, c->x0, c->coord_scale,
                   m->coord_size,
                   c->lumped_diag, c->consistent, c->op_J, c->law_kind, c->law_coef,
                   c->last_x, c->last_xd, c->last_xdd, c->last_q, c->last_qd, c->last_qdd,
                   c->guess, c->start, c->path, c->found};
    for (size_t k = 0; k < sizeof(all) / sizeof(all[0]); k++)
        free(all[k]);
    if (c->eval.q) {
        fm_state_free(&c->eval);
        fm_state_free(&c->out);
        band_free(&c->sd);
        band_free(&c->sd_acc);
    }
    Py_TYPE(c)->tp_free((PyObject *)c);
}

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

static int build_maps(FmModel *m, const int *dc_row, const int *dc_col, int ndc,
                      const int *sa_u, const int *sa_v, int nsa, const int *sm_u,
                      const int *sc_u, const int *sc_v)
{
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
    m->ndc_map = ndc;
    m->nsd_a = nsa;
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
static void reference_terms(Core *c)
{
    FmModel *m = &c->m;
    double cc[64], out[64 * 65];
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

static int Core_init(Core *c, PyObject *args, PyObject *kwds)
{
    PyObject *spec;
    static char *keywords[] = {"spec", NULL};
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "O!", keywords, &PyDict_Type, &spec))
        return -1;
    FmModel *m = &c->m;
    memset(m, 0, sizeof(*m));
    const char *sizes[] = {"nx", "ne", "nel", "nq", "nxm", "nr", "nrigid", "nfree", "nmult",
                           "nd_dyn", "ndc", "total_j", "total_b"};
    int *fields[] = {&m->nx, &m->ne, &m->nel, &m->nq, &m->nxm, &m->nr, &m->nrigid, &m->nfree,
                     &m->nmult, &m->nd_dyn, &m->ndc, &m->total_j, &m->total_b};
    for (size_t k = 0; k < sizeof(sizes) / sizeof(sizes[0]); k++) {
        PyObject *item = PyDict_GetItemString(spec, sizes[k]);
        *fields[k] = item ? (int)PyLong_AsLong(item) : -1;
        if (!item || PyErr_Occurred())
            return PyErr_Occurred() ? -1 : (PyErr_Format(PyExc_KeyError, "core spec: %s",
                                                         sizes[k]), -1);
    }
    m->ns = m->nfree + m->nmult;
    int *dc_row, *dc_col, *sa_u, *sa_v, *sm_u, *sc_u, *sc_v;
    double *gravity;
    Py_ssize_t nfixed, nsupported, ndc, nsa, nsm, nsc, nrot;
    struct { const char *name; void **field; char type; Py_ssize_t *n; } arrays[] = {
        {"etype", (void **)&m->etype, 'i', 0}, {"c_off", (void **)&m->c_off, 'i', 0},
        {"c_idx", (void **)&m->c_idx, 'i', 0}, {"d_off", (void **)&m->d_off, 'i', 0},
        {"d_idx", (void **)&m->d_idx, 'i', 0}, {"p_off", (void **)&m->p_off, 'i', 0},
        {"j_off", (void **)&m->j_off, 'i', 0}, {"b_off", (void **)&m->b_off, 'i', 0},
        {"law_off", (void **)&m->law_off, 'i', 0}, {"param", (void **)&m->param, 'd', 0},
        {"emass", (void **)&m->emass, 'd', 0}, {"S", (void **)&m->S, 'd', 0},
        {"C", (void **)&m->C, 'd', 0}, {"elastic", (void **)&m->elastic, 'i', 0},
        {"sigma0", (void **)&m->sigma0, 'd', 0}, {"x_fixed", (void **)&m->x_fixed, 'd', 0},
        {"q_coord", (void **)&m->q_coord, 'i', 0}, {"q_def", (void **)&m->q_def, 'i', 0},
        {"q_input", (void **)&m->q_input, 'i', 0}, {"q_dyn", (void **)&m->q_dyn, 'i', 0},
        {"rows", (void **)&m->rows, 'i', 0}, {"row_of_def", (void **)&m->row_of_def, 'i', 0},
        {"dep", (void **)&m->dep, 'i', 0}, {"free_of", (void **)&m->free_of, 'i', 0},
        {"dyn_coord", (void **)&m->dyn_coord, 'i', 0},
        {"dyn_def", (void **)&m->dyn_def, 'i', 0},
        {"elastic_def", (void **)&m->elastic_def, 'i', 0},
        {"periodic", (void **)&m->periodic, 'i', 0},
        {"rotations", (void **)&m->rot, 'i', &nrot},
        {"nodal_mass", (void **)&m->nodal_mass, 'd', 0},
        {"f_const", (void **)&m->f_const, 'd', 0}, {"dc_src", (void **)&m->dc_src, 'i', 0},
        {"dc_rowband", (void **)&m->dc_rowband, 'i', 0},
        {"dc_colband", (void **)&m->dc_colband, 'i', 0},
        {"dc_colscale", (void **)&m->dc_colscale, 'd', 0},
        {"sd_band", (void **)&m->sd_band, 'i', 0}, {"sd_a_src", (void **)&m->sd_a_src, 'i', 0},
        {"sd_c_src", (void **)&m->sd_c_src, 'i', 0},
        {"sd_m_coord", (void **)&m->sd_m_coord, 'i', 0},
        {"mult_of_def", (void **)&m->mult_of_def, 'i', 0}, {"x0", (void **)&c->x0, 'd', 0},
        {"coord_scale", (void **)&c->coord_scale, 'd', 0},
        {"coord_size", (void **)&m->coord_size, 'd', 0},
        {"lumped_diag", (void **)&c->lumped_diag, 'd', 0},
        {"consistent", (void **)&c->consistent, 'i', 0},
        {"fixed", (void **)&m->fixed, 'i', &nfixed},
        {"supported", (void **)&m->supported, 'i', &nsupported},
        {"dc_row", (void **)&dc_row, 'i', &ndc}, {"dc_col", (void **)&dc_col, 'i', 0},
        {"sd_a_u", (void **)&sa_u, 'i', &nsa}, {"sd_a_v", (void **)&sa_v, 'i', 0},
        {"sd_m_u", (void **)&sm_u, 'i', &nsm}, {"sd_c_u", (void **)&sc_u, 'i', &nsc},
        {"sd_c_v", (void **)&sc_v, 'i', 0}, {"gravity", (void **)&gravity, 'd', 0},
    };
    const size_t count = sizeof(arrays) / sizeof(arrays[0]);
    for (size_t k = 0; k < count; k++)
        if (copy(spec, arrays[k].name, arrays[k].type, arrays[k].field, arrays[k].n) < 0)
            return -1;
    m->nfixed = (int)nfixed;
    m->nrot = (int)(nrot / 4);
    m->nsupported = (int)nsupported;
    m->nsd_m = (int)nsm;
    m->nsd_c = (int)nsc;
    m->gravity[0] = gravity[0];
    m->gravity[1] = gravity[1];
    m->gravity[2] = gravity[2];
    m->gravity_on = gravity[0] != 0.0 || gravity[1] != 0.0 || gravity[2] != 0.0;
    for (int k = 0; k < m->nel; k++)
        if (m->etype[k] < 0 || m->etype[k] >= FM_N_TYPES) {
            PyErr_SetString(PyExc_ValueError, "core spec: unknown element type");
            return -1;
        }
    m->tolerance = 1e-10;
    m->max_iterations = 25;
    m->regularity_limit = 1e-4;
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
    int failed = build_maps(m, dc_row, dc_col, (int)ndc, sa_u, sa_v, (int)nsa, sm_u, sc_u, sc_v)
                 || !m->varying || !m->mconst || !m->dc_rowscale || !c->op_J || !c->law_kind
                 || !c->law_coef || missing || fm_state_init(&c->eval, m)
                 || fm_state_init(&c->out, m) || band_init(&c->sd, m->ns, m->sd_kl, m->sd_ku)
                 || band_init(&c->sd_acc, m->ns, m->sd_kl, m->sd_ku);
    if (!failed) {
        reference_terms(c);
        for (Py_ssize_t k = 0; k < ndc; k++)
            m->dc_w[k] = m->dc_rowscale[dc_row[k]] * m->dc_colscale[dc_col[k]];
        memcpy(c->eval.x, c->x0, sizeof(double) * m->nx);
        memcpy(c->start, c->x0, sizeof(double) * m->nx);
    }
    void *temporary[] = {dc_row, dc_col, sa_u, sa_v, sm_u, sc_u, sc_v, gravity};
    for (size_t k = 0; k < sizeof(temporary) / sizeof(temporary[0]); k++)
        free(temporary[k]);
    return failed ? (PyErr_NoMemory(), -1) : 0;
}

/* --- failures ------------------------------------------------------------------------------ */
/* The status of a run (or a failure) as a dict; a pending Python exception (a callback
 * raised, or Ctrl-C) is handed over as "exception". */
static PyObject *status(const FmError *e, int reached, int code, const AlphaResult *r, long nfev)
{
    PyObject *type = NULL, *value = NULL, *traceback = NULL;
    if (code == FM_PYTHON && PyErr_Occurred()) {
        PyErr_Fetch(&type, &value, &traceback);
        PyErr_NormalizeException(&type, &value, &traceback);
    }
    PyObject *info = Py_BuildValue(
        "{s:i,s:i,s:d,s:i,s:d,s:i,s:d,s:d,s:d,s:l,s:l,s:l,s:l,s:O}", "reached", reached,
        "code", code, "time", e->time, "iterations", e->iterations, "residual", e->residual,
        "worst", e->worst, "conditioning", e->conditioning, "limit", e->limit, "step", e->step,
        "nfev", nfev, "njev", r ? r->njev : 0, "nlu", r ? r->nlu : 0,
        "nsteps", r ? r->nsteps : 0, "exception", value ? value : Py_None);
    Py_XDECREF(type);
    Py_XDECREF(value);
    Py_XDECREF(traceback);
    return info;
}

/* NULL with CoreError for a failed single evaluation (or the pending Python error). */
static PyObject *raise_core(Core *c, int code)
{
    if (code == FM_PYTHON || PyErr_Occurred())
        return NULL;
    c->error.code = code;
    PyObject *info = status(&c->error, 0, code, NULL, 0);
    if (info) {
        PyErr_SetObject(CoreError, info);
        Py_DECREF(info);
    }
    return NULL;
}

static void reset_error(Core *c)
{
    memset(&c->error, 0, sizeof(c->error));
    c->error.worst = -1;
    c->error.conditioning = c->error.limit = c->error.time = NAN;
}

/* --- laws, loads, progress ----------------------------------------------------------------- */
/* q, qd and qdd of a state at time t from the laws; the integrated entries from (q_d, qd_d,
 * qdd_d) when given (qdd_d NULL: zero). */
static int compose(Core *c, FmState *s, double t, const double *q_d, const double *qd_d,
                   const double *qdd_d)
{
    const FmModel *m = &c->m;
    if (c->law_callback) {
        PyObject *done = PyObject_CallFunction(c->law_callback, "d", t);
        if (!done)
            return FM_PYTHON;
        Py_DECREF(done);
    }
    for (int j = 0, d = 0; j < m->nq; j++) {
        const double *k = c->law_kind[j] == 1 ? c->law_values + 3 * j : c->law_coef + 3 * j;
        if (c->law_kind[j] == 2) {
            s->q[j] = q_d[d];
            s->qd[j] = qd_d[d];
            s->qdd[j] = qdd_d ? qdd_d[d] : 0.0;
            d++;
        } else if (c->law_kind[j] == 1) {
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

/* The applied loads of the Python callable at the state, or NULL without one. */
static int user_loads(Core *c, FmState *s, const double **loads)
{
    *loads = NULL;
    if (!c->forces)
        return FM_OK;
    memcpy(c->force_x, s->x, sizeof(double) * c->m.nx);
    memcpy(c->force_xd, s->xd, sizeof(double) * c->m.nx);
    PyObject *done = PyObject_CallFunction(c->forces, "d", s->t);
    if (!done)
        return FM_PYTHON;
    Py_DECREF(done);
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

/* The progress callback, and Ctrl-C. */
static int report(void *context, double t)
{
    Core *c = context;
    if (c->progress) {
        PyObject *done = PyObject_CallFunction(c->progress, "d", t);
        if (!done)
            return FM_PYTHON;
        Py_DECREF(done);
    }
    return PyErr_CheckSignals() < 0 ? FM_PYTHON : FM_OK;
}

/* --- outputs ---------------------------------------------------------------------------------- */
/* Row k of the output arrays from a state (reactions and driving loads are written in
 * place by dynamics_of). */
static void store(Core *c, int k, FmState *s)
{
    const FmModel *m = &c->m;
    const double *rows[N_OUT] = {s->x, s->xd, s->xdd, s->e, s->ed, s->edd, s->q, s->qd, s->qdd,
                                 s->sigma, NULL, NULL};
    const int sizes[N_OUT] = {m->nx, m->nx, m->nx, m->ne, m->ne, m->ne, m->nq, m->nq, m->nq,
                              m->ne, m->nx, m->nq};
    for (int o = 0; o < N_OUT; o++)
        if (c->outs[o] && rows[o])
            memcpy(c->outs[o] + (size_t)k * sizes[o], rows[o], sizeof(double) * sizes[o]);
}

/* Stresses of every deformation, reactions and driving loads of a state (THEORY 8), its
 * dynamic accelerations solved first (`solve`); with `free_dynamic` (a simulation) the
 * dynamic entries move freely, so their driving load is zero. Stores output k. */
static int dynamics_of(Core *c, FmState *s, int k, int free_dynamic, int solve)
{
    const FmModel *m = &c->m;
    const double *loads;
    int code = user_loads(c, s, &loads);
    if (code)
        return code;
    if (solve) {
        if ((code = fm_accelerations(m, s, &c->sd_acc, loads, &c->error)))
            return code;
    } else {
        fm_stresses(m, s);
        fm_inertia(m, s);
        fm_nodal_force(m, s, loads);
    }
    double *r = c->outs[OUT_REACTIONS] ? c->outs[OUT_REACTIONS] + (size_t)k * m->nx : NULL;
    double *drive = c->outs[OUT_DRIVING] ? c->outs[OUT_DRIVING] + (size_t)k * m->nq : NULL;
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
    store(c, k, s);
    return FM_OK;
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
static int solve_at(Core *c, FmState *s, double t, int first)
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
static int approach(Core *c, FmState *s, double t0, double t)
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

static PyObject *Core_kinematic_run(Core *c, PyObject *args)
{
    PyObject *times_object;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "O", &times_object))
        return NULL;
    const double *times = array(&v, times_object, 0, 0, "times");
    if (!times)
        return NULL;
    const int n = (int)(v.view[0].len / sizeof(double));
    FmState *s = &c->eval;
    int code = FM_OK, k;
    reset_error(c);
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
            store(c, k, s);
        if (!code && (k + 1) % 256 == 0)
            code = report(c, t);
        if (code)
            break;
    }
    if (!code)
        report(c, n ? times[n - 1] : 0.0);
    release(&v);
    return status(&c->error, k, code, NULL, 0);
}

/* --- the mechanical system for generalized-alpha --------------------------------------------- */
static void remember(Core *c, const FmState *s, int zero_xdd)
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
static void predict(Core *c, FmState *s, double t)
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
static int off_branch(Core *c, FmState *s)
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
static int along_path(Core *c, FmState *s, double t, const double *q_d, const double *qd_d,
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
static int keep_branch(Core *c, FmState *s, double t, const double *q_d, const double *qd_d,
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
    Core *c = context;
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
    Core *c = context;
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
    Core *c = context;
    memcpy(c->op_J, c->eval.J, sizeof(double) * c->m.total_j);
    return fm_saddle(&c->m, &c->eval, &c->sd, c_q, c_v, &c->error);
}

static int mech_apply(void *context, const double *r, double *da)
{
    Core *c = context;
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
    Core *c = context;
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
            store(c, k, s);
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
    Core *c = context;
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

static AlphaSystem mechanical(Core *c)
{
    AlphaSystem sys = {.m = c->m.nd_dyn, .context = c, .accelerations = mech_accelerations,
                       .residual = mech_residual, .renew = mech_renew, .apply = mech_apply,
                       .output = mech_output, .leave = c->n_watch ? mech_leave : NULL,
                       .error = &c->error, .trial = &c->trial};
    return sys;
}

/* The int32 positions in q_d of the free rotations to watch (three each), held in `b`;
 * -1 with a Python exception when they are not such positions. */
static int watch_of(Core *c, PyObject *object, Py_buffer *b)
{
    c->watch = NULL;
    c->n_watch = 0;
    if (object == Py_None)
        return 0;
    if (PyObject_GetBuffer(object, b, PyBUF_FORMAT | PyBUF_C_CONTIGUOUS) < 0)
        return -1;
    const int *w = b->buf;
    const Py_ssize_t n = b->len / (Py_ssize_t)sizeof(int);
    int bad = b->itemsize != sizeof(int) || strcmp(b->format, "i") || n % 3;
    for (Py_ssize_t k = 0; !bad && k < n; k++)
        bad = w[k] < 0 || w[k] >= c->m.nd_dyn;
    if (bad) {
        PyErr_SetString(PyExc_ValueError, "watch: int32 positions in q_d, three per rotation");
        PyBuffer_Release(b);
        return -1;
    }
    c->watch = w;
    c->n_watch = (int)(n / 3);
    return 0;
}

static PyObject *Core_alpha_run(Core *c, PyObject *args, PyObject *kwds)
{
    PyObject *times_object, *q0_object, *v0_object;
    AlphaOptions opt = {0};
    Views v = {.n = 0};
    PyObject *watch_object = Py_None, *end_object = Py_None;
    Py_buffer watch_buffer;
    static char *keywords[] = {"times", "q0", "v0", "step", "rho_inf", "rtol", "atol",
                               "iterations", "renew_every", "near", "watch", "end", NULL};
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOddddiid|OO", keywords, &times_object,
                                     &q0_object, &v0_object, &opt.step, &opt.rho_inf, &opt.rtol,
                                     &opt.atol, &opt.iterations, &opt.renew_every, &c->near,
                                     &watch_object, &end_object))
        return NULL;
    const double *times = array(&v, times_object, 0, 0, "times");
    const double *q0 = times ? array(&v, q0_object, c->m.nd_dyn, 0, "q0") : NULL;
    const double *v0 = q0 ? array(&v, v0_object, c->m.nd_dyn, 0, "v0") : NULL;
    opt.end = !v0 || end_object == Py_None ? NULL
                                           : array(&v, end_object, 2 * c->m.nd_dyn, 1, "end");
    if (!v0 || (end_object != Py_None && !opt.end) || watch_of(c, watch_object, &watch_buffer)) {
        release(&v);
        return NULL;
    }
    reset_error(c);
    c->have_last = 0;
    c->nfev = 0;
    AlphaSystem sys = mechanical(c);
    opt.progress = report;
    opt.progress_context = c;
    AlphaResult result = alpha_run(&sys, times, (int)(v.view[0].len / sizeof(double)), q0, v0,
                                   &opt);
    if (c->watch)
        PyBuffer_Release(&watch_buffer);
    c->watch = NULL;
    c->n_watch = 0;
    release(&v);
    return status(&c->error, result.reached, result.status, &result, c->nfev);
}

/* --- single evaluations ------------------------------------------------------------------------ */
/* accelerations(t, y, out): qdd_d at y = [q_d, qd_d], for scipy's integrators */
static PyObject *Core_accelerations(Core *c, PyObject *args)
{
    double t;
    PyObject *yo, *oo;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "dOO", &t, &yo, &oo))
        return NULL;
    const int nd = c->m.nd_dyn;
    const double *y = array(&v, yo, 2 * nd, 0, "y");
    double *out = y ? array(&v, oo, nd, 1, "out") : NULL;
    int code = FM_OK;
    if (out) {
        reset_error(c);
        code = mech_accelerations(c, t, y, y + nd, out);
    }
    release(&v);
    return !out ? NULL : code ? raise_core(c, code) : Py_NewRef(Py_None);
}

/* residual(t, y, a, r): the reduced residual at y = [q_d, qd_d] and dynamic accelerations a,
 * the state generalized-alpha evaluates */
static PyObject *Core_residual(Core *c, PyObject *args)
{
    double t;
    PyObject *yo, *ao, *ro;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "dOOO", &t, &yo, &ao, &ro))
        return NULL;
    const int nd = c->m.nd_dyn;
    const double *y = array(&v, yo, 2 * nd, 0, "y");
    const double *a = y ? array(&v, ao, nd, 0, "a") : NULL;
    double *r = a ? array(&v, ro, nd, 1, "r") : NULL;
    int code = FM_OK;
    if (r) {
        reset_error(c);
        code = mech_residual(c, t, y, y + nd, a, r);
    }
    release(&v);
    return !r ? NULL : code ? raise_core(c, code) : Py_NewRef(Py_None);
}

/* correction(c_q, c_v, r, da): Newton's da = -S^-1 r with S = Mbar + c_q K + c_v C at the
 * state of the last residual */
static PyObject *Core_correction(Core *c, PyObject *args)
{
    double c_q, c_v;
    PyObject *ro, *dao;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "ddOO", &c_q, &c_v, &ro, &dao))
        return NULL;
    const double *r = array(&v, ro, c->m.nd_dyn, 0, "r");
    double *da = r ? array(&v, dao, c->m.nd_dyn, 1, "da") : NULL;
    int code = FM_OK;
    if (da) {
        reset_error(c);
        if (!(code = mech_renew(c, c_q, c_v)))
            code = mech_apply(c, r, da);
    }
    release(&v);
    return !da ? NULL : code ? raise_core(c, code) : Py_NewRef(Py_None);
}

/* output(k, t, y): the full state at output k from y = [q_d, qd_d] */
static PyObject *Core_output(Core *c, PyObject *args)
{
    int k;
    double t;
    PyObject *yo;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "idO", &k, &t, &yo))
        return NULL;
    if (k < 0 || k >= c->n_outputs) {
        PyErr_SetString(PyExc_IndexError, "output index out of range");
        return NULL;
    }
    const double *y = array(&v, yo, 2 * c->m.nd_dyn, 0, "y");
    int code = FM_OK;
    if (y) {
        reset_error(c);
        code = mech_output(c, k, t, y, y + c->m.nd_dyn, NULL);
    }
    release(&v);
    return !y ? NULL : code ? raise_core(c, code) : Py_NewRef(Py_None);
}

/* state(t, q, qd, qdd, guess, x, xd, xdd, e, ed, edd): the kinematics of one state, exact
 * position solve (full Newton, D_c refreshed at the solution) */
static PyObject *Core_state(Core *c, PyObject *args)
{
    double t;
    PyObject *o[10];
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "dOOOOOOOOOO", &t, &o[0], &o[1], &o[2], &o[3], &o[4], &o[5],
                          &o[6], &o[7], &o[8], &o[9]))
        return NULL;
    const FmModel *m = &c->m;
    FmState *s = &c->out;
    const int sizes[10] = {m->nq, m->nq, m->nq, m->nx, m->nx, m->nx, m->nx, m->ne, m->ne, m->ne};
    double *a[10];
    for (int k = 0; k < 10; k++)
        if (!(a[k] = array(&v, o[k], sizes[k], k > 3, "state"))) {
            release(&v);
            return NULL;
        }
    reset_error(c);
    c->failed = s;
    memcpy(s->q, a[0], sizeof(double) * m->nq);
    memcpy(s->qd, a[1], sizeof(double) * m->nq);
    memcpy(s->qdd, a[2], sizeof(double) * m->nq);
    int code = fm_kinematics(m, s, t, a[3], m->tolerance, 0, 1, &c->error);
    const double *from[6] = {s->x, s->xd, s->xdd, s->e, s->ed, s->edd};
    for (int k = 0; !code && k < 6; k++)
        memcpy(a[4 + k], from[k], sizeof(double) * sizes[4 + k]);
    release(&v);
    return code ? raise_core(c, code) : Py_NewRef(Py_None);
}

/* mass_matrix(x, xd, M, h, f): the dense mass matrix (nx x nx), the velocity-dependent
 * inertia h and the constant loads with gravity f (nx each) at (x, xd) */
static PyObject *Core_mass_matrix(Core *c, PyObject *args)
{
    PyObject *o[5];
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "OOOOO", &o[0], &o[1], &o[2], &o[3], &o[4]))
        return NULL;
    const FmModel *m = &c->m;
    const Py_ssize_t sizes[5] = {m->nx, m->nx, (Py_ssize_t)m->nx * m->nx, m->nx, m->nx};
    double *a[5];
    for (int k = 0; k < 5; k++)
        if (!(a[k] = array(&v, o[k], sizes[k], k > 1, "mass_matrix"))) {
            release(&v);
            return NULL;
        }
    FmState *s = &c->out;
    double *M = a[2], *h = a[3], *f = a[4];
    memcpy(s->x, a[0], sizeof(double) * m->nx);
    memcpy(s->xd, a[1], sizeof(double) * m->nx);
    fm_inertia(m, s);
    memset(M, 0, sizeof(double) * m->nx * m->nx);
    memset(h, 0, sizeof(double) * m->nx);
    memcpy(f, m->f_const, sizeof(double) * m->nx);
    for (int i = 0; i < m->nx; i++)
        M[i * m->nx + i] += m->nodal_mass[i];
    for (int k = 0; k < m->nel; k++) {
        const int nc = m->c_off[k + 1] - m->c_off[k], *ci = m->c_idx + m->c_off[k];
        for (int a_ = 0; a_ < nc; a_++) {
            h[ci[a_]] += s->hvec[m->c_off[k] + a_];
            f[ci[a_]] += s->gvec[m->c_off[k] + a_];
            for (int b = 0; b < nc; b++)
                M[ci[a_] * m->nx + ci[b]] += s->blocks[m->b_off[k] + a_ * nc + b];
        }
    }
    release(&v);
    Py_RETURN_NONE;
}

/* element_values(name, x, out): the kernel "deform_jac" or "hessian" of every element at
 * x, element after element (fm_element_values) */
static PyObject *Core_element_values(Core *c, PyObject *args)
{
    const char *name;
    PyObject *xo, *oo;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "sOO", &name, &xo, &oo))
        return NULL;
    const int hessian = !strcmp(name, "hessian");
    if (!hessian && strcmp(name, "deform_jac")) {
        PyErr_Format(PyExc_ValueError, "element_values: no kernel %s for all elements", name);
        return NULL;
    }
    const Py_ssize_t size = (Py_ssize_t)fm_element_values(&c->m, hessian, NULL, NULL);
    const double *x = array(&v, xo, c->m.nx, 0, "x");
    double *out = x ? array(&v, oo, size, 1, "out") : NULL;
    if (out)
        fm_element_values(&c->m, hessian, x, out);
    release(&v);
    return out ? Py_NewRef(Py_None) : NULL;
}

/* inertia_slopes(x, q, qd, qdd, step, rates, out): fm_inertia_slopes */
static PyObject *Core_inertia_slopes(Core *c, PyObject *args)
{
    PyObject *o[6];
    int rates;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "OOOOOpO", &o[0], &o[1], &o[2], &o[3], &o[4], &rates, &o[5]))
        return NULL;
    const FmModel *m = &c->m;
    const Py_ssize_t sizes[6] = {m->nx, m->nq, m->nq, m->nq, m->nq,
                                 (Py_ssize_t)(m->nx + m->ne) * m->nq};
    double *a[6];
    for (int k = 0; k < 6; k++)
        if (!(a[k] = array(&v, o[k], sizes[k], k == 5, "inertia_slopes"))) {
            release(&v);
            return NULL;
        }
    reset_error(c);
    c->failed = &c->out;
    const int code = fm_inertia_slopes(m, &c->out, a[0], a[1], a[2], a[3], a[4], rates, a[5],
                                       &c->error);
    release(&v);
    return code ? raise_core(c, code) : Py_NewRef(Py_None);
}

/* factor(x): D_c at x; returns its scaled conditioning (0 when singular) */
static PyObject *Core_factor(Core *c, PyObject *args)
{
    PyObject *xo;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "O", &xo))
        return NULL;
    const double *x = array(&v, xo, c->m.nx, 0, "x");
    if (!x)
        return NULL;
    FmState *s = &c->out;
    reset_error(c);
    s->cond_column = -1;                     /* a configuration of its own: estimate in full */
    const int code = fm_factor_at(&c->m, s, x);
    release(&v);
    return PyFloat_FromDouble(code ? 0.0 : fm_conditioning(&c->m, s));
}

/* solve(rhs, transposed): D_c^-1 rhs (or D_c^-T rhs) in place for rhs (k, nr), with the
 * last factor(x) */
static PyObject *Core_solve(Core *c, PyObject *args)
{
    PyObject *ro;
    int transposed;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "Op", &ro, &transposed))
        return NULL;
    if (!c->out.has_factor) {
        PyErr_SetString(PyExc_RuntimeError, "D_c is not factorised");
        return NULL;
    }
    double *r = array(&v, ro, 0, 1, "rhs");
    if (!r)
        return NULL;
    const int count = c->m.nr ? (int)(v.view[0].len / sizeof(double) / c->m.nr) : 0;
    if (!transposed && count > 1) {
        const int code = fm_solve_dc_many(&c->m, &c->out, r, count);
        release(&v);
        if (code)
            return PyErr_NoMemory();
        Py_RETURN_NONE;
    }
    for (int k = 0; k < count; k++)
        fm_solve_dc(&c->m, &c->out, r + (size_t)k * c->m.nr, transposed);
    release(&v);
    Py_RETURN_NONE;
}

/* configuration(out): the configuration of the last failure, or of the last evaluation */
static PyObject *Core_configuration(Core *c, PyObject *args)
{
    PyObject *xo;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "O", &xo))
        return NULL;
    double *x = array(&v, xo, c->m.nx, 1, "x");
    if (!x)
        return NULL;
    memcpy(x, (c->failed ? c->failed : &c->eval)->x, sizeof(double) * c->m.nx);
    release(&v);
    Py_RETURN_NONE;
}

static PyObject *Core_bands(Core *c, PyObject *unused)
{
    (void)unused;
    return Py_BuildValue("{s:i,s:i,s:i,s:i,s:i,s:i}", "dc_n", c->m.nr, "dc_kl", c->m.dc_kl,
                         "dc_ku", c->m.dc_ku, "saddle_n", c->m.ns, "saddle_kl", c->m.sd_kl,
                         "saddle_ku", c->m.sd_ku);
}

/* settings(tolerance, max_iterations, regularity_limit) of the position solve */
static PyObject *Core_settings(Core *c, PyObject *args)
{
    if (!PyArg_ParseTuple(args, "didd", &c->m.tolerance, &c->m.max_iterations,
                          &c->m.regularity_limit, &c->m.reference_conditioning))
        return NULL;
    Py_RETURN_NONE;
}

/* reset([start]): forget the last evaluation; the next run starts from `start` (nx), or
 * from the reference configuration */
static PyObject *Core_reset(Core *c, PyObject *args)
{
    PyObject *so = Py_None;
    Views v = {.n = 0};
    if (!PyArg_ParseTuple(args, "|O", &so))
        return NULL;
    const double *start = so == Py_None ? c->x0 : array(&v, so, c->m.nx, 0, "start");
    if (!start)
        return NULL;
    memcpy(c->start, start, sizeof(double) * c->m.nx);
    release(&v);
    c->have_last = 0;
    c->nfev = 0;
    Py_RETURN_NONE;
}

/* prepare(law_kind, law_coef, outputs, n_outputs, dynamics, [law_callback, law_values,
 * forces, force_x, force_xd, force_f, progress]): a run's laws, loads and output arrays */
static PyObject *Core_prepare(Core *c, PyObject *args, PyObject *kwds)
{
    PyObject *kind, *coef, *outputs, *callback = Py_None, *values = Py_None;
    PyObject *forces = Py_None, *fx = Py_None, *fxd = Py_None, *ff = Py_None;
    PyObject *progress = Py_None;
    int n_outputs, dynamics;
    static char *keywords[] = {"law_kind", "law_coef", "outputs", "n_outputs", "dynamics",
                               "law_callback", "law_values", "forces", "force_x", "force_xd",
                               "force_f", "progress", NULL};
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOO!ii|OOOOOOO", keywords, &kind, &coef,
                                     &PyDict_Type, &outputs, &n_outputs, &dynamics, &callback,
                                     &values, &forces, &fx, &fxd, &ff, &progress))
        return NULL;
    release_run(c);
    FmModel *m = &c->m;
    Py_buffer b;
    if (PyObject_GetBuffer(kind, &b, PyBUF_FORMAT | PyBUF_C_CONTIGUOUS) < 0)
        return NULL;
    const int good = b.itemsize == sizeof(int) && b.len == (Py_ssize_t)sizeof(int) * m->nq;
    if (good)
        memcpy(c->law_kind, b.buf, b.len);
    PyBuffer_Release(&b);
    if (!good) {
        PyErr_SetString(PyExc_ValueError, "law_kind: an int32 array over q is needed");
        return NULL;
    }
    Views held = {.n = 0};
    const double *co = array(&held, coef, 3 * m->nq, 0, "law_coef");
    if (!co)
        return NULL;
    memcpy(c->law_coef, co, sizeof(double) * 3 * m->nq);
    release(&held);
    int ok = 1;
    if (callback != Py_None)
        ok = (c->law_values = array(&c->held, values, 3 * m->nq, 1, "law_values")) != NULL;
    if (ok && forces != Py_None)
        ok = (c->force_x = array(&c->held, fx, m->nx, 1, "force_x"))
             && (c->force_xd = array(&c->held, fxd, m->nx, 1, "force_xd"))
             && (c->force_f = array(&c->held, ff, m->nx, 1, "force_f"));
    const int sizes[N_OUT] = {m->nx, m->nx, m->nx, m->ne, m->ne, m->ne, m->nq, m->nq, m->nq,
                              m->ne, m->nx, m->nq};
    for (int o = 0; ok && o < N_OUT; o++) {
        PyObject *item = PyDict_GetItemString(outputs, OUT_NAMES[o]);
        if (item && item != Py_None)
            ok = (c->outs[o] = array(&c->held, item, (Py_ssize_t)n_outputs * sizes[o], 1,
                                     OUT_NAMES[o])) != NULL;
    }
    if (!ok) {
        release_run(c);
        return NULL;
    }
    c->law_callback = callback == Py_None ? NULL : Py_NewRef(callback);
    c->forces = forces == Py_None ? NULL : Py_NewRef(forces);
    c->progress = progress == Py_None ? NULL : Py_NewRef(progress);
    c->n_outputs = n_outputs;
    c->dynamics = dynamics;
    c->level = 0;
    for (int o = 0; o < N_OUT; o++)
        if (c->outs[o] && o != OUT_X && o != OUT_E && o != OUT_Q) {
            const int rates = o == OUT_XD || o == OUT_ED || o == OUT_QD;
            c->level = rates && c->level < 2 ? 1 : 2;
        }
    c->have_last = 0;
    Py_RETURN_NONE;
}

static PyObject *Core_release(Core *c, PyObject *unused)
{
    (void)unused;
    release_run(c);
    Py_RETURN_NONE;
}

static PyMethodDef Core_methods[] = {
    {"prepare", (PyCFunction)(void (*)(void))Core_prepare, METH_VARARGS | METH_KEYWORDS,
     "Prepare a run: laws, loads, output arrays."},
    {"release", (PyCFunction)Core_release, METH_NOARGS, "Let go of the prepared run's arrays."},
    {"settings", (PyCFunction)Core_settings, METH_VARARGS,
     "settings(tolerance, max_iterations, regularity_limit, reference_conditioning) of the "
     "position solve."},
    {"kinematic_run", (PyCFunction)Core_kinematic_run, METH_VARARGS,
     "Kinematics (and with dynamics, stresses and reactions) at every time of a grid."},
    {"alpha_run", (PyCFunction)(void (*)(void))Core_alpha_run, METH_VARARGS | METH_KEYWORDS,
     "Generalized-alpha integration with the outputs of every time of a grid."},
    {"accelerations", (PyCFunction)Core_accelerations, METH_VARARGS,
     "accelerations(t, y, out): qdd_d at y = [q_d, qd_d]."},
    {"residual", (PyCFunction)Core_residual, METH_VARARGS,
     "residual(t, y, a, r): the reduced residual at y = [q_d, qd_d], accelerations a."},
    {"correction", (PyCFunction)Core_correction, METH_VARARGS,
     "correction(c_q, c_v, r, da): Newton's -S^-1 r at the last residual's state."},
    {"output", (PyCFunction)Core_output, METH_VARARGS,
     "output(k, t, y): the full state at output k from y = [q_d, qd_d]."},
    {"reset", (PyCFunction)Core_reset, METH_VARARGS,
     "reset([start]): forget the last evaluation; the next run starts from start."},
    {"state", (PyCFunction)Core_state, METH_VARARGS,
     "state(t, q, qd, qdd, guess, x, xd, xdd, e, ed, edd): kinematics of one state."},
    {"mass_matrix", (PyCFunction)Core_mass_matrix, METH_VARARGS,
     "mass_matrix(x, xd, M, h, f): mass matrix, velocity inertia, loads and gravity."},
    {"element_values", (PyCFunction)Core_element_values, METH_VARARGS,
     "element_values(name, x, out): kernel deform_jac or hessian of every element at x."},
    {"inertia_slopes", (PyCFunction)Core_inertia_slopes, METH_VARARGS,
     "inertia_slopes(x, q, qd, qdd, step, rates, out): differences of M xdd + h and ed."},
    {"factor", (PyCFunction)Core_factor, METH_VARARGS, "factor(x): D_c at x; its conditioning."},
    {"solve", (PyCFunction)Core_solve, METH_VARARGS, "solve(rhs, transposed): with D_c."},
    {"configuration", (PyCFunction)Core_configuration, METH_VARARGS,
     "configuration(out): the configuration of the last failure or evaluation."},
    {"bands", (PyCFunction)Core_bands, METH_NOARGS, "Sizes and bands of the square systems."},
    {NULL, NULL, 0, NULL}};

static PyTypeObject CoreType = {
    PyVarObject_HEAD_INIT(NULL, 0)
    .tp_name = "flexmbd._core.Core",
    .tp_basicsize = sizeof(Core),
    .tp_flags = Py_TPFLAGS_DEFAULT,
    .tp_doc = "A model compiled for the core (see flexmbd/engine.py).",
    .tp_new = PyType_GenericNew,
    .tp_init = (initproc)Core_init,
    .tp_dealloc = (destructor)Core_dealloc,
    .tp_methods = Core_methods,
};

/* --- result files ---------------------------------------------------------------------------- */
/* Write all of `size` bytes to the file descriptor `fd`; 0, or -1 with errno set. */
static int write_all(int fd, const char *text, size_t size)
{
    while (size > 0) {
        const ssize_t done = write(fd, text, size);
        if (done < 0) {
            if (errno == EINTR)
                continue;
            return -1;
        }
        text += done;
        size -= (size_t)done;
    }
    return 0;
}

/* csv_write(fd, columns): the rows of equally long float64 columns (1-d, any strides) as
 * CSV lines on the file descriptor fd, each number as "%.17g" writes it (text.c). Rows
 * are formatted into a buffer of CSV_BUFFER bytes and written as it fills: the memory
 * stays the same whatever the rows, and no large allocation costs the kernel page faults
 * (a thread formatting half of the rows gained nothing in a fresh process: the second
 * processor's wake-up took as long). Other threads of Python run meanwhile (the columns
 * must not change). */
#define CSV_BUFFER 65536
static PyObject *csv_write(PyObject *self, PyObject *args)
{
    int fd;
    PyObject *sequence;
    (void)self;
    if (!PyArg_ParseTuple(args, "iO", &fd, &sequence))
        return NULL;
    PyObject *items = PySequence_Fast(sequence, "csv_write: columns must be a sequence");
    if (!items)
        return NULL;
    const Py_ssize_t columns = PySequence_Fast_GET_SIZE(items);
    Py_buffer *b = PyMem_Calloc(columns > 0 ? (size_t)columns : 1, sizeof(Py_buffer));
    char *text = PyMem_Malloc(CSV_BUFFER);
    Py_ssize_t held = 0, rows = 0;
    int failed = !b || !text;
    if (failed)
        PyErr_NoMemory();
    for (; !failed && held < columns; held++) {
        if (PyObject_GetBuffer(PySequence_Fast_GET_ITEM(items, held), &b[held],
                               PyBUF_FORMAT | PyBUF_STRIDES) < 0) {
            failed = 1;
            break;
        }
        const Py_buffer *c = &b[held];
        if (c->ndim != 1 || c->itemsize != sizeof(double) || strcmp(c->format, "d") ||
            (held > 0 && c->shape[0] != rows)) {
            PyErr_SetString(PyExc_ValueError, "csv_write: equally long 1-d float64 columns "
                                              "are needed");
            held++;
            failed = 1;
            break;
        }
        rows = c->shape[0];
    }
    int error = 0;
    if (!failed && columns > 0) {
        Py_BEGIN_ALLOW_THREADS
        size_t used = 0;
        for (Py_ssize_t r = 0; r < rows && !error; r++)
            for (Py_ssize_t k = 0; k < columns; k++) {
                if (used > CSV_BUFFER - 32) {        /* a number takes 25 bytes at most */
                    if (write_all(fd, text, used)) {
                        error = errno;
                        break;
                    }
                    used = 0;
                }
                const char *at = (const char *)b[k].buf + r * b[k].strides[0];
                used += (size_t)format_17g(*(const double *)at, text + used);
                text[used++] = k + 1 < columns ? ',' : '\n';
            }
        if (!error && write_all(fd, text, used))
            error = errno;
        Py_END_ALLOW_THREADS
        if (error) {
            errno = error;
            PyErr_SetFromErrno(PyExc_OSError);
            failed = 1;
        }
    }
    for (Py_ssize_t k = 0; k < held; k++)
        if (b[k].obj)
            PyBuffer_Release(&b[k]);
    PyMem_Free(b);
    PyMem_Free(text);
    Py_DECREF(items);
    if (failed)
        return NULL;
    Py_RETURN_NONE;
}

/* format_17g(x): one number as csv_write writes it (for the tests) */
static PyObject *format_number(PyObject *self, PyObject *args)
{
    double x;
    char out[32];
    (void)self;
    if (!PyArg_ParseTuple(args, "d", &x))
        return NULL;
    return PyUnicode_FromStringAndSize(out, format_17g(x, out));
}

/* --- generated kernels, for the tests -------------------------------------------------------- */
/* kernel(type, name, c, p, v, g, out): one generated element kernel at one element */
static PyObject *kernel(PyObject *self, PyObject *args)
{
    int type;
    const char *name;
    PyObject *co, *po, *vo, *go, *oo;
    Views w = {.n = 0};
    (void)self;
    if (!PyArg_ParseTuple(args, "isOOOOO", &type, &name, &co, &po, &vo, &go, &oo))
        return NULL;
    if (type < 0 || type >= FM_N_TYPES) {
        PyErr_SetString(PyExc_ValueError, "unknown element type");
        return NULL;
    }
    const FmKernels *k = &FM_KERNELS[type];
    const Py_ssize_t nc = k->nc, nd = k->nd;
    const double *c = array(&w, co, nc, 0, "c"), *p = c ? array(&w, po, k->np, 0, "p") : NULL;
    const double *v = p && vo != Py_None ? array(&w, vo, nc, 0, "v") : NULL;
    const double *g = p && go != Py_None ? array(&w, go, 2, 0, "g") : NULL;
    double *out = p && !PyErr_Occurred() ? array(&w, oo, 1, 1, "out") : NULL;
    const Py_ssize_t room = out ? w.view[w.n - 1].len / (Py_ssize_t)sizeof(double) : 0;
    int done = 1;
    if (!out)
        done = 0;
    else if (!strcmp(name, "deform") && room >= nd)
        k->deform(c, p, out);
    else if (!strcmp(name, "deform_jac") && room >= nd * (1 + nc))
        k->deform_jac(c, p, out);
    else if (!strcmp(name, "quadratic") && v && room >= nd)
        k->quadratic(c, v, p, out);
    else if (!strcmp(name, "hessian") && room >= nd * nc * nc)
        k->hessian(c, p, out);
    else if (!strcmp(name, "mass") && k->mass && room >= nc * nc)
        k->mass(c, p, out);
    else if (!strcmp(name, "inertia") && k->inertia && v && room >= nc)
        k->inertia(c, v, p, out);
    else if (!strcmp(name, "gravity") && k->gravity && g && room >= nc)
        k->gravity(c, p, g, out);
    else {
        PyErr_Format(PyExc_ValueError, "kernel %s: not defined for %s, or wrong arguments",
                     name, k->keyword);
        done = 0;
    }
    release(&w);
    return done ? Py_NewRef(Py_None) : NULL;
}

static PyMethodDef module_methods[] = {
    {"csv_write", csv_write, METH_VARARGS,
     "csv_write(fd, columns): equally long float64 columns as CSV rows on fd, as %.17g."},
    {"format_17g", format_number, METH_VARARGS, "format_17g(x): x as %.17g writes it."},
    {"kernel", kernel, METH_VARARGS,
     "kernel(type, name, c, p, v, g, out): one generated element kernel."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "flexmbd._core",
                                    "flexmbd's compiled core (see flexmbd/engine.py).", -1,
                                    module_methods};

PyMODINIT_FUNC PyInit__core(void)
{
    if (PyType_Ready(&CoreType) < 0)
        return NULL;
    PyObject *mod = PyModule_Create(&module);
    if (!mod)
        return NULL;
    CoreError = PyErr_NewException("flexmbd._core.CoreError", PyExc_RuntimeError, NULL);
    PyModule_AddObject(mod, "Core", Py_NewRef((PyObject *)&CoreType));
    PyModule_AddObject(mod, "CoreError", CoreError);
    PyObject *keywords = PyTuple_New(FM_N_TYPES);
    for (int k = 0; k < FM_N_TYPES; k++)
        PyTuple_SET_ITEM(keywords, k, PyUnicode_FromString(FM_KERNELS[k].keyword));
    PyModule_AddObject(mod, "KEYWORDS", keywords);
    PyModule_AddStringConstant(mod, "DEFINITIONS_HASH", FM_DEFINITIONS_HASH);
    PyModule_AddStringConstant(mod, "BUILD", FLEXMBD_BUILD " (" __VERSION__ ")");
    const char *names[] = {"OK", "NOT_CONVERGED", "SINGULAR", "SINGULAR_TOLERANCE", "MASSLESS",
                           "NOT_FINITE", "STEP_FAILED", "PYTHON", "INTERRUPTED", "NO_MEMORY",
                           "PARTITION"};
    for (int k = 0; k < 11; k++)
        PyModule_AddIntConstant(mod, names[k], k);
    return mod;
}
