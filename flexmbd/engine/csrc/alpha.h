/* The generalized-alpha integrator (alpha.c) and what it needs of a system. */
#ifndef FLEXMBD_ALPHA_H
#define FLEXMBD_ALPHA_H

#include "core.h"

/* A second-order system R(t, q, v, a) = 0 in m unknowns. Every function returns FM_OK
 * or an error code; errors that a smaller step may avoid (a position solve that fails
 * at a trial state) are marked by `trial` in the system's error. */
typedef struct {
    int m;
    void *context;
    /* the accelerations a (m) that solve the equations at (t, q, v) */
    int (*accelerations)(void *context, double t, const double *q, const double *v, double *a);
    /* the residual at (t, q, v, a), in whatever form the operator takes (m entries) */
    int (*residual)(void *context, double t, const double *q, const double *v, const double *a,
                    double *r);
    /* a new Newton operator at the state evaluated last, for dq/da = c_q, dv/da = c_v */
    int (*renew)(void *context, double c_q, double c_v);
    /* da = -S^-1 r with the operator of the last renewal */
    int (*apply)(void *context, const double *r, double *da);
    /* output k has been reached at time t with state (q, v) and acceleration a */
    int (*output)(void *context, int k, double t, const double *q, const double *v,
                  const double *a);
    /* after each step: non-zero ends the run there with FM_PARTITION (NULL: never) */
    int (*leave)(void *context, double t, const double *q);
    /* the error of the last failed call */
    FmError *error;
    int *trial;                    /* set by the system when the failure was at a trial state */
} AlphaSystem;

typedef struct {
    double step, rho_inf, rtol, atol;
    int iterations;                /* 0: Newton to the tolerances; k > 0: k corrections */
    /* 1: the step follows the local error estimate, `step` the first one (0: chosen from
     * the state) and max_step its bound; 0: fixed steps of `step` */
    int adaptive;
    double max_step;
    int renew_every;
    /* called every `progress_every` steps; a non-zero return stops the run (interrupt) */
    int (*progress)(void *context, double t);
    void *progress_context;
    double *end;                   /* 2 m or NULL: q and v where the run ended */
} AlphaOptions;

typedef struct {
    long nfev, njev, nlu, nsteps;  /* nfev is counted by the system */
    long nrejected;                /* steps rejected by the error estimate */
    int reached;                   /* outputs reached */
    int status;                    /* FM_OK, or the error code that ended the run */
    double t;                      /* where the run ended */
} AlphaResult;

/* Integrate from times[0] to times[n - 1] starting at (q0, v0); output at every time. */
AlphaResult alpha_run(AlphaSystem *sys, const double *times, int n, const double *q0,
                      const double *v0, const AlphaOptions *options);

#endif
