# cython: language_level=3, boundscheck=False, wraparound=False, embedsignature=True
"""flexmbd's compiled core as Python sees it: a binding, with no mechanics of its own.

The C is in ``csrc/``: ``runs.c`` holds a compiled model and drives its runs, ``system.c``
evaluates one state, ``alpha.c`` integrates, ``band.c`` factorises, ``kernels.c`` holds
the generated element kernels. ``Core(spec)`` takes a :class:`~flexmbd.engine.spec.CoreSpec`
(checked when it was made) and keeps its own copies. Arrays are typed memoryviews:
C-contiguous float64 (or int32) of the lengths each call names, else ``ValueError``. A
run's failure comes back as its status dict, a single evaluation's as :class:`CoreError`;
what a Python callback (a law, the loads, progress) raised, or Ctrl-C, is raised again.
"""

import os

import numpy as np

from cpython.exc cimport PyErr_CheckSignals
from cpython.mem cimport PyMem_Free, PyMem_Malloc
from libc.stddef cimport ptrdiff_t

cdef extern from "core.h":
    cpdef enum FmStatus:
        FM_OK, FM_NOT_CONVERGED, FM_SINGULAR, FM_SINGULAR_TOLERANCE, FM_MASSLESS
        FM_NOT_FINITE, FM_STEP_FAILED, FM_PYTHON, FM_NO_MEMORY, FM_PARTITION
        FM_STEP_TOO_SMALL
    cpdef enum FmLawKind:
        FM_LAW_POLYNOMIAL, FM_LAW_CALLBACK, FM_LAW_INTEGRATED

    ctypedef void (*FmDeform)(const double *c, const double *p, double *out)
    ctypedef void (*FmRates)(const double *c, const double *v, const double *p, double *out)
    ctypedef void (*FmLoad)(const double *c, const double *p, const double *g, double *out)
    ctypedef struct FmKernels:
        const char *keyword
        int nc, nd, np, ng
        FmDeform deform, deform_jac, hessian, mass
        FmRates quadratic, inertia
        FmLoad gravity, gravity_jac
    const FmKernels FM_KERNELS[]
    const int FM_N_TYPES
    const char FM_DEFINITIONS_HASH[]
    ctypedef struct FmError:
        double time, residual, conditioning, limit, step
        int iterations, worst
    ctypedef struct FmModel:
        int nx, ne, nq, nr, ns, nfree, nmult, nd_dyn, dc_kl, dc_ku, sd_kl, sd_ku, max_iterations
        double tolerance, regularity_limit, reference_conditioning
    size_t fm_element_values(const FmModel *m, int hessian, const double *x, double *out)
    size_t fm_gravity_slopes(const FmModel *m, const double *x, double *out)

cdef extern from "core.h":
    ctypedef struct Band:
        int n, kl, ku, ldab
        double *ab
        int *ipiv
        double *work
    int band_init(Band *b, int n, int kl, int ku)
    void band_free(Band *b)
    int band_factor(Band *b)
    void band_solve(const Band *b, double *x)
    void band_solve_many(const Band *b, double *x, int k)
    void band_solve_t(const Band *b, double *x)
    double band_inverse_norm(Band *b, int *column)
    double band_min_pivot(const Band *b)

cdef extern from "alpha.h":
    ctypedef struct AlphaOptions:
        double step, rho_inf, rtol, atol
        int iterations, renew_every, adaptive
        double max_step
        double *end
    ctypedef struct AlphaResult:
        long nfev, njev, nlu, nsteps, nrejected
        int reached, status

