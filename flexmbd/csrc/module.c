/* flexmbd._core: the Python face of the compiled core.
 *
 * Core(spec) takes the flat arrays of flexmbd/engine.py (any object with the buffer
 * protocol: numpy arrays) and keeps its own copies. A run is prepared once (laws,
 * loads, output arrays, progress) and then driven entirely here: kinematic and inverse
 * runs over a time grid, generalized-alpha integration with its outputs, or single
 * evaluations for scipy's integrators and the per-state functions. Python code is
 * called back only for laws and loads that are Python callables, and for progress.
 * Failures come back as a status tuple (runs) or as CoreError (single evaluations);
 * flexmbd/engine.py turns both into flexmbd's exceptions with names and partial results.
 */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "alpha.h"
#include "core.h"

#ifndef FLEXMBD_BUILD
#define FLEXMBD_BUILD "C"
#endif

static PyObject *CoreError;

/* --- arrays in, arrays out ------------------------------------------------------------- */
static int copy_buffer(PyObject *spec, const char *name, char format, void **out, Py_ssize_t *n,
                       int required)
{
    PyObject *item = PyDict_GetItemString(spec, name);
    *out = NULL;
    if (n)
        *n = 0;
    if (!item || item == Py_None) {
        if (required) {
            PyErr_Format(PyExc_KeyError, "core spec: %s is missing", name);
            return -1;
        }
        return 0;
    }
    Py_buffer view;
    if (PyObject_GetBuffer(item, &view, PyBUF_FORMAT | PyBUF_C_CONTIGUOUS) < 0)
        return -1;
    const size_t size = format == 'd' ? sizeof(double) : sizeof(int);
    const char *want = format == 'd' ? "d" : "i";
    if (view.itemsize != (Py_ssize_t)size || !view.format || strcmp(view.format, want)) {
        PyErr_Format(PyExc_TypeError, "core spec: %s must be %s", name,
                     format == 'd' ? "float64" : "int32");
        PyBuffer_Release(&view);
        return -1;
    }
    const Py_ssize_t count = view.len / view.itemsize;
    *out = malloc((count > 0 ? count : 1) * size);
    if (!*out) {
        PyBuffer_Release(&view);
        PyErr_NoMemory();
        return -1;
    }
    memcpy(*out, view.buf, count * size);
    if (n)
        *n = count;
    PyBuffer_Release(&view);
    return 0;
}

static int get_int(PyObject *spec, const char *name, int *out)
{
    PyObject *item = PyDict_GetItemString(spec, name);
    if (!item) {
        PyErr_Format(PyExc_KeyError, "core spec: %s is missing", name);
        return -1;
    }
    *out = (int)PyLong_AsLong(item);
    return PyErr_Occurred() ? -1 : 0;
}

/* A writable double array of at least n entries, or NULL (None). */
static double *writable(PyObject *object, Py_ssize_t n, Py_buffer *view, const char *name)
{
    if (!object || object == Py_None)
        return NULL;
    if (PyObject_GetBuffer(object, view, PyBUF_WRITABLE | PyBUF_FORMAT | PyBUF_C_CONTIGUOUS) < 0)
        return NULL;
    if (view->itemsize != sizeof(double) || strcmp(view->format, "d")
        || view->len < n * (Py_ssize_t)sizeof(double)) {
        PyErr_Format(PyExc_ValueError, "%s: a float64 array of %zd entries is needed", name, n);
        PyBuffer_Release(view);
        return NULL;
    }
    return view->buf;
}

static const double *readable(PyObject *object, Py_ssize_t n, Py_buffer *view, const char *name)
{
    if (PyObject_GetBuffer(object, view, PyBUF_FORMAT | PyBUF_C_CONTIGUOUS) < 0)
        return NULL;
    if (view->itemsize != sizeof(double) || strcmp(view->format, "d")
        || view->len < n * (Py_ssize_t)sizeof(double)) {
        PyErr_Format(PyExc_ValueError, "%s: a float64 array of %zd entries is needed", name, n);
        PyBuffer_Release(view);
        return NULL;
    }
    return view->buf;
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
    FmState eval, out;             /* the integrator's evaluations; outputs */
    Band sd;                       /* the saddle-point matrix of the Newton operator */
    double *op_J;                  /* the element Jacobians of the operator's state */
    Band sd_acc;                   /* and of the accelerations (kept apart: an output between
                                      two steps must not replace the operator) */
    FmError error;
    int trial;
    FmState *failed;               /* the state of the last failure */
    /* the prepared run */
    int *law_kind;                 /* per q entry: 0 polynomial, 1 Python, 2 integrated */
    double *law_coef;              /* x0, v0, a0 per q entry */
    PyObject *law_callback;        /* fills law_values for the Python entries */
    double *law_values;            /* view of the callback's buffer (nq x 3) */
    Py_buffer law_view;
    PyObject *forces;              /* forces(t): reads force_x, force_xd, fills force_f */
    double *force_x, *force_xd, *force_f;
    Py_buffer force_views[3];
    PyObject *progress;
    Py_buffer out_views[N_OUT];
    double *outs[N_OUT];
    int n_outputs;
    double near;
    /* the integrator's predictor memory: the last evaluation */
    int have_last;
    double last_t, *last_x, *last_xd, *last_xdd, *last_q, *last_qd, *last_qdd, *guess;
    long nfev;
    int dynamics;                  /* runs compute stresses, reactions, driving */
} Core;

static void release_run(Core *c)
{
    Py_CLEAR(c->law_callback);
    if (c->law_values) {
        PyBuffer_Release(&c->law_view);
        c->law_values = NULL;
    }
    Py_CLEAR(c->forces);
    if (c->force_f) {
        for (int k = 0; k < 3; k++)
            PyBuffer_Release(&c->force_views[k]);
        c->force_x = c->force_xd = c->force_f = NULL;
    }
    Py_CLEAR(c->progress);
    for (int k = 0; k < N_OUT; k++)
        if (c->outs[k]) {
            PyBuffer_Release(&c->out_views[k]);
            c->outs[k] = NULL;
        }
}

