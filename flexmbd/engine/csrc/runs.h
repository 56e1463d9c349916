/* A compiled model and its runs (runs.c): what the binding (_core.pyx) holds.
 *
 * FmCore keeps its own copies of a model's arrays (handed over field by field, see
 * fm_field_name), the two states of its evaluations, the saddle-point matrices and the
 * prepared run: laws, loads and output arrays. A run is driven entirely here: kinematic
 * and inverse runs over a time grid, generalized-alpha integration with its outputs, or
 * single evaluations for scipy's integrators and the per-state functions. The binding is
 * called back only for laws and loads that are Python callables, and for progress (which
 * also lets Ctrl-C through); every function returns an FmStatus, with the details of a
 * failure in the core's `error`.
 */
#ifndef FLEXMBD_RUNS_H
#define FLEXMBD_RUNS_H

#include "alpha.h"
#include "core.h"

/* The columns a run fills, each n_outputs rows of fm_output_size values. */
enum FmOutput { FM_OUT_X, FM_OUT_XD, FM_OUT_XDD, FM_OUT_E, FM_OUT_ED, FM_OUT_EDD, FM_OUT_Q,
                FM_OUT_QD, FM_OUT_QDD, FM_OUT_SIGMA, FM_OUT_REACTIONS, FM_OUT_DRIVING,
                FM_N_OUT };
extern const char *const FM_OUTPUT_NAMES[FM_N_OUT];

/* A callback of the binding at time t: FM_OK, or FM_PYTHON when it raised (the binding
 * keeps the exception). */
typedef int (*FmCallback)(void *context, double t);

typedef struct {
    FmModel m;
    double *x0, *coord_scale, *lumped_diag;
    int *consistent;
    /* what only fm_core_init reads: the D_c and saddle entries' rows and columns */
    int *dc_row, *dc_col, *sd_a_u, *sd_a_v, *sd_m_u, *sd_c_u, *sd_c_v;
    double *gravity;
    int ready;                     /* fm_core_init succeeded */
    FmState eval, out;             /* the integrator's evaluations; outputs and single states */
    FmState *failed;               /* the state of the last failure */
    Band sd;                       /* the saddle-point matrix of the Newton operator */
    double *op_J;                  /* the element Jacobians of the operator's state */
    Band sd_acc;                   /* and of the accelerations (an output between two steps
                                      must not replace the operator) */
    FmState stat;                  /* the static equilibrium in all coordinates: its state, */
    Band sd_static;                /* its factorised tangent [[K, C^T], [C, 0]] */
    double static_scale;           /* and the scale of that matrix's constraint rows */
    int has_static;
    FmError error;
    int trial;
    /* the prepared run */
    int *law_kind;                 /* per q entry: an enum FmLawKind */
    double *law_coef;              /* x0, v0, a0 per q entry */
    void *context;                 /* the binding's, for its callbacks */
    FmCallback laws;               /* fills law_values (3 nq) for the callback entries */
    double *law_values;
    FmCallback loads;              /* reads force_x, force_xd (nx), fills force_f (nx) */
    double *force_x, *force_xd, *force_f;
    FmCallback progress;           /* every 256 outputs or steps */
    double *outs[FM_N_OUT];
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
    const int *watch;              /* during fm_core_alpha_run: the q_d positions of free
                                      rotations' dynamic Euler parameters, three per rotation */
    int n_watch;                   /* rotations watched */
} FmCore;

/* --- the model's fields: sizes ('n'), int32 ('i') and float64 ('d') arrays by name ------ */
int fm_fields(void);
const char *fm_field_name(int k);
char fm_field_type(int k);
/* Field k from `data` (n entries; a size: its value in n): FM_OK or FM_NO_MEMORY. The
 * binding checks the lengths (flexmbd/engine/spec.py declares them). */
int fm_core_set(FmCore *c, int k, const void *data, long n);
/* After every field: the maps, bands and reference terms; FM_OK or FM_NO_MEMORY. */
int fm_core_init(FmCore *c);
void fm_core_free(FmCore *c);     /* also of a core whose fields or init failed */
int fm_output_size(const FmCore *c, int output);
void fm_reset_error(FmCore *c);

/* --- a run --------------------------------------------------------------------------------- */
/* Laws (law_kind, law_coef: 3 nq) and the output arrays (NULL: not kept); the callbacks
 * and their arrays are set by the caller beforehand. */
void fm_core_prepare(FmCore *c, const int *law_kind, const double *law_coef,
                     double *const outs[FM_N_OUT], int n_outputs, int dynamics);
void fm_core_reset(FmCore *c, const double *start);   /* start NULL: the reference */
int fm_core_kinematic_run(FmCore *c, const double *times, int n, int *reached);
AlphaResult fm_core_alpha_run(FmCore *c, const double *times, int n, const double *q0,
                              const double *v0, AlphaOptions *options);

/* --- single evaluations (y = [q_d, qd_d]) ----------------------------------------------------- */
int fm_core_accelerations(FmCore *c, double t, const double *y, double *out);
int fm_core_residual(FmCore *c, double t, const double *y, const double *a, double *r);
int fm_core_correction(FmCore *c, double c_q, double c_v, const double *r, double *da);
int fm_core_output(FmCore *c, int k, double t, const double *y);
int fm_core_state(FmCore *c, double t, const double *q, const double *qd, const double *qdd,
                  const double *guess, double *const kinematics[6]);
int fm_core_equilibrium(FmCore *c, double t, const double *q, const double *qd,
                        const double *qdd, const double *guess, const double *loads,
                        double *const outs[FM_N_OUT]);
void fm_core_mass_matrix(FmCore *c, const double *x, const double *xd, double *M, double *h,
                         double *f);
int fm_core_inertia_slopes(FmCore *c, const double *x, const double *q, const double *qd,
                           const double *qdd, const double *step, int rates, double *out);
double fm_core_factor(FmCore *c, const double *x);  /* scaled conditioning, 0 singular */
/* Static equilibrium in all coordinates (fm_static_saddle) at x (nx) with q (nq: targets of
 * the inputs, references of periodic deformations), constraint stresses mu (nmult) and
 * applied loads (nx): its residual r (ns) and factorised tangent, kept for the next two. */
int fm_core_static_saddle(FmCore *c, const double *x, const double *q, const double *mu,
                          const double *loads, double *r);
/* The kept tangent's solution of `count` right-hand sides (count, ns) in place: over the
 * free coordinates, then the multipliers (constraint stresses); FM_SINGULAR without one. */
int fm_core_static_solve(FmCore *c, double *rhs, int count, int transposed);
/* Whether the mass is regular on the motions the constraints allow at x (nx): the
 * saddle-point matrix [[M, C^T], [C, 0]] factorised; FM_OK, or FM_MASSLESS / FM_SINGULAR. */
int fm_core_mass_regular(FmCore *c, const double *x);
/* M v over the free coordinates at the kept tangent's configuration, v (count, nfree). */
int fm_core_free_mass_times(FmCore *c, const double *v, int count, double *out);
int fm_core_solve(FmCore *c, double *rhs, int count, int transposed);
/* The configuration x (nx) of the last failure, or of the last evaluation. */
void fm_core_configuration(const FmCore *c, double *x);
/* How the core was built: "C, gcc -O3 ... (version), Cython 3.x binding". */
const char *fm_build(void);

#endif