cdef extern from "runs.h":
    enum: FM_N_OUT
    const char *const FM_OUTPUT_NAMES[]
    ctypedef int (*FmCallback)(void *context, double t) noexcept
    ctypedef struct FmCore:
        FmModel m
        FmError error
        void *context
        FmCallback laws, loads, progress
        double *law_values
        double *force_x
        double *force_xd
        double *force_f
        int n_outputs
        double near
        const int *watch
        int n_watch
    const char *fm_build()
    int fm_fields()
    const char *fm_field_name(int k)
    char fm_field_type(int k)
    int fm_core_set(FmCore *c, int k, const void *data, long n)
    int fm_core_init(FmCore *c)
    void fm_core_free(FmCore *c)
    int fm_output_size(const FmCore *c, int output)
    void fm_reset_error(FmCore *c)
    void fm_core_prepare(FmCore *c, const int *law_kind, const double *law_coef,
                         double **outs, int n_outputs, int dynamics)
    void fm_core_reset(FmCore *c, const double *start)
    int fm_core_kinematic_run(FmCore *c, const double *times, int n, int *reached)
    AlphaResult fm_core_alpha_run(FmCore *c, const double *times, int n, const double *q0,
                                  const double *v0, AlphaOptions *options)
    int fm_core_accelerations(FmCore *c, double t, const double *y, double *out)
    int fm_core_residual(FmCore *c, double t, const double *y, const double *a, double *r)
    int fm_core_correction(FmCore *c, double c_q, double c_v, const double *r, double *da)
    int fm_core_output(FmCore *c, int k, double t, const double *y)
    int fm_core_state(FmCore *c, double t, const double *q, const double *qd,
                      const double *qdd, const double *guess, double **kinematics)
    int fm_core_equilibrium(FmCore *c, double t, const double *q, const double *qd,
                            const double *qdd, const double *guess, const double *loads,
                            double **outs)
    void fm_core_mass_matrix(FmCore *c, const double *x, const double *xd, double *M,
                             double *h, double *f)
    int fm_core_inertia_slopes(FmCore *c, const double *x, const double *q, const double *qd,
                               const double *qdd, const double *step, int rates, double *out)
    double fm_core_factor(FmCore *c, const double *x)
    int fm_core_solve(FmCore *c, double *rhs, int count, int transposed)
    int fm_core_static_saddle(FmCore *c, const double *x, const double *q, const double *mu,
                              const double *loads, double *r)
    int fm_core_static_solve(FmCore *c, double *rhs, int count, int transposed)
    int fm_core_free_mass_times(FmCore *c, const double *v, int count, double *out)
    int fm_core_mass_regular(FmCore *c, const double *x)
    void fm_core_configuration(const FmCore *c, double *x)

cdef extern from "text.h":
    int format_number "format_17g"(double x, char *out)
    int fm_csv_write(int fd, const char *const *columns, const ptrdiff_t *strides,
                     int n_columns, ptrdiff_t rows) nogil

KEYWORDS = tuple(FM_KERNELS[k].keyword.decode() for k in range(FM_N_TYPES))
#: (coordinates, deformations, reference parameters) of each element type's kernels
KERNEL_SIZES = tuple((FM_KERNELS[k].nc, FM_KERNELS[k].nd, FM_KERNELS[k].np)
                     for k in range(FM_N_TYPES))
DEFINITIONS_HASH = FM_DEFINITIONS_HASH.decode()
BUILD = fm_build().decode()
OUTPUTS = tuple(FM_OUTPUT_NAMES[o].decode() for o in range(FM_N_OUT))
FIELDS = tuple(fm_field_name(k).decode() for k in range(fm_fields()))


class CoreError(RuntimeError):
    """A single evaluation failed; ``args[0]`` is its status (as a run's)."""


cdef inline int need(Py_ssize_t got, Py_ssize_t wanted, str name) except -1:
    if got != wanted:
        raise ValueError(f"{name}: a float64 array of {wanted} entries is needed, got {got}")
    return 0


cdef int call_laws(void *context, double t) noexcept:
    return (<Core>context).callback((<Core>context).law_function, t)


cdef int call_loads(void *context, double t) noexcept:
    return (<Core>context).callback((<Core>context).load_function, t)


cdef int call_progress(void *context, double t) noexcept:
    return (<Core>context).callback((<Core>context).progress_function, t, True)