static void Core_dealloc(Core *c)
{
    release_run(c);
    FmModel *m = &c->m;
    void *all[] = {m->etype, m->c_off, m->c_idx, m->d_off, m->d_idx, m->p_off, m->j_off,
                   m->b_off, m->param, m->emass, m->varying, m->S, m->C, m->law_off,
                   m->elastic, m->prestressed, m->sigma0, m->mconst, m->fixed, m->x_fixed,
                   m->q_coord, m->q_def, m->q_input, m->q_dyn, m->q_in, m->rows, m->row_of_def,
                   m->dep, m->free_of, m->dyn_coord, m->dyn_def, m->supported, m->elastic_def,
                   m->nodal_mass, m->f_const, m->dc_src, m->dc_dst, m->dc_rowband,
                   m->dc_colband, m->dc_w, m->dc_colscale, m->dc_rowscale, m->sd_band,
                   m->sd_a_src, m->sd_a_dst, m->sd_c_src, m->sd_c_dst, m->sd_c_dstt,
                   m->sd_m_coord, m->sd_m_dst, m->mult_of_def, c->x0, c->coord_scale,
                   c->lumped_diag, c->consistent, c->op_J, c->law_kind, c->law_coef, c->last_x,
                   c->last_xd, c->last_xdd, c->last_q, c->last_qd, c->last_qdd, c->guess};
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

/* band position of (row, col) in a band of kl, ku */
static int band_at(int row, int col, int kl, int ku) { return kl + ku + row - col + col * (2 * kl + ku + 1); }

static int build_maps(Core *c, const int *dc_row, const int *dc_col, Py_ssize_t ndc,
                      const int *sa_u, const int *sa_v, Py_ssize_t nsa,
                      const int *sm_u, const int *sc_u, const int *sc_v)
{
    FmModel *m = &c->m;
    int kl = 0, ku = 0;
    for (Py_ssize_t k = 0; k < ndc; k++) {
        const int d = m->dc_rowband[dc_row[k]] - m->dc_colband[dc_col[k]];
        kl = d > kl ? d : kl;
        ku = -d > ku ? -d : ku;
    }
    m->dc_kl = kl;
    m->dc_ku = ku;
    m->ndc_map = (int)ndc;
    m->dc_dst = malloc(sizeof(int) * (ndc ? ndc : 1));
    m->dc_w = malloc(sizeof(double) * (ndc ? ndc : 1));
    for (Py_ssize_t k = 0; k < ndc; k++)
        m->dc_dst[k] = band_at(m->dc_rowband[dc_row[k]], m->dc_colband[dc_col[k]], kl, ku);
    /* saddle: symmetric structure */
    int bw = 0;
    for (Py_ssize_t k = 0; k < nsa; k++) {
        const int d = abs(m->sd_band[sa_u[k]] - m->sd_band[sa_v[k]]);
        bw = d > bw ? d : bw;
    }
    for (int k = 0; k < m->nsd_c; k++) {
        const int d = abs(m->sd_band[sc_u[k]] - m->sd_band[sc_v[k]]);
        bw = d > bw ? d : bw;
    }
    m->sd_kl = m->sd_ku = bw;
    m->nsd_a = (int)nsa;
    m->sd_a_dst = malloc(sizeof(int) * (nsa ? nsa : 1));
    for (Py_ssize_t k = 0; k < nsa; k++)
        m->sd_a_dst[k] = band_at(m->sd_band[sa_u[k]], m->sd_band[sa_v[k]], bw, bw);
    m->sd_m_dst = malloc(sizeof(int) * (m->nsd_m ? m->nsd_m : 1));
    for (int k = 0; k < m->nsd_m; k++)
        m->sd_m_dst[k] = band_at(m->sd_band[sm_u[k]], m->sd_band[sm_u[k]], bw, bw);
    m->sd_c_dst = malloc(sizeof(int) * (m->nsd_c ? m->nsd_c : 1));
    m->sd_c_dstt = malloc(sizeof(int) * (m->nsd_c ? m->nsd_c : 1));
    for (int k = 0; k < m->nsd_c; k++) {
        m->sd_c_dst[k] = band_at(m->sd_band[sc_u[k]], m->sd_band[sc_v[k]], bw, bw);
        m->sd_c_dstt[k] = band_at(m->sd_band[sc_v[k]], m->sd_band[sc_u[k]], bw, bw);
    }
    return m->dc_dst && m->dc_w && m->sd_a_dst && m->sd_m_dst && m->sd_c_dst && m->sd_c_dstt
           ? 0 : -1;
}

/* The constant element masses and their weight, and the row scales of D_c from D_x at
 * the reference configuration (THEORY 5; the conditioning of kinematics.py). */
static void reference_terms(Core *c)
{
    FmModel *m = &c->m;
    double cc[64], out[64 * 64];
    m->varying = calloc(m->nel ? m->nel : 1, sizeof(int));
    m->mconst = calloc(m->total_b ? m->total_b : 1, sizeof(double));
    for (int k = 0; k < m->nel; k++) {
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        const int nc = kern->nc;
        double *M = m->mconst + m->b_off[k];
        for (int a = 0; a < nc; a++)
            M[a * nc + a] = c->lumped_diag[m->c_off[k] + a];
        if (!c->consistent[k] || !kern->mass)
            continue;
        if (!kern->mass_constant) {
            m->varying[k] = 1;
            continue;
        }
        for (int a = 0; a < nc; a++)
            cc[a] = c->x0[m->c_idx[m->c_off[k] + a]];
        const double *p = m->param + m->p_off[k];
        kern->mass(cc, p, out);
        for (int a = 0; a < nc * nc; a++)
            M[a] += m->emass[k] * out[a];
        if (m->gravity_on) {
            kern->gravity(cc, p, m->gravity, out);
            for (int a = 0; a < nc; a++)
                m->f_const[m->c_idx[m->c_off[k] + a]] += m->emass[k] * out[a];
        }
    }
    /* row scales: one over the norm of each D_x row with angles scaled by the model size */
    memcpy(c->eval.x, c->x0, sizeof(double) * m->nx);
    for (int k = 0; k < m->nel; k++) {
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        for (int a = 0; a < kern->nc; a++)
            cc[a] = c->x0[m->c_idx[m->c_off[k] + a]];
        kern->deform_jac(cc, m->param + m->p_off[k], out);
        for (int i = 0; i < kern->nd; i++) {
            const int row = m->row_of_def[m->d_idx[m->d_off[k] + i]];
            if (row < 0)
                continue;
            double sum = 0.0;
            for (int a = 0; a < kern->nc; a++) {
                const double v = out[kern->nd + i * kern->nc + a]
                                 * c->coord_scale[m->c_idx[m->c_off[k] + a]];
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
    int *size_fields[] = {&m->nx, &m->ne, &m->nel, &m->nq, &m->nxm, &m->nr, &m->nrigid,
                          &m->nfree, &m->nmult, &m->nd_dyn, &m->ndc, &m->total_j, &m->total_b};
    for (size_t k = 0; k < sizeof(sizes) / sizeof(sizes[0]); k++)
        if (get_int(spec, sizes[k], size_fields[k]) < 0)
            return -1;
    m->ns = m->nfree + m->nmult;
    Py_ssize_t n;
    struct { const char *name; void **field; char format; Py_ssize_t *count; } arrays[] = {
        {"etype", (void **)&m->etype, 'i', NULL}, {"c_off", (void **)&m->c_off, 'i', NULL},
        {"c_idx", (void **)&m->c_idx, 'i', NULL}, {"d_off", (void **)&m->d_off, 'i', NULL},
        {"d_idx", (void **)&m->d_idx, 'i', NULL}, {"p_off", (void **)&m->p_off, 'i', NULL},
        {"j_off", (void **)&m->j_off, 'i', NULL}, {"b_off", (void **)&m->b_off, 'i', NULL},
        {"law_off", (void **)&m->law_off, 'i', NULL}, {"param", (void **)&m->param, 'd', NULL},
        {"emass", (void **)&m->emass, 'd', NULL}, {"S", (void **)&m->S, 'd', NULL},
        {"C", (void **)&m->C, 'd', NULL}, {"elastic", (void **)&m->elastic, 'i', NULL},
        {"prestressed", (void **)&m->prestressed, 'i', NULL},
        {"sigma0", (void **)&m->sigma0, 'd', NULL}, {"x_fixed", (void **)&m->x_fixed, 'd', NULL},
        {"q_coord", (void **)&m->q_coord, 'i', NULL}, {"q_def", (void **)&m->q_def, 'i', NULL},
        {"q_input", (void **)&m->q_input, 'i', NULL}, {"q_dyn", (void **)&m->q_dyn, 'i', NULL},
        {"rows", (void **)&m->rows, 'i', NULL}, {"row_of_def", (void **)&m->row_of_def, 'i', NULL},
        {"dep", (void **)&m->dep, 'i', NULL}, {"free_of", (void **)&m->free_of, 'i', NULL},
        {"dyn_coord", (void **)&m->dyn_coord, 'i', NULL},
        {"dyn_def", (void **)&m->dyn_def, 'i', NULL},
        {"elastic_def", (void **)&m->elastic_def, 'i', NULL},
        {"nodal_mass", (void **)&m->nodal_mass, 'd', NULL},
        {"f_const", (void **)&m->f_const, 'd', NULL},
        {"dc_src", (void **)&m->dc_src, 'i', NULL},
        {"dc_rowband", (void **)&m->dc_rowband, 'i', NULL},
        {"dc_colband", (void **)&m->dc_colband, 'i', NULL},
        {"dc_colscale", (void **)&m->dc_colscale, 'd', NULL},
        {"sd_band", (void **)&m->sd_band, 'i', NULL},
        {"sd_a_src", (void **)&m->sd_a_src, 'i', NULL},
        {"sd_c_src", (void **)&m->sd_c_src, 'i', NULL},
        {"sd_m_coord", (void **)&m->sd_m_coord, 'i', NULL},
        {"mult_of_def", (void **)&m->mult_of_def, 'i', NULL},
        {"x0", (void **)&c->x0, 'd', NULL}, {"coord_scale", (void **)&c->coord_scale, 'd', NULL},
        {"lumped_diag", (void **)&c->lumped_diag, 'd', NULL},
        {"consistent", (void **)&c->consistent, 'i', NULL},
    };
    for (size_t k = 0; k < sizeof(arrays) / sizeof(arrays[0]); k++)
        if (copy_buffer(spec, arrays[k].name, arrays[k].format, arrays[k].field, &n, 1) < 0)
            return -1;
    int *fixed, *supported, *dc_row, *dc_col, *sa_u, *sa_v, *sm_u, *sc_u, *sc_v;
    Py_ssize_t nfixed, nsupported, ndc, nsa, nsm, nsc;
    double *gravity;
    if (copy_buffer(spec, "fixed", 'i', (void **)&fixed, &nfixed, 1) < 0
        || copy_buffer(spec, "supported", 'i', (void **)&supported, &nsupported, 1) < 0
        || copy_buffer(spec, "dc_row", 'i', (void **)&dc_row, &ndc, 1) < 0
        || copy_buffer(spec, "dc_col", 'i', (void **)&dc_col, NULL, 1) < 0
        || copy_buffer(spec, "sd_a_u", 'i', (void **)&sa_u, &nsa, 1) < 0
        || copy_buffer(spec, "sd_a_v", 'i', (void **)&sa_v, NULL, 1) < 0
        || copy_buffer(spec, "sd_m_u", 'i', (void **)&sm_u, &nsm, 1) < 0
        || copy_buffer(spec, "sd_c_u", 'i', (void **)&sc_u, &nsc, 1) < 0
        || copy_buffer(spec, "sd_c_v", 'i', (void **)&sc_v, NULL, 1) < 0
        || copy_buffer(spec, "gravity", 'd', (void **)&gravity, NULL, 1) < 0)
        return -1;
    m->fixed = fixed;
    m->nfixed = (int)nfixed;
    m->supported = supported;
    m->nsupported = (int)nsupported;
    m->nsd_m = (int)nsm;
    m->nsd_c = (int)nsc;
    m->gravity[0] = gravity[0];
    m->gravity[1] = gravity[1];
    m->gravity_on = gravity[0] != 0.0 || gravity[1] != 0.0;
    free(gravity);
    for (int k = 0; k < m->nel; k++)
        if (m->etype[k] < 0 || m->etype[k] >= FM_N_TYPES) {
            PyErr_SetString(PyExc_ValueError, "core spec: unknown element type");
            return -1;
        }
    m->dc_rowscale = malloc(sizeof(double) * (m->nr ? m->nr : 1));
    int failed = build_maps(c, dc_row, dc_col, ndc, sa_u, sa_v, nsa, sm_u, sc_u, sc_v);
    m->tolerance = 1e-10;
    m->max_iterations = 25;
    m->regularity_limit = 1e-4;
    if (!failed && (!m->dc_rowscale || fm_state_init(&c->eval, m) || fm_state_init(&c->out, m)
                    || band_init(&c->sd, m->ns, m->sd_kl, m->sd_ku)
                    || band_init(&c->sd_acc, m->ns, m->sd_kl, m->sd_ku)))
        failed = 1;
    if (!failed) {
        reference_terms(c);
        for (Py_ssize_t k = 0; k < ndc; k++)
            m->dc_w[k] = m->dc_rowscale[dc_row[k]] * m->dc_colscale[dc_col[k]];
    }
    free(dc_row); free(dc_col); free(sa_u); free(sa_v); free(sm_u); free(sc_u); free(sc_v);
    const int nq = m->nq > 0 ? m->nq : 1, nx = m->nx > 0 ? m->nx : 1;
    c->op_J = calloc(m->total_j > 0 ? m->total_j : 1, sizeof(double));
    c->law_kind = calloc(nq, sizeof(int));
    c->law_coef = calloc(3 * nq, sizeof(double));
    double **memory[] = {&c->last_x, &c->last_xd, &c->last_xdd, &c->guess};
    for (size_t k = 0; k < 4; k++)
        *memory[k] = calloc(nx, sizeof(double));
    c->last_q = calloc(nq, sizeof(double));
    c->last_qd = calloc(nq, sizeof(double));
    c->last_qdd = calloc(nq, sizeof(double));
    if (failed || !c->op_J || !c->law_kind || !c->law_coef || !c->last_x || !c->last_xd || !c->last_xdd
        || !c->guess || !c->last_q || !c->last_qd || !c->last_qdd) {
        PyErr_NoMemory();
        return -1;
    }
    memcpy(c->eval.x, c->x0, sizeof(double) * m->nx);
    return 0;
}

/* --- errors ---------------------------------------------------------------------------------- */
static PyObject *status(const FmError *e, int reached, int code, const AlphaResult *r, long nfev)
{
    PyObject *type = NULL, *value = NULL, *traceback = NULL;
    if (code == FM_PYTHON && PyErr_Occurred()) {  /* a callback raised: hand it over */
        PyErr_Fetch(&type, &value, &traceback);
        PyErr_NormalizeException(&type, &value, &traceback);
    }
    PyObject *info = Py_BuildValue("{s:i,s:i,s:d,s:i,s:d,s:i,s:d,s:d,s:d,s:l,s:l,s:l,s:l}",
                         "reached", reached, "code", code, "time", e->time,
                         "iterations", e->iterations, "residual", e->residual, "worst", e->worst,
                         "conditioning", e->conditioning, "limit", e->limit, "step", e->step,
                         "nfev", r ? r->nfev + nfev : nfev, "njev", r ? r->njev : 0,
                         "nlu", r ? r->nlu : 0, "nsteps", r ? r->nsteps : 0);
    if (info)
        PyDict_SetItemString(info, "exception", value ? value : Py_None);
    Py_XDECREF(type);
    Py_XDECREF(value);
    Py_XDECREF(traceback);
    return info;
}

/* Raise CoreError for a failed single evaluation (a pending Python error stays). */
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
    c->error.conditioning = NAN;
    c->error.limit = NAN;
    c->error.time = NAN;
}

/* --- laws, loads, progress ------------------------------------------------------------------- */
/* q, qd and the prescribed entries of qdd at time t from the laws; integrated entries from
 * (q_d, qd_d, qdd_d) when given (qdd_d NULL: zero). */
static int compose(Core *c, FmState *s, double t, const double *q_d, const double *qd_d,
                   const double *qdd_d)
{
    const FmModel *m = &c->m;
    int python = 0;
    for (int j = 0; j < m->nq; j++)
        python |= c->law_kind[j] == 1;
    if (python) {
        PyObject *done = PyObject_CallFunction(c->law_callback, "d", t);
        if (!done)
            return FM_PYTHON;
        Py_DECREF(done);
    }
    int d = 0;
    for (int j = 0; j < m->nq; j++) {
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

/* --- outputs ----------------------------------------------------------------------------------- */
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

/* Stresses of every deformation, reactions and driving loads of a state whose
 * accelerations are known (THEORY 8); `free_dynamic`: the dynamic entries move freely
 * (a simulation), so their driving load is zero. */
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
    if (drive && free_dynamic)
        for (int j = 0; j < m->nd_dyn; j++)
            drive[m->q_dyn[j]] = 0.0;
    store(c, k, s);
    return FM_OK;
}

/* --- the kinematic and inverse runs --------------------------------------------------------- */
static PyObject *Core_kinematic_run(Core *c, PyObject *args)
{
    PyObject *times_object;
    if (!PyArg_ParseTuple(args, "O", &times_object))
        return NULL;
    Py_buffer tv;
    const FmModel *m = &c->m;
    const double *times = readable(times_object, 0, &tv, "times");
    if (!times)
        return NULL;
    const int n = (int)(tv.len / sizeof(double));
    reset_error(c);
    FmState *s = &c->eval;
    int code = FM_OK, k;
    for (k = 0; k < n && !code; k++) {
        const double t = times[k];
        if ((code = compose(c, s, t, NULL, NULL, NULL)))
            break;
        if (k) {                             /* first-order predictor, x + F_q dq (THEORY 3) */
            const double dt = t - times[k - 1];
            for (int i = 0; i < m->nx; i++)
                c->guess[i] = s->x[i] + dt * s->xd[i];
        } else {
            memcpy(c->guess, c->x0, sizeof(double) * m->nx);
        }
        if ((code = fm_kinematics(m, s, t, c->guess, m->tolerance, 0, 1, &c->error)))
            break;
        if (c->dynamics) {
            if ((code = dynamics_of(c, s, k, 0, 0)))
                break;
        } else {
            store(c, k, s);
        }
        if ((k + 1) % 256 == 0 && (code = report(c, t)))
            break;
    }
    if (!code)
        report(c, n ? times[n - 1] : 0.0);
    PyBuffer_Release(&tv);
    c->failed = s;
    return status(&c->error, k, code, NULL, 0);
}

/* --- the mechanical system for generalized-alpha -------------------------------------------- */
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
        memcpy(c->guess, c->x0, sizeof(double) * m->nx);
        return;
    }
    const double dt = t - c->last_t;
    double *change = c->out.w6;              /* scratch of the other state */
    memset(change, 0, sizeof(double) * m->nx);
    double *missed = c->out.w5;
    for (int j = 0; j < m->nq; j++)
        missed[j] = s->q[j] - (c->last_q[j] + dt * c->last_qd[j] + 0.5 * dt * dt * c->last_qdd[j]);
    for (int k = 0; k < m->nxm; k++)
        change[m->q_coord[k]] = missed[k];
    fm_dependent_rates(m, &c->eval, change, missed + m->nxm, NULL);
    for (int i = 0; i < m->nx; i++)
        c->guess[i] = c->last_x[i] + dt * c->last_xd[i] + 0.5 * dt * dt * c->last_xdd[i]
                      + change[i];
}

static int mech_accelerations(void *context, double t, const double *q, const double *v,
                              double *a)
{
    Core *c = context;
    const FmModel *m = &c->m;
    FmState *s = &c->eval;
    int code;
    c->nfev++;
    if ((code = compose(c, s, t, q, v, NULL)))
        return code;
    predict(c, s, t);
    c->failed = s;
    if ((code = fm_kinematics(m, s, t, c->guess, c->near, 0, 0, &c->error)))
        return code;
    const double *loads;
    if ((code = user_loads(c, s, &loads)))
        return code;
    /* the predictor extrapolates linearly from here: xdd above lacks qdd_d */
    remember(c, s, 1);
    if ((code = fm_accelerations(m, s, &c->sd_acc, loads, &c->error)))
        return code;
    for (int j = 0; j < m->nd_dyn; j++)
        a[j] = s->qdd[m->q_dyn[j]];
    return FM_OK;
}

static int mech_residual(void *context, double t, const double *q, const double *v,
                         const double *a, double *r)
{
    Core *c = context;
    const FmModel *m = &c->m;
    FmState *s = &c->eval;
    int code;
    c->nfev++;
    if ((code = compose(c, s, t, q, v, a)))
        return code;
    predict(c, s, t);
    c->failed = s;
    if ((code = fm_kinematics(m, s, t, c->guess, c->near, 0, 0, &c->error))) {
        c->trial = code != FM_PYTHON;        /* a smaller step may get past it */
        return code;
    }
    remember(c, s, 0);
    const double *loads;
    if ((code = user_loads(c, s, &loads)))
        return code;
    fm_stresses(m, s);
    fm_inertia(m, s);
    fm_nodal_force(m, s, loads);
    fm_reduced_residual(m, s, r, s->w6);
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

/* The full state at output k from the integrated (q_d, qd_d): positions from the last
 * evaluation's solution and its D_c (chord steps, then D_c at the solution), the
 * accelerations, stresses and reactions. */
static int mech_output(void *context, int k, double t, const double *q, const double *v,
                       const double *a)
{
    Core *c = context;
    const FmModel *m = &c->m;
    FmState *s = &c->out;
    int code;
    (void)a;
    c->failed = s;
    fm_state_copy(s, &c->eval, m);
    if ((code = compose(c, s, t, q, v, NULL)))
        return code;
    if ((code = fm_kinematics(m, s, t, c->eval.x, m->tolerance, c->eval.has_factor, 0, &c->error)))
        return code;
    return dynamics_of(c, s, k, 1, 1);
}

static PyObject *Core_alpha_run(Core *c, PyObject *args, PyObject *kwds)
{
    PyObject *times_object, *q0_object, *v0_object;
    AlphaOptions opt = {0};
    static char *keywords[] = {"times", "q0", "v0", "step", "rho_inf", "rtol", "atol",
                               "iterations", "renew_every", "near", NULL};
    double near = 0.0;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOddddiid", keywords, &times_object,
                                     &q0_object, &v0_object, &opt.step, &opt.rho_inf, &opt.rtol,
                                     &opt.atol, &opt.iterations, &opt.renew_every, &near))
        return NULL;
    const FmModel *m = &c->m;
    Py_buffer tv, qv, vv;
    const double *times = readable(times_object, 0, &tv, "times");
    if (!times)
        return NULL;
    const double *q0 = readable(q0_object, m->nd_dyn, &qv, "q0");
    if (!q0) {
        PyBuffer_Release(&tv);
        return NULL;
    }
    const double *v0 = readable(v0_object, m->nd_dyn, &vv, "v0");
    if (!v0) {
        PyBuffer_Release(&tv);
        PyBuffer_Release(&qv);
        return NULL;
    }
    reset_error(c);
    c->near = near;
    c->have_last = 0;
    c->nfev = 0;
    AlphaSystem sys = {m->nd_dyn, c, mech_accelerations, mech_residual, mech_renew, mech_apply,
                       mech_output, &c->error, &c->trial};
    opt.progress = report;
    opt.progress_context = c;
    AlphaResult result = alpha_run(&sys, times, (int)(tv.len / sizeof(double)), q0, v0, &opt);
    PyBuffer_Release(&tv);
    PyBuffer_Release(&qv);
    PyBuffer_Release(&vv);
    return status(&c->error, result.reached, result.status, &result, c->nfev);
}

/* --- single evaluations for scipy's integrators ---------------------------------------------- */
static PyObject *Core_accelerations(Core *c, PyObject *args)
{
    double t;
    PyObject *y_object, *out_object;
    if (!PyArg_ParseTuple(args, "dOO", &t, &y_object, &out_object))
        return NULL;
    const int nd = c->m.nd_dyn;
    Py_buffer yv, ov;
    const double *y = readable(y_object, 2 * nd, &yv, "y");
    if (!y)
        return NULL;
    double *out = writable(out_object, nd, &ov, "out");
    if (!out) {
        PyBuffer_Release(&yv);
        return NULL;
    }
    reset_error(c);
    int code = mech_accelerations(c, t, y, y + nd, out);
    PyBuffer_Release(&yv);
    PyBuffer_Release(&ov);
    if (code)
        return raise_core(c, code);
    Py_RETURN_NONE;
}

/* residual(t, y, a, r): the reduced residual of the equations of motion at y = [q_d, qd_d]
 * and dynamic accelerations a (the state generalized-alpha evaluates) */
static PyObject *Core_residual(Core *c, PyObject *args)
{
    double t;
    PyObject *yo, *ao, *ro;
    if (!PyArg_ParseTuple(args, "dOOO", &t, &yo, &ao, &ro))
        return NULL;
    const int nd = c->m.nd_dyn;
    Py_buffer v[3];
    const double *y = readable(yo, 2 * nd, &v[0], "y");
    if (!y)
        return NULL;
    const double *a = readable(ao, nd, &v[1], "a");
    if (!a) {
        PyBuffer_Release(&v[0]);
        return NULL;
    }
    double *r = writable(ro, nd, &v[2], "r");
    if (!r) {
        PyBuffer_Release(&v[0]);
        PyBuffer_Release(&v[1]);
        return NULL;
    }
    reset_error(c);
    int code = mech_residual(c, t, y, y + nd, a, r);
    for (int k = 0; k < 3; k++)
        PyBuffer_Release(&v[k]);
    if (code)
        return raise_core(c, code);
    Py_RETURN_NONE;
}

/* correction(c_q, c_v, r, da): Newton's da = -S^-1 r with S = Mbar + c_q K + c_v C at the
 * state the last residual evaluated */
static PyObject *Core_correction(Core *c, PyObject *args)
{
    double c_q, c_v;
    PyObject *ro, *dao;
    if (!PyArg_ParseTuple(args, "ddOO", &c_q, &c_v, &ro, &dao))
        return NULL;
    const int nd = c->m.nd_dyn;
    Py_buffer v[2];
    const double *r = readable(ro, nd, &v[0], "r");
    if (!r)
        return NULL;
    double *da = writable(dao, nd, &v[1], "da");
    if (!da) {
        PyBuffer_Release(&v[0]);
        return NULL;
    }
    reset_error(c);
    int code = mech_renew(c, c_q, c_v);
    if (!code)
        code = mech_apply(c, r, da);
    PyBuffer_Release(&v[0]);
    PyBuffer_Release(&v[1]);
    if (code)
        return raise_core(c, code);
    Py_RETURN_NONE;
}

static PyObject *Core_output(Core *c, PyObject *args)
{
    int k;
    double t;
    PyObject *y_object;
    if (!PyArg_ParseTuple(args, "idO", &k, &t, &y_object))
        return NULL;
    const int nd = c->m.nd_dyn;
    Py_buffer yv;
    const double *y = readable(y_object, 2 * nd, &yv, "y");
    if (!y)
        return NULL;
    if (k < 0 || k >= c->n_outputs) {
        PyBuffer_Release(&yv);
        PyErr_SetString(PyExc_IndexError, "output index out of range");
        return NULL;
    }
    reset_error(c);
    int code = mech_output(c, k, t, y, y + nd, NULL);
    PyBuffer_Release(&yv);
    if (code)
        return raise_core(c, code);
    Py_RETURN_NONE;
}

static PyObject *Core_reset(Core *c, PyObject *unused)
{
    (void)unused;
    c->have_last = 0;
    c->nfev = 0;
    Py_RETURN_NONE;
}

/* --- preparing a run ---------------------------------------------------------------------------- */
static PyObject *Core_prepare(Core *c, PyObject *args, PyObject *kwds)
{
    PyObject *kind, *coef, *callback = Py_None, *values = Py_None, *forces = Py_None;
    PyObject *fx = Py_None, *fxd = Py_None, *ff = Py_None, *outputs, *progress = Py_None;
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
    Py_buffer view;
    if (PyObject_GetBuffer(kind, &view, PyBUF_FORMAT | PyBUF_C_CONTIGUOUS) < 0)
        return NULL;
    if (view.itemsize != sizeof(int) || view.len != (Py_ssize_t)sizeof(int) * m->nq) {
        PyBuffer_Release(&view);
        PyErr_SetString(PyExc_ValueError, "law_kind: an int32 array over q is needed");
        return NULL;
    }
    memcpy(c->law_kind, view.buf, sizeof(int) * m->nq);
    PyBuffer_Release(&view);
    const double *co = readable(coef, 3 * m->nq, &view, "law_coef");
    if (!co)
        return NULL;
    memcpy(c->law_coef, co, sizeof(double) * 3 * m->nq);
    PyBuffer_Release(&view);
    int integrated = 0;
    for (int j = 0; j < m->nq; j++)
        integrated += c->law_kind[j] == 2;
    if (integrated && integrated != m->nd_dyn) {
        PyErr_SetString(PyExc_ValueError, "law_kind: the integrated entries must be the "
                                          "dynamic ones");
        return NULL;
    }
    if (callback != Py_None) {
        if (!(c->law_values = writable(values, 3 * m->nq, &c->law_view, "law_values")))
            return NULL;
        Py_INCREF(callback);
        c->law_callback = callback;
    }
    if (forces != Py_None) {
        double **views[] = {&c->force_x, &c->force_xd, &c->force_f};
        PyObject *objects[] = {fx, fxd, ff};
        for (int k = 0; k < 3; k++)
            if (!(*views[k] = writable(objects[k], m->nx, &c->force_views[k], "forces"))) {
                for (int j = 0; j < k; j++)
                    PyBuffer_Release(&c->force_views[j]);
                c->force_x = c->force_xd = c->force_f = NULL;
                return NULL;
            }
        Py_INCREF(forces);
        c->forces = forces;
    }
    if (progress != Py_None) {
        Py_INCREF(progress);
        c->progress = progress;
    }
    const int sizes[N_OUT] = {m->nx, m->nx, m->nx, m->ne, m->ne, m->ne, m->nq, m->nq, m->nq,
                              m->ne, m->nx, m->nq};
    for (int o = 0; o < N_OUT; o++) {
        PyObject *array = PyDict_GetItemString(outputs, OUT_NAMES[o]);
        if (!array || array == Py_None)
            continue;
        if (!(c->outs[o] = writable(array, (Py_ssize_t)n_outputs * sizes[o], &c->out_views[o],
                                    OUT_NAMES[o]))) {
            release_run(c);
            return NULL;
        }
    }
    c->n_outputs = n_outputs;
    c->dynamics = dynamics;
    c->have_last = 0;
    Py_RETURN_NONE;
}

static PyObject *Core_release(Core *c, PyObject *unused)
{
    (void)unused;
    release_run(c);
    Py_RETURN_NONE;
}

/* --- per-state functions ------------------------------------------------------------------------ */
/* elements(x, xd, e, J, qv, H): the element values at x (xd for qv; NULL outputs skipped) */
static PyObject *Core_elements(Core *c, PyObject *args)
{
    PyObject *xo, *xdo, *eo, *jo, *qo, *ho;
    if (!PyArg_ParseTuple(args, "OOOOOO", &xo, &xdo, &eo, &jo, &qo, &ho))
        return NULL;
    const FmModel *m = &c->m;
    Py_buffer v[6];
    int held[6] = {0};
    PyObject *result = NULL;
    const double *x = readable(xo, m->nx, &v[0], "x");
    if (!x)
        return NULL;
    held[0] = 1;
    const double *xd = NULL;
    if (xdo != Py_None) {
        if (!(xd = readable(xdo, m->nx, &v[1], "xd")))
            goto done;
        held[1] = 1;
    }
    int hsize = 0;
    for (int k = 0; k < m->nel; k++) {
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        hsize += kern->nd * kern->nc * kern->nc;
    }
    double *e = NULL, *J = NULL, *qv = NULL, *H = NULL;
    PyObject *objects[] = {eo, jo, qo, ho};
    double **targets[] = {&e, &J, &qv, &H};
    const int sizes[] = {m->ne, m->total_j, m->ne, hsize};
    for (int k = 0; k < 4; k++) {
        if (objects[k] == Py_None)
            continue;
        if (!(*targets[k] = writable(objects[k], sizes[k], &v[2 + k], "elements")))
            goto done;
        held[2 + k] = 1;
    }
    double cc[64], vv[64], out[64 * 65];
    int h_at = 0;
    for (int k = 0; k < m->nel; k++) {
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        const int nc = kern->nc, nd = kern->nd;
        const double *p = m->param + m->p_off[k];
        for (int a = 0; a < nc; a++) {
            cc[a] = x[m->c_idx[m->c_off[k] + a]];
            vv[a] = xd ? xd[m->c_idx[m->c_off[k] + a]] : 0.0;
        }
        kern->deform_jac(cc, p, out);
        for (int i = 0; i < nd; i++)
            if (e)
                e[m->d_idx[m->d_off[k] + i]] = out[i];
        if (J)
            memcpy(J + m->j_off[k], out + nd, sizeof(double) * nd * nc);
        if (qv && xd) {
            kern->quadratic(cc, vv, p, out);
            for (int i = 0; i < nd; i++)
                qv[m->d_idx[m->d_off[k] + i]] = out[i];
        }
        if (H) {
            kern->hessian(cc, p, H + h_at);
        }
        h_at += nd * nc * nc;
    }
    result = Py_None;
    Py_INCREF(result);
done:
    for (int k = 0; k < 6; k++)
        if (held[k])
            PyBuffer_Release(&v[k]);
    return result;
}

/* mass_matrix(x, xd, M, h, g): the dense mass matrix (nx x nx), the velocity-dependent
 * inertia h (nx) and the gravity load of the elements and nodes (nx) at (x, xd) */
static PyObject *Core_mass_matrix(Core *c, PyObject *args)
{
    PyObject *xo, *xdo, *mo, *ho, *go;
    if (!PyArg_ParseTuple(args, "OOOOO", &xo, &xdo, &mo, &ho, &go))
        return NULL;
    const FmModel *m = &c->m;
    FmState *s = &c->out;
    Py_buffer v[5];
    const double *x = readable(xo, m->nx, &v[0], "x");
    if (!x)
        return NULL;
    const double *xd = readable(xdo, m->nx, &v[1], "xd");
    if (!xd) {
        PyBuffer_Release(&v[0]);
        return NULL;
    }
    double *M = writable(mo, (Py_ssize_t)m->nx * m->nx, &v[2], "M");
    double *h = M ? writable(ho, m->nx, &v[3], "h") : NULL;
    double *g = h ? writable(go, m->nx, &v[4], "g") : NULL;
    if (!g) {
        for (int k = 0; k < 2 + (M != NULL) + (h != NULL); k++)
            PyBuffer_Release(&v[k]);
        return NULL;
    }
    memcpy(s->x, x, sizeof(double) * m->nx);
    memcpy(s->xd, xd, sizeof(double) * m->nx);
    fm_inertia(m, s);
    memset(M, 0, sizeof(double) * m->nx * m->nx);
    memset(h, 0, sizeof(double) * m->nx);
    memcpy(g, m->f_const, sizeof(double) * m->nx);
    for (int i = 0; i < m->nx; i++)
        M[i * m->nx + i] += m->nodal_mass[i];
    for (int k = 0; k < m->nel; k++) {
        const int nc = m->c_off[k + 1] - m->c_off[k];
        const int *ci = m->c_idx + m->c_off[k];
        for (int a = 0; a < nc; a++) {
            h[ci[a]] += s->hvec[m->c_off[k] + a];
            g[ci[a]] += s->gvec[m->c_off[k] + a];
            for (int b = 0; b < nc; b++)
                M[ci[a] * m->nx + ci[b]] += s->blocks[m->b_off[k] + a * nc + b];
        }
    }
    for (int k = 0; k < 5; k++)
        PyBuffer_Release(&v[k]);
    Py_RETURN_NONE;
}

/* positions(t, q, guess, x_out, near): the position solve; returns (iterations, residual)
 * of the solve is not tracked here: x_out is the solution */
static PyObject *Core_positions(Core *c, PyObject *args)
{
    double t, near;
    PyObject *qo, *go, *xo;
    if (!PyArg_ParseTuple(args, "dOOOd", &t, &qo, &go, &xo, &near))
        return NULL;
    const FmModel *m = &c->m;
    FmState *s = &c->eval;
    Py_buffer v[3];
    const double *q = readable(qo, m->nq, &v[0], "q");
    if (!q)
        return NULL;
    const double *guess = readable(go, m->nx, &v[1], "guess");
    if (!guess) {
        PyBuffer_Release(&v[0]);
        return NULL;
    }
    double *x = writable(xo, m->nx, &v[2], "x");
    if (!x) {
        PyBuffer_Release(&v[0]);
        PyBuffer_Release(&v[1]);
        return NULL;
    }
    reset_error(c);
    c->failed = s;
    memcpy(s->q, q, sizeof(double) * m->nq);
    int code = fm_positions(m, s, t, guess, near, 0, 1, &c->error);
    if (!code)
        memcpy(x, s->x, sizeof(double) * m->nx);
    for (int k = 0; k < 3; k++)
        PyBuffer_Release(&v[k]);
    if (code)
        return raise_core(c, code);
    return Py_BuildValue("d", fm_conditioning(m, s));
}

/* state(t, q, qd, qdd, guess, x, xd, xdd, e, ed, edd): kinematics of one state */
static PyObject *Core_state(Core *c, PyObject *args)
{
    double t;
    PyObject *in[4], *outs[6];
    if (!PyArg_ParseTuple(args, "dOOOOOOOOOO", &t, &in[0], &in[1], &in[2], &in[3], &outs[0],
                          &outs[1], &outs[2], &outs[3], &outs[4], &outs[5]))
        return NULL;
    const FmModel *m = &c->m;
    FmState *s = &c->eval;
    const int in_sizes[4] = {m->nq, m->nq, m->nq, m->nx};
    const int out_sizes[6] = {m->nx, m->nx, m->nx, m->ne, m->ne, m->ne};
    Py_buffer views[10];
    const double *vectors[4];
    double *targets[6];
    int held = 0;
    PyObject *result = NULL;
    for (int k = 0; k < 4; k++) {
        if (!(vectors[k] = readable(in[k], in_sizes[k], &views[held], "state")))
            goto done;
        held++;
    }
    for (int k = 0; k < 6; k++) {
        if (!(targets[k] = writable(outs[k], out_sizes[k], &views[held], "state")))
            goto done;
        held++;
    }
    reset_error(c);
    c->failed = s;
    memcpy(s->q, vectors[0], sizeof(double) * m->nq);
    memcpy(s->qd, vectors[1], sizeof(double) * m->nq);
    memcpy(s->qdd, vectors[2], sizeof(double) * m->nq);
    int code = fm_kinematics(m, s, t, vectors[3], m->tolerance, 0, 1, &c->error);
    if (code) {
        raise_core(c, code);
        goto done;
    }
    const double *from[6] = {s->x, s->xd, s->xdd, s->e, s->ed, s->edd};
    for (int k = 0; k < 6; k++)
        memcpy(targets[k], from[k], sizeof(double) * out_sizes[k]);
    result = Py_None;
    Py_INCREF(result);
done:
    for (int k = 0; k < held; k++)
        PyBuffer_Release(&views[k]);
    return result;
}

/* settings(tolerance, max_iterations, regularity_limit) of the position solve */
static PyObject *Core_settings(Core *c, PyObject *args)
{
    if (!PyArg_ParseTuple(args, "did", &c->m.tolerance, &c->m.max_iterations,
                          &c->m.regularity_limit))
        return NULL;
    Py_RETURN_NONE;
}

/* factor(x): D_c at x (from the element Jacobians there); returns its conditioning */
static PyObject *Core_factor(Core *c, PyObject *args)
{
    PyObject *xo;
    if (!PyArg_ParseTuple(args, "O", &xo))
        return NULL;
    const FmModel *m = &c->m;
    FmState *s = &c->eval;
    Py_buffer v;
    const double *x = readable(xo, m->nx, &v, "x");
    if (!x)
        return NULL;
    memcpy(s->x, x, sizeof(double) * m->nx);
    PyBuffer_Release(&v);
    double cc[64], out[64 * 65];
    for (int k = 0; k < m->nel; k++) {
        const FmKernels *kern = &FM_KERNELS[m->etype[k]];
        for (int a = 0; a < kern->nc; a++)
            cc[a] = x[m->c_idx[m->c_off[k] + a]];
        kern->deform_jac(cc, m->param + m->p_off[k], out);
        memcpy(s->J + m->j_off[k], out + kern->nd, sizeof(double) * kern->nd * kern->nc);
    }
    Band *b = &s->dc;
    s->has_factor = 0;
    if (!m->nr)
        return Py_BuildValue("d", 1.0);
    memset(b->ab, 0, sizeof(double) * (size_t)b->ldab * b->n);
    for (int k = 0; k < m->ndc_map; k++)
        b->ab[m->dc_dst[k]] = s->J[m->dc_src[k]] * m->dc_w[k];
    if (band_factor(b) || !(band_min_pivot(b) > 0.0) || !isfinite(band_min_pivot(b)))
        return Py_BuildValue("d", 0.0);
    s->has_factor = 1;
    s->conditioning = NAN;
    s->cond_column = -1;                     /* a configuration of its own: estimate in full */
    return Py_BuildValue("d", fm_conditioning(m, s));
}

/* solve(rhs, transposed): D_c^-1 rhs (rows -> columns) or D_c^-T rhs, in place, for rhs of
 * shape (k, nr) */
static PyObject *Core_solve(Core *c, PyObject *args)
{
    PyObject *ro;
    int transposed;
    if (!PyArg_ParseTuple(args, "Op", &ro, &transposed))
        return NULL;
    const FmModel *m = &c->m;
    FmState *s = &c->eval;
    if (!s->has_factor) {
        PyErr_SetString(PyExc_RuntimeError, "D_c is not factorised");
        return NULL;
    }
    Py_buffer v;
    double *r = writable(ro, 0, &v, "rhs");
    if (!r)
        return NULL;
    const int count = m->nr ? (int)(v.len / sizeof(double) / m->nr) : 0;
    double *work = s->w2;
    for (int k = 0; k < count; k++) {
        double *x = r + (size_t)k * m->nr;
        if (transposed) {
            for (int j = 0; j < m->nr; j++)
                work[m->dc_colband[j]] = m->dc_colscale[j] * x[j];
            band_solve_t(&s->dc, work);
            for (int i = 0; i < m->nr; i++)
                x[i] = m->dc_rowscale[i] * work[m->dc_rowband[i]];
        } else {
            for (int i = 0; i < m->nr; i++)
                work[m->dc_rowband[i]] = m->dc_rowscale[i] * x[i];
            band_solve(&s->dc, work);
            for (int j = 0; j < m->nr; j++)
                x[j] = m->dc_colscale[j] * work[m->dc_colband[j]];
        }
    }
    PyBuffer_Release(&v);
    Py_RETURN_NONE;
}

/* failed_x(out): the configuration of the last failure (nx) */
static PyObject *Core_failed_x(Core *c, PyObject *args)
{
    PyObject *xo;
    if (!PyArg_ParseTuple(args, "O", &xo))
        return NULL;
    Py_buffer v;
    double *x = writable(xo, c->m.nx, &v, "x");
    if (!x)
        return NULL;
    memcpy(x, (c->failed ? c->failed : &c->eval)->x, sizeof(double) * c->m.nx);
    PyBuffer_Release(&v);
    Py_RETURN_NONE;
}

static PyObject *Core_bands(Core *c, PyObject *unused)
{
    (void)unused;
    return Py_BuildValue("{s:i,s:i,s:i,s:i,s:i,s:i}", "dc_n", c->m.nr, "dc_kl", c->m.dc_kl,
                         "dc_ku", c->m.dc_ku, "saddle_n", c->m.ns, "saddle_kl", c->m.sd_kl,
                         "saddle_ku", c->m.sd_ku);
}

static PyMethodDef Core_methods[] = {
    {"prepare", (PyCFunction)(void (*)(void))Core_prepare, METH_VARARGS | METH_KEYWORDS,
     "Prepare a run: laws, loads, output arrays, solver settings."},
    {"release", (PyCFunction)Core_release, METH_NOARGS, "Let go of the prepared run's arrays."},
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
    {"reset", (PyCFunction)Core_reset, METH_NOARGS, "Forget the last evaluation."},
    {"elements", (PyCFunction)Core_elements, METH_VARARGS,
     "elements(x, xd, e, J, qv, H): element values at x."},
    {"mass_matrix", (PyCFunction)Core_mass_matrix, METH_VARARGS,
     "mass_matrix(x, xd, M, h, g): mass matrix, velocity inertia and gravity load."},
    {"positions", (PyCFunction)Core_positions, METH_VARARGS,
     "positions(t, q, guess, x, near): the position solve; returns the conditioning."},
    {"factor", (PyCFunction)Core_factor, METH_VARARGS, "factor(x): D_c at x; its conditioning."},
    {"state", (PyCFunction)Core_state, METH_VARARGS,
     "state(t, q, qd, qdd, guess, x, xd, xdd, e, ed, edd): kinematics of one state."},
    {"settings", (PyCFunction)Core_settings, METH_VARARGS,
     "settings(tolerance, max_iterations, regularity_limit) of the position solve."},
    {"solve", (PyCFunction)Core_solve, METH_VARARGS, "solve(rhs, transposed): with D_c."},
    {"bands", (PyCFunction)Core_bands, METH_NOARGS, "Sizes and bands of the square systems."},
    {"failed_x", (PyCFunction)Core_failed_x, METH_VARARGS,
     "failed_x(out): the configuration of the last failure."},
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

/* --- generalized-alpha for a Python y' = fun(t, y) ----------------------------------------- */
typedef struct {
    PyObject *fun, *simulation_error, *pending_type, *pending_value, *pending_tb;
    int m;
    double rtol, atol;
    double *y, *f, *jac, *lastq, *lastv, *lasta, last_t;
    Band lu;
    double *y_out;
    int trial;
    long nfev;
    FmError error;
} PySystem;

/* a = fun(t, [q; v])[m:]; a SimulationError is kept as a trial failure */
static int py_call(PySystem *p, double t, const double *q, const double *v, double *a)
{
    PyObject *array_module = NULL, *y = NULL, *result = NULL;
    int code = FM_OK;
    memcpy(p->y, q, sizeof(double) * p->m);
    memcpy(p->y + p->m, v, sizeof(double) * p->m);
    PyObject *list = PyList_New(2 * p->m);
    if (!list)
        return FM_PYTHON;
    for (int i = 0; i < 2 * p->m; i++)
        PyList_SET_ITEM(list, i, PyFloat_FromDouble(p->y[i]));
    array_module = PyImport_ImportModule("numpy");
    if (array_module)
        y = PyObject_CallMethod(array_module, "array", "O", list);
    Py_DECREF(list);
    p->nfev++;
    if (y)
        result = PyObject_CallFunction(p->fun, "dO", t, y);
    if (result) {
        PyObject *seq = PySequence_Fast(result, "fun must return a sequence");
        if (seq && PySequence_Fast_GET_SIZE(seq) == 2 * p->m) {
            for (int i = 0; i < p->m; i++)
                a[i] = PyFloat_AsDouble(PySequence_Fast_GET_ITEM(seq, p->m + i));
            if (PyErr_Occurred())
                code = FM_PYTHON;
        } else if (seq) {
            PyErr_SetString(PyExc_ValueError, "fun returned a state of the wrong size");
            code = FM_PYTHON;
        } else {
            code = FM_PYTHON;
        }
        Py_XDECREF(seq);
    } else {
        code = FM_PYTHON;
    }
    Py_XDECREF(result);
    Py_XDECREF(y);
    Py_XDECREF(array_module);
    if (code == FM_PYTHON && p->simulation_error
        && PyErr_ExceptionMatches(p->simulation_error)) {
        Py_XDECREF(p->pending_type);
        Py_XDECREF(p->pending_value);
        Py_XDECREF(p->pending_tb);
        PyErr_Fetch(&p->pending_type, &p->pending_value, &p->pending_tb);
        p->trial = 1;
        p->error.code = FM_PYTHON;
    }
    return code;
}

static int py_accelerations(void *context, double t, const double *q, const double *v, double *a)
{
    PySystem *p = context;
    int code = py_call(p, t, q, v, a);
    if (!code) {
        p->last_t = t;
        memcpy(p->lastq, q, sizeof(double) * p->m);
        memcpy(p->lastv, v, sizeof(double) * p->m);
        memcpy(p->lasta, a, sizeof(double) * p->m);
    }
    return code;
}

static int py_residual(void *context, double t, const double *q, const double *v,
                       const double *a, double *r)
{
    PySystem *p = context;
    int code = py_accelerations(context, t, q, v, r);
    if (code)
        return code;
    for (int i = 0; i < p->m; i++)
        r[i] = a[i] - r[i];
    return FM_OK;
}

/* I - c_q da/dq - c_v da/dv by forward differences at the state evaluated last */
static int py_renew(void *context, double c_q, double c_v)
{
    PySystem *p = context;
    const int m = p->m;
    double *shifted = calloc(2 * m, sizeof(double)), *column = calloc(m, sizeof(double));
    int code = shifted && column ? FM_OK : FM_NO_MEMORY;
    memset(p->lu.ab, 0, sizeof(double) * (size_t)p->lu.ldab * p->lu.n);
    for (int j = 0; j < 2 * m && !code; j++) {
        memcpy(shifted, p->lastq, sizeof(double) * m);
        memcpy(shifted + m, p->lastv, sizeof(double) * m);
        const double value = shifted[j], size = fabs(value) > p->atol / p->rtol
                                                ? fabs(value) : p->atol / p->rtol;
        const double delta = 1e-6 * size;
        shifted[j] = value + delta;
        int trial = p->trial;
        if ((code = py_call(p, p->last_t, shifted, shifted + m, column)))
            break;
        p->trial = trial;
        const double weight = j < m ? c_q : c_v;
        for (int i = 0; i < m; i++) {
            const double entry = -weight * (column[i] - p->lasta[i]) / delta;
            p->lu.ab[(size_t)(p->lu.kl + p->lu.ku + i - (j % m)) + (size_t)(j % m) * p->lu.ldab]
                += entry;
        }
    }
    for (int i = 0; i < m && !code; i++)
        p->lu.ab[(size_t)(p->lu.kl + p->lu.ku) + (size_t)i * p->lu.ldab] += 1.0;
    free(shifted);
    free(column);
    if (!code && band_factor(&p->lu))
        code = FM_STEP_FAILED;
    return code;
}

static int py_apply(void *context, const double *r, double *da)
{
    PySystem *p = context;
    for (int i = 0; i < p->m; i++)
        da[i] = -r[i];
    band_solve(&p->lu, da);
    return FM_OK;
}

static int py_output(void *context, int k, double t, const double *q, const double *v,
                     const double *a)
{
    PySystem *p = context;
    (void)t;
    (void)a;
    memcpy(p->y_out + (size_t)k * 2 * p->m, q, sizeof(double) * p->m);
    memcpy(p->y_out + (size_t)k * 2 * p->m + p->m, v, sizeof(double) * p->m);
    return FM_OK;
}

static int py_progress(void *context, double t)
{
    (void)context;
    (void)t;
    return PyErr_CheckSignals() < 0 ? FM_PYTHON : FM_OK;
}

/* alpha_ode(fun, times, y0, y_out, step, rho_inf, rtol, atol, iterations, renew_every) */
static PyObject *alpha_ode(PyObject *self, PyObject *args, PyObject *kwds)
{
    PyObject *fun, *times_object, *y0_object, *out_object;
    AlphaOptions opt = {0};
    static char *keywords[] = {"fun", "times", "y0", "y_out", "step", "rho_inf", "rtol", "atol",
                               "iterations", "renew_every", NULL};
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kwds, "OOOOddddii", keywords, &fun, &times_object,
                                     &y0_object, &out_object, &opt.step, &opt.rho_inf, &opt.rtol,
                                     &opt.atol, &opt.iterations, &opt.renew_every))
        return NULL;
    Py_buffer tv, yv, ov;
    const double *times = readable(times_object, 0, &tv, "times");
    if (!times)
        return NULL;
    const double *y0 = readable(y0_object, 0, &yv, "y0");
    if (!y0) {
        PyBuffer_Release(&tv);
        return NULL;
    }
    const int n = (int)(tv.len / sizeof(double)), m = (int)(yv.len / sizeof(double) / 2);
    double *y_out = writable(out_object, (Py_ssize_t)n * 2 * m, &ov, "y_out");
    if (!y_out) {
        PyBuffer_Release(&tv);
        PyBuffer_Release(&yv);
        return NULL;
    }
    PySystem p;
    memset(&p, 0, sizeof(p));
    p.fun = fun;
    p.m = m;
    p.rtol = opt.rtol;
    p.atol = opt.atol;
    p.y_out = y_out;
    p.error.worst = -1;
    PyObject *errors = PyImport_ImportModule("flexmbd.errors");
    if (errors) {
        p.simulation_error = PyObject_GetAttrString(errors, "SimulationError");
        Py_DECREF(errors);
    }
    PyErr_Clear();
    p.y = calloc(2 * m + 1, sizeof(double));
    p.lastq = calloc(m + 1, sizeof(double));
    p.lastv = calloc(m + 1, sizeof(double));
    p.lasta = calloc(m + 1, sizeof(double));
    band_init(&p.lu, m, m > 0 ? m - 1 : 0, m > 0 ? m - 1 : 0);
    AlphaSystem sys = {m, &p, py_accelerations, py_residual, py_renew, py_apply, py_output,
                       &p.error, &p.trial};
    opt.progress = py_progress;
    AlphaResult result = alpha_run(&sys, times, n, y0, y0 + m, &opt);
    free(p.y); free(p.lastq); free(p.lastv); free(p.lasta);
    band_free(&p.lu);
    PyBuffer_Release(&tv);
    PyBuffer_Release(&yv);
    PyBuffer_Release(&ov);
    Py_XDECREF(p.simulation_error);
    if (result.status == FM_PYTHON && !PyErr_Occurred() && p.pending_type) {
        PyErr_Restore(p.pending_type, p.pending_value, p.pending_tb);
    } else {
        Py_XDECREF(p.pending_type);
        Py_XDECREF(p.pending_value);
        Py_XDECREF(p.pending_tb);
    }
    return status(&p.error, result.reached, result.status, &result, p.nfev);
}