cdef class Core:
    """A model compiled for the core, its workspace and its prepared run."""
    cdef FmCore c
    cdef list held                 # the prepared run's arrays, which the core writes
    cdef object law_function, load_function, progress_function
    cdef object pending            # what a callback raised

    def __init__(self, spec):
        from .spec import CoreSpec
        if not isinstance(spec, CoreSpec):
            raise TypeError(f"Core takes a flexmbd.engine.spec.CoreSpec, not {spec!r}")
        fm_core_free(&self.c)
        values = spec.fields()
        if set(values) != set(FIELDS):
            raise ValueError(f"the core and flexmbd/engine/spec.py disagree on the fields: "
                             f"{sorted(set(values) ^ set(FIELDS))}")
        cdef const int[::1] ints
        cdef const double[::1] floats
        cdef int k, code
        for k, name in enumerate(FIELDS):
            kind = fm_field_type(k)
            if kind == b'n':
                code = fm_core_set(&self.c, k, NULL, values[name])
            elif kind == b'i':
                ints = values[name]
                code = fm_core_set(&self.c, k, &ints[0], len(ints))
            else:
                floats = values[name]
                code = fm_core_set(&self.c, k, &floats[0], len(floats))
            if code:
                raise MemoryError(f"core spec: {name}")
        if fm_core_init(&self.c):
            raise MemoryError("the core's workspace")
        self.c.context = <void *>self
        self.held = []

    def __dealloc__(self):
        fm_core_free(&self.c)

    cdef int callback(self, function, double t, bint signals=False) noexcept:
        try:
            if function is not None:
                function(t)
            if signals:
                PyErr_CheckSignals()
        except BaseException as error:
            self.pending = error
            return FM_PYTHON
        return FM_OK

    cdef dict status(self, int code, int reached, AlphaResult *r):
        cdef FmError *e = &self.c.error
        error, self.pending = (self.pending if code == FM_PYTHON else None), None
        return {"reached": reached, "code": FmStatus(code), "time": e.time,
                "iterations": e.iterations, "residual": e.residual, "worst": e.worst,
                "conditioning": e.conditioning, "limit": e.limit, "step": e.step,
                "nfev": r.nfev if r else 0, "njev": r.njev if r else 0,
                "nlu": r.nlu if r else 0, "nsteps": r.nsteps if r else 0,
                "nrejected": r.nrejected if r else 0,
                "exception": error}

    cdef int check(self, int code) except -1:
        """Raise the failure of a single evaluation."""
        if code == FM_OK:
            return 0
        if code == FM_PYTHON and self.pending is not None:
            error, self.pending = self.pending, None
            raise error
        raise CoreError(self.status(code, 0, NULL))

    def settings(self, double tolerance, int max_iterations, double regularity_limit,
                 double reference_conditioning):
        """The position solve's tolerance [m, rad], iteration limit, the scaled conditioning
        of ``D_c`` below which a solution counts as singular, and the reference's."""
        self.c.m.tolerance, self.c.m.max_iterations = tolerance, max_iterations
        self.c.m.regularity_limit = regularity_limit
        self.c.m.reference_conditioning = reference_conditioning

    def bands(self):
        """Sizes and bands of the two square systems, ``D_c`` and the saddle-point matrix."""
        m = &self.c.m
        return {"dc_n": m.nr, "dc_kl": m.dc_kl, "dc_ku": m.dc_ku, "saddle_n": m.ns,
                "saddle_kl": m.sd_kl, "saddle_ku": m.sd_ku}

    # --- a run --------------------------------------------------------------------------------
    def prepare(self, const int[::1] law_kind not None, const double[:, ::1] law_coef not None,
                dict outputs not None, int n_outputs, bint dynamics, law_callback=None,
                double[:, ::1] law_values=None, forces=None, double[::1] force_x=None,
                double[::1] force_xd=None, double[::1] force_f=None, progress=None):
        """A run's laws (``law_kind`` ``(nq,)`` of :class:`FmLawKind`: polynomial with
        ``law_coef`` ``(nq, 3)``, a ``law_callback(t)`` filling ``law_values`` ``(nq, 3)``, or
        integrated), its loads
        (``forces(t)`` reads ``force_x``, ``force_xd`` and fills ``force_f``, ``(nx,)``
        each), ``progress(t)`` and the ``outputs`` ``{name: (n_outputs, size)}`` it fills."""
        cdef FmModel *m = &self.c.m
        cdef double *outs[FM_N_OUT]
        need(law_kind.shape[0], m.nq, "law_kind")
        need(law_coef.shape[0] * law_coef.shape[1], 3 * m.nq, "law_coef")
        self.held = self.columns(outputs, n_outputs, outs)
        self.c.laws = self.c.loads = NULL
        if law_callback is not None:
            need(law_values.shape[0] * law_values.shape[1], 3 * m.nq, "law_values")
            self.c.laws, self.c.law_values = call_laws, &law_values[0, 0]
            self.held.append(law_values)
        if forces is not None:
            for given, name in ((force_x, "force_x"), (force_xd, "force_xd"),
                                (force_f, "force_f")):
                need(len(given), m.nx, name)
            self.c.loads = call_loads
            self.c.force_x, self.c.force_xd = &force_x[0], &force_xd[0]
            self.c.force_f = &force_f[0]
            self.held += [force_x, force_xd, force_f]
        self.c.progress = call_progress
        self.law_function, self.load_function = law_callback, forces
        self.progress_function = progress
        fm_core_prepare(&self.c, &law_kind[0], &law_coef[0, 0], outs, n_outputs, dynamics)

    cdef list columns(self, dict outputs, Py_ssize_t rows, double **outs):
        """The pointers of the output arrays ``{name: (rows, size)}`` (NULL where absent);
        their memoryviews, which hold them."""
        cdef double[:, ::1] column
        if not set(outputs) <= set(OUTPUTS):
            raise ValueError(f"outputs: no column {sorted(set(outputs) - set(OUTPUTS))} (the "
                             f"core's: {OUTPUTS})")
        held = []
        for o, name in enumerate(OUTPUTS):
            outs[o] = NULL
            if outputs.get(name) is not None:
                column = outputs[name]
                need(column.shape[0] * column.shape[1], rows * fm_output_size(&self.c, o), name)
                outs[o] = &column[0, 0]
                held.append(column)
        return held

    def reset(self, const double[::1] start=None):
        """Forget the last evaluation; the next run starts from ``start`` ``(nx,)``, or from
        the reference configuration."""
        if start is not None:
            need(start.shape[0], self.c.m.nx, "start")
        fm_core_reset(&self.c, &start[0] if start is not None else NULL)

    def kinematic_run(self, const double[::1] times not None):
        """Kinematics (and with dynamics, stresses and reactions) at every time of a grid;
        the run's status."""
        cdef int reached = 0
        code = fm_core_kinematic_run(&self.c, &times[0], len(times), &reached)
        return self.status(code, reached, NULL)

    def alpha_run(self, const double[::1] times not None, const double[::1] q0 not None,
                  const double[::1] v0 not None, *, double step, double rho_inf, double rtol,
                  double atol, int iterations, int renew_every, bint adaptive,
                  double max_step, double near,
                  const int[::1] watch=None, double[::1] end=None):
        """Generalized-alpha integration from ``(q0, v0)`` ``(nd,)`` with the outputs at every
        time of a grid, in fixed steps of ``step`` or (``adaptive``) steps that follow the
        local error, the first ``step`` (0: chosen), at most ``max_step``; stops where a ``watch``-ed free rotation's partition is spent (three
        positions in ``q_d`` each), its state then in ``end`` ``(2 nd,)``. The status."""
        cdef int nd = self.c.m.nd_dyn
        cdef AlphaOptions options
        need(q0.shape[0], nd, "q0")
        need(v0.shape[0], nd, "v0")
        if end is not None:
            need(end.shape[0], 2 * nd, "end")
        if watch is not None and (len(watch) % 3 or min(watch, default=0) < 0
                                  or max(watch, default=0) >= nd):
            raise ValueError("watch: int32 positions in q_d, three per rotation")
        if len(times) == 0:
            raise ValueError("times: at least one output time is needed")
        options.step, options.rho_inf, options.rtol, options.atol = step, rho_inf, rtol, atol
        options.iterations, options.renew_every = iterations, renew_every
        options.adaptive, options.max_step = adaptive, max_step
        options.end = &end[0] if end is not None else NULL
        self.c.near = near
        self.c.watch = &watch[0] if watch is not None and len(watch) else NULL
        self.c.n_watch = len(watch) // 3 if watch is not None else 0
        try:
            result = fm_core_alpha_run(&self.c, &times[0], len(times), &q0[0], &v0[0],
                                       &options)
        finally:
            self.c.watch, self.c.n_watch = NULL, 0
        return self.status(result.status, result.reached, &result)

    # --- single evaluations ---------------------------------------------------------------
    def accelerations(self, double t, const double[::1] y not None, double[::1] out not None):
        """``qdd_d`` into ``out`` ``(nd,)`` at ``y = [q_d, qd_d]``, for scipy's integrators."""
        need(y.shape[0], 2 * self.c.m.nd_dyn, "y")
        need(out.shape[0], self.c.m.nd_dyn, "out")
        self.check(fm_core_accelerations(&self.c, t, &y[0], &out[0]))

    def residual(self, double t, const double[::1] y not None, const double[::1] a not None,
                 double[::1] r not None):
        """The reduced residual ``r`` at ``y = [q_d, qd_d]``, accelerations ``a`` (tests)."""
        need(y.shape[0], 2 * self.c.m.nd_dyn, "y")
        need(a.shape[0], self.c.m.nd_dyn, "a")
        need(r.shape[0], self.c.m.nd_dyn, "r")
        self.check(fm_core_residual(&self.c, t, &y[0], &a[0], &r[0]))

    def correction(self, double c_q, double c_v, const double[::1] r not None,
                   double[::1] da not None):
        """Newton's ``-(Mbar + c_q K + c_v C)^-1 r`` at the last residual's state (tests)."""
        need(r.shape[0], self.c.m.nd_dyn, "r")
        need(da.shape[0], self.c.m.nd_dyn, "da")
        self.check(fm_core_correction(&self.c, c_q, c_v, &r[0], &da[0]))

    def output(self, int k, double t, const double[::1] y not None):
        """The state at output ``k`` of the prepared run from ``y = [q_d, qd_d]``."""
        if not 0 <= k < self.c.n_outputs:
            raise IndexError("output index out of range")
        need(y.shape[0], 2 * self.c.m.nd_dyn, "y")
        self.check(fm_core_output(&self.c, k, t, &y[0]))

    def state(self, double t, const double[::1] q not None, const double[::1] qd not None,
              const double[::1] qdd not None, const double[::1] guess not None,
              double[::1] x not None, double[::1] xd not None, double[::1] xdd not None,
              double[::1] e not None, double[::1] ed not None, double[::1] edd not None):
        """The kinematics of one state (exact position solve from ``guess``) into ``x, xd,
        xdd`` ``(nx,)`` and ``e, ed, edd`` ``(ne,)``."""
        cdef FmModel *m = &self.c.m
        cdef double *kinematics[6]
        need(q.shape[0], m.nq, "q")
        need(qd.shape[0], m.nq, "qd")
        need(qdd.shape[0], m.nq, "qdd")
        need(guess.shape[0], m.nx, "guess")
        need(x.shape[0], m.nx, "x")
        need(xd.shape[0], m.nx, "xd")
        need(xdd.shape[0], m.nx, "xdd")
        need(e.shape[0], m.ne, "e")
        need(ed.shape[0], m.ne, "ed")
        need(edd.shape[0], m.ne, "edd")
        kinematics[:] = [&x[0], &xd[0], &xdd[0], &e[0], &ed[0], &edd[0]]
        self.check(fm_core_state(&self.c, t, &q[0], &qd[0], &qdd[0], &guess[0], kinematics))

    def equilibrium(self, double t, const double[::1] q not None, const double[::1] qd not None,
                    const double[::1] qdd not None, const double[::1] guess not None,
                    const double[::1] loads not None, dict outputs not None):
        """Inverse dynamics at one state with the applied ``loads`` ``(nx,)``, exact position
        solve from ``guess``, into ``outputs`` ``{name: (1, size)}`` as a run's output."""
        cdef FmModel *m = &self.c.m
        cdef double *outs[FM_N_OUT]
        for given, n, name in ((q, m.nq, "q"), (qd, m.nq, "qd"), (qdd, m.nq, "qdd"),
                               (guess, m.nx, "guess"), (loads, m.nx, "loads")):
            need(len(given), n, name)
        held = self.columns(outputs, 1, outs)
        self.check(fm_core_equilibrium(&self.c, t, &q[0], &qd[0], &qdd[0], &guess[0],
                                       &loads[0], outs))

    def mass_matrix(self, const double[::1] x not None, const double[::1] xd not None,
                    double[:, ::1] M not None, double[::1] h not None, double[::1] f not None):
        """The mass matrix ``M`` ``(nx, nx)``, the velocity-dependent inertia ``h`` and the
        constant loads with gravity ``f`` ``(nx,)`` at ``(x, xd)``."""
        cdef int nx = self.c.m.nx
        need(x.shape[0], nx, "x")
        need(xd.shape[0], nx, "xd")
        need(h.shape[0], nx, "h")
        need(f.shape[0], nx, "f")
        need(M.shape[0] * M.shape[1], nx * nx, "M")
        fm_core_mass_matrix(&self.c, &x[0], &xd[0], &M[0, 0], &h[0], &f[0])

    def masses(self, const double[:, ::1] x not None, double[:, :, ::1] M not None):
        """The mass matrices ``M`` ``(k, nx, nx)`` at the configurations ``x`` ``(k, nx)``
        at rest, in one call."""
        cdef int nx = self.c.m.nx
        cdef Py_ssize_t k
        need(x.shape[1], nx, "x")
        need(M.shape[0] * M.shape[1] * M.shape[2], x.shape[0] * nx * nx, "M")
        rest = np.zeros((3, nx))
        cdef double[:, ::1] work = rest
        for k in range(x.shape[0]):
            fm_core_mass_matrix(&self.c, &x[k, 0], &work[0, 0], &M[k, 0, 0], &work[1, 0],
                                &work[2, 0])

    def element_values(self, str name, const double[::1] x not None, double[::1] out not None):
        """The kernel ``"deform_jac"`` or ``"hessian"`` of every element at ``x`` ``(nx,)``,
        element after element, into ``out``."""
        if name not in ("deform_jac", "hessian"):
            raise ValueError(f"element_values: no kernel {name} for all elements")
        hessian = name == "hessian"
        need(x.shape[0], self.c.m.nx, "x")
        need(out.shape[0], fm_element_values(&self.c.m, hessian, NULL, NULL), "out")
        fm_element_values(&self.c.m, hessian, &x[0], &out[0])

    def gravity_slopes(self, const double[::1] x not None, double[::1] out not None):
        """Per element, element after element, ``m d(int N^T g)/dc`` ``(nc, nc)`` at ``x``
        ``(nx,)`` where an element's gravity turns with it, else zeros, into ``out``."""
        need(x.shape[0], self.c.m.nx, "x")
        need(out.shape[0], fm_gravity_slopes(&self.c.m, NULL, NULL), "out")
        fm_gravity_slopes(&self.c.m, &x[0], &out[0])

    def inertia_slopes(self, const double[::1] x not None, const double[::1] q not None,
                       const double[::1] qd not None, const double[::1] qdd not None,
                       const double[::1] step not None, bint rates,
                       double[:, ::1] out not None):
        """Central differences ``(nx + ne, nq)`` of ``M xdd + h`` and ``ed`` along each entry
        of ``q`` (of ``qd`` with ``rates``), ``step`` either side."""
        cdef FmModel *m = &self.c.m
        need(x.shape[0], m.nx, "x")
        for given, name in ((q, "q"), (qd, "qd"), (qdd, "qdd"), (step, "step")):
            need(len(given), m.nq, name)
        need(out.shape[0] * out.shape[1], (m.nx + m.ne) * m.nq, "out")
        self.check(fm_core_inertia_slopes(&self.c, &x[0], &q[0], &qd[0], &qdd[0],
                                          &step[0], rates, &out[0, 0]))

    def factor(self, const double[::1] x not None):
        """Factorise ``D_c`` at ``x`` ``(nx,)``; its scaled conditioning (0 when singular)."""
        need(x.shape[0], self.c.m.nx, "x")
        return fm_core_factor(&self.c, &x[0])

    def solve(self, double[:, ::1] rhs not None, bint transposed):
        """``D_c^-1`` (or ``D_c^-T``) of each row of ``rhs`` ``(k, nr)`` in place, with the
        last :meth:`factor`."""
        need(rhs.shape[1], self.c.m.nr, "rhs")
        code = fm_core_solve(&self.c, &rhs[0, 0], rhs.shape[0], transposed)
        if code == FM_SINGULAR:
            raise RuntimeError("D_c is not factorised")
        if code:
            raise MemoryError("D_c's solve")

    def static_saddle(self, const double[::1] x not None, const double[::1] q not None,
                      const double[::1] mu not None, const double[::1] loads not None,
                      double[::1] r not None):
        """The static equilibrium in all coordinates at ``x`` ``(nx,)``: its residual into
        ``r`` ``(ns,)`` (free coordinates, then constrained deformations) at the constraint
        stresses ``mu`` ``(nmult,)`` under ``loads`` ``(nx,)``, ``q`` ``(nq,)`` holding the
        input targets; the factorised tangent is kept for :meth:`static_solve`."""
        cdef FmModel *m = &self.c.m
        need(x.shape[0], m.nx, "x")
        need(q.shape[0], m.nq, "q")
        need(mu.shape[0], m.nmult, "mu")
        need(loads.shape[0], m.nx, "loads")
        need(r.shape[0], m.ns, "r")
        cdef double z = 0.0
        self.check(fm_core_static_saddle(&self.c, &x[0], &q[0] if m.nq else &z,
                                         &mu[0] if m.nmult else &z, &loads[0],
                                         &r[0] if m.ns else &z))

    def static_solve(self, double[:, ::1] rhs not None, bint transposed=False):
        """The kept static tangent's solutions of the rows of ``rhs`` ``(k, ns)``, in place
        (with its transpose when ``transposed``)."""
        need(rhs.shape[1], self.c.m.ns, "rhs")
        if rhs.shape[0] == 0 or rhs.shape[1] == 0:
            return
        code = fm_core_static_solve(&self.c, &rhs[0, 0], rhs.shape[0], transposed)
        if code == FM_SINGULAR:
            raise RuntimeError("no static tangent is factorised")
        if code:
            raise MemoryError("the static tangent's solve")

    def mass_regular(self, const double[::1] x not None):
        """Whether every motion the constraints allow at ``x`` ``(nx,)`` moves mass (the
        saddle-point matrix of the mass and the constraints is regular)."""
        need(x.shape[0], self.c.m.nx, "x")
        return fm_core_mass_regular(&self.c, &x[0]) == FM_OK

    def free_mass_times(self, const double[:, ::1] v not None, double[:, ::1] out not None):
        """``M v`` over the free coordinates for the rows of ``v`` ``(k, nfree)``, at the
        configuration of the kept static tangent."""
        need(v.shape[1], self.c.m.nfree, "v")
        need(out.shape[0] * out.shape[1], v.shape[0] * v.shape[1], "out")
        if v.shape[0] == 0 or v.shape[1] == 0:
            return
        if fm_core_free_mass_times(&self.c, &v[0, 0], v.shape[0], &out[0, 0]):
            raise RuntimeError("no static tangent is factorised")

    def configuration(self, double[::1] x not None):
        """The configuration of the last failure (or of the last evaluation) into ``x``."""
        need(x.shape[0], self.c.m.nx, "x")
        fm_core_configuration(&self.c, &x[0])


def csv_write(int fd, columns):
    """Equally long 1-d float64 ``columns`` (any strides) as CSV rows on the file descriptor
    ``fd``, each number as ``"%.17g"`` writes it; other threads of Python run meanwhile
    (the columns must not change). Raises ``OSError`` when the file cannot take them."""
    cdef const double[:] view
    cdef list held = []
    cdef Py_ssize_t n = len(columns), rows = len(columns[0]) if n else 0
    cdef const char **at = <const char **>PyMem_Malloc(sizeof(char *) * (n + 1))
    cdef ptrdiff_t *strides = <ptrdiff_t *>PyMem_Malloc(sizeof(ptrdiff_t) * (n + 1))
    try:
        if not at or not strides:
            raise MemoryError("csv_write")
        for k in range(n):
            view = columns[k]
            need(view.shape[0], rows, "csv_write: a column")
            held.append(view)
            at[k], strides[k] = <const char *>&view[0], view.strides[0]
        with nogil:
            error = fm_csv_write(fd, at, strides, <int>n, rows)
        if error:
            raise OSError(error, os.strerror(error))
    finally:
        PyMem_Free(at)
        PyMem_Free(strides)


def format_17g(double x):
    """One number as :func:`csv_write` writes it (for the tests)."""
    cdef char out[32]
    return out[:format_number(x, out)].decode()