/* --- generated kernels, for the tests ---------------------------------------------------------- */
static PyObject *kernel(PyObject *self, PyObject *args)
{
    int type;
    const char *name;
    PyObject *co, *po, *vo, *go, *oo;
    (void)self;
    if (!PyArg_ParseTuple(args, "isOOOOO", &type, &name, &co, &po, &vo, &go, &oo))
        return NULL;
    if (type < 0 || type >= FM_N_TYPES) {
        PyErr_SetString(PyExc_ValueError, "unknown element type");
        return NULL;
    }
    const FmKernels *k = &FM_KERNELS[type];
    Py_buffer b[5];
    int held = 0;
    PyObject *result = NULL;
    const double *c = readable(co, k->nc, &b[held], "c");
    if (!c)
        goto done;
    held++;
    const double *p = readable(po, k->np, &b[held], "p");
    if (!p)
        goto done;
    held++;
    const double *v = NULL, *g = NULL;
    if (vo != Py_None) {
        if (!(v = readable(vo, k->nc, &b[held], "v")))
            goto done;
        held++;
    }
    if (go != Py_None) {
        if (!(g = readable(go, 2, &b[held], "g")))
            goto done;
        held++;
    }
    double *out = writable(oo, 1, &b[held], "out");
    if (!out)
        goto done;
    held++;
    const Py_ssize_t room = b[held - 1].len / sizeof(double);
    const Py_ssize_t nc = k->nc, nd = k->nd;
    if (!strcmp(name, "deform") && room >= nd)
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
        goto done;
    }
    result = Py_None;
    Py_INCREF(result);