def kernel(int type, str name, const double[::1] c not None, const double[::1] p not None,
           const double[::1] v, const double[::1] g, double[::1] out not None):
    """One generated kernel (``name``: deform, deform_jac, quadratic, hessian, mass,
    inertia, gravity, gravity_jac) of element type ``type`` at coordinates ``c`` ``(nc,)``, reference
    parameters ``p``, rates ``v`` ``(nc,)`` and gravity ``g`` ``(2,)`` or ``(3,)``."""
    if not 0 <= type < FM_N_TYPES:
        raise ValueError("unknown element type")
    cdef const FmKernels *k = &FM_KERNELS[type]
    need(c.shape[0], k.nc, "c")
    need(p.shape[0], k.np, "p")
    if v is not None:
        need(v.shape[0], k.nc, "v")
    if g is not None:
        need(g.shape[0], k.ng, "g")
    sizes = {"deform": k.nd, "deform_jac": k.nd * (1 + k.nc), "quadratic": k.nd,
             "hessian": k.nd * k.nc * k.nc, "mass": k.nc * k.nc, "inertia": k.nc,
             "gravity": k.nc, "gravity_jac": k.nc * k.nc}
    defined = {"deform": True, "deform_jac": True, "quadratic": v is not None,
               "hessian": True, "mass": k.mass != NULL, "inertia": k.inertia != NULL
               and v is not None, "gravity": k.gravity != NULL and g is not None,
               "gravity_jac": k.gravity_jac != NULL and g is not None}
    if not defined.get(name) or out.shape[0] < sizes[name]:
        raise ValueError(f"kernel {name}: not defined for {k.keyword.decode()}, or wrong "
                         f"arguments")
    cdef const double *pp = &p[0] if k.np else NULL
    if name == "deform":
        k.deform(&c[0], pp, &out[0])
    elif name == "deform_jac":
        k.deform_jac(&c[0], pp, &out[0])
    elif name == "quadratic":
        k.quadratic(&c[0], &v[0], pp, &out[0])
    elif name == "hessian":
        k.hessian(&c[0], pp, &out[0])
    elif name == "mass":
        k.mass(&c[0], pp, &out[0])
    elif name == "inertia":
        k.inertia(&c[0], &v[0], pp, &out[0])
    elif name == "gravity":
        k.gravity(&c[0], pp, &g[0], &out[0])
    else:
        k.gravity_jac(&c[0], pp, &g[0], &out[0])