done:
    for (int j = 0; j < held; j++)
        PyBuffer_Release(&b[j]);
    return result;
}

static PyMethodDef module_methods[] = {
    {"alpha_ode", (PyCFunction)(void (*)(void))alpha_ode, METH_VARARGS | METH_KEYWORDS,
     "Generalized-alpha integration of a Python y' = fun(t, y) with y = [q; v]."},
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
    Py_INCREF(&CoreType);
    PyModule_AddObject(mod, "Core", (PyObject *)&CoreType);
    PyModule_AddObject(mod, "CoreError", CoreError);
    PyObject *keywords = PyTuple_New(FM_N_TYPES);
    for (int k = 0; k < FM_N_TYPES; k++)
        PyTuple_SET_ITEM(keywords, k, PyUnicode_FromString(FM_KERNELS[k].keyword));
    PyModule_AddObject(mod, "KEYWORDS", keywords);
    PyModule_AddStringConstant(mod, "DEFINITIONS_HASH", FM_DEFINITIONS_HASH);
    PyModule_AddStringConstant(mod, "BUILD", FLEXMBD_BUILD);
    const char *names[] = {"OK", "NOT_CONVERGED", "SINGULAR", "SINGULAR_TOLERANCE", "MASSLESS",
                           "NOT_FINITE", "STEP_FAILED", "PYTHON", "INTERRUPTED", "NO_MEMORY"};
    for (int k = 0; k < 10; k++)
        PyModule_AddIntConstant(mod, names[k], k);
    return mod;
}