def banded_lu(const double[:, ::1] a not None, int kl, int ku, double[:, ::1] rhs not None,
              str how="each"):
    """The core's banded LU (``band.c``) of the matrix ``a`` ``(n, n)``, whose entries
    outside ``kl`` sub- and ``ku`` super-diagonals are ignored, for its tests against
    LAPACK: the rows of ``rhs`` ``(k, n)`` are solved in place, one by one (``how="each"``),
    all at once (``"many"``) or with the transpose (``"transposed"``). Returns
    ``(info, pivots, factors, smallest_pivot, inverse_norm)``: ``info`` 0 or ``j + 1``
    for a zero pivot ``j``, the 0-based row interchanges ``(n,)``, the factors in LAPACK's
    band storage ``(2 kl + ku + 1, n)``, the smallest ``|u_jj|`` and the estimate of
    ``||a^-1||_1``."""
    cdef Py_ssize_t n = a.shape[0], i, j, r
    cdef Band b
    cdef int column = -1
    cdef double[:, ::1] block
    if a.shape[1] != n or rhs.shape[1] != n or kl < 0 or ku < 0:
        raise ValueError("banded_lu: a square (n, n), rows of rhs (k, n), kl, ku >= 0")
    if how not in ("each", "many", "transposed"):
        raise ValueError(f"banded_lu: how is each, many or transposed, not {how!r}")
    if band_init(&b, <int>n, kl, ku):
        band_free(&b)
        raise MemoryError("banded_lu")
    try:
        for j in range(n):
            for i in range(max(0, j - ku), min(n, j + kl + 1)):
                b.ab[(kl + ku + i - j) + j * b.ldab] = a[i, j]
        info = band_factor(&b)
        if info == 0:
            if how == "many" and rhs.shape[0]:
                # band_solve_many takes the right-hand sides as columns, (n, k) row-major
                solved = np.ascontiguousarray(np.asarray(rhs).T)
                block = solved
                band_solve_many(&b, &block[0, 0], <int>rhs.shape[0])
                np.asarray(rhs)[...] = solved.T
            else:
                for r in range(rhs.shape[0]):
                    if how == "transposed":
                        band_solve_t(&b, &rhs[r, 0])
                    else:
                        band_solve(&b, &rhs[r, 0])
        pivots = np.array([b.ipiv[j] for j in range(n)], dtype=np.int32)
        factors = np.array([[b.ab[i + j * b.ldab] for j in range(n)] for i in range(b.ldab)])
        smallest = band_min_pivot(&b)
        estimate = band_inverse_norm(&b, &column) if info == 0 else float("inf")
        return info, pivots, factors, smallest, estimate
    finally:
        band_free(&b)
