/* Banded LU factorisation with partial pivoting (the algorithm of LAPACK's dgbtf2 and
 * dgbtrs, in its storage layout), and an estimate of ||A^-1||_1.
 *
 * One backend serves every square system of a run: D_c and the saddle-point matrix.
 * The band is chosen once per model from a bandwidth-reducing ordering; for a chain
 * of beams it stays narrow, so the cost grows linearly with the number of elements,
 * and for a small or tightly coupled mechanism it is simply the dense matrix.
 *
 * Element (i, j) of A, for max(0, j - ku) <= i <= min(n - 1, j + kl), is stored at
 * ab[kl + ku + i - j + j * ldab] with ldab = 2 kl + ku + 1; the first kl rows hold the
 * fill-in of the row interchanges and must be zero before factorising.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core.h"

#define AB(i, j) b->ab[(size_t)(b->kl + b->ku + (i) - (j)) + (size_t)(j) * b->ldab]

int band_init(Band *b, int n, int kl, int ku)
{
    b->n = n;
    b->kl = kl;
    b->ku = ku;
    b->ldab = 2 * kl + ku + 1;
    b->ab = calloc((size_t)b->ldab * (n > 0 ? n : 1), sizeof(double));
    b->ipiv = calloc(n > 0 ? n : 1, sizeof(int));
    b->work = calloc(2 * (n > 0 ? n : 1), sizeof(double));
    return b->ab && b->ipiv && b->work ? 0 : FM_NO_MEMORY;
}

void band_free(Band *b)
{
    free(b->ab);
    free(b->ipiv);
    free(b->work);
    b->ab = NULL;
    b->ipiv = NULL;
    b->work = NULL;
}

void band_copy(Band *to, const Band *from)
{
    memcpy(to->ab, from->ab, sizeof(double) * (size_t)from->ldab * from->n);
    memcpy(to->ipiv, from->ipiv, sizeof(int) * from->n);
}

int band_factor(Band *b)
{
    const int n = b->n, kl = b->kl, kv = b->kl + b->ku;
    int info = 0, ju = 0;
    for (int j = 0; j < n; j++) {
        const int km = kl < n - 1 - j ? kl : n - 1 - j;
        double *col = &AB(j, j);               /* A(j..j+km, j) is contiguous */
        int p = 0;
        double big = fabs(col[0]);
        for (int i = 1; i <= km; i++)
            if (fabs(col[i]) > big) {
                big = fabs(col[i]);
                p = i;
            }
        b->ipiv[j] = j + p;
        if (!(big > 0.0)) {                    /* zero (or NaN) pivot */
            if (!info)
                info = j + 1;
            continue;
        }
        const int last = j + b->ku + p < n - 1 ? j + b->ku + p : n - 1;
        if (last > ju)
            ju = last;
        if (p)
            for (int c = j; c <= ju; c++) {    /* swap rows j and j + p */
                double *u = &AB(j, c), *w = &AB(j + p, c);
                const double t = *u;
                *u = *w;
                *w = t;
            }
        const double inverse = 1.0 / col[0];
        for (int i = 1; i <= km; i++)
            col[i] *= inverse;
        for (int c = j + 1; c <= ju; c++) {    /* rank-one update of the band */
            const double t = AB(j, c);
            if (t == 0.0)
                continue;
            double *target = &AB(j + 1, c);
            for (int i = 1; i <= km; i++)
                target[i - 1] -= col[i] * t;
        }
    }
    (void)kv;
    return info;
}

void band_solve(const Band *b, double *x)
{
    const int n = b->n, kl = b->kl, kv = b->kl + b->ku;
    for (int j = 0; j < n - 1; j++) {          /* L, with the interchanges */
        const int lm = kl < n - 1 - j ? kl : n - 1 - j;
        const int l = b->ipiv[j];
        if (l != j) {
            const double t = x[l];
            x[l] = x[j];
            x[j] = t;
        }
        const double xj = x[j];
        if (xj != 0.0) {
            const double *col = &AB(j, j);
            for (int i = 1; i <= lm; i++)
                x[j + i] -= col[i] * xj;
        }
    }
    for (int j = n - 1; j >= 0; j--) {         /* U, bandwidth kl + ku above the diagonal */
        const double *col = &AB(j, j);
        const double xj = x[j] / col[0];
        x[j] = xj;
        const int top = kv < j ? kv : j;
        for (int i = 1; i <= top; i++)
            x[j - i] -= col[-i] * xj;
    }
}

/* A X = R for k right-hand sides at once, in place: x holds R row by row, (n, k), the k
 * values of a row side by side, so every step of the substitutions runs along a row.
 * Each column gets the operations band_solve would give it, in the same order. */
void band_solve_many(const Band *b, double *x, int k)
{
    const int n = b->n, kl = b->kl, kv = b->kl + b->ku;
    for (int j = 0; j < n - 1; j++) {          /* L, with the interchanges */
        const int lm = kl < n - 1 - j ? kl : n - 1 - j;
        double *xj = x + (size_t)j * k;
        const int l = b->ipiv[j];
        if (l != j) {
            double *xl = x + (size_t)l * k;
            for (int c = 0; c < k; c++) {
                const double t = xl[c];
                xl[c] = xj[c];
                xj[c] = t;
            }
        }
        const double *col = &AB(j, j);
        for (int i = 1; i <= lm; i++) {
            const double a = col[i];
            double *xi = x + (size_t)(j + i) * k;
            for (int c = 0; c < k; c++)
                xi[c] -= a * xj[c];
        }
    }
    for (int j = n - 1; j >= 0; j--) {         /* U, bandwidth kl + ku above the diagonal */
        const double *col = &AB(j, j);
        double *xj = x + (size_t)j * k;
        for (int c = 0; c < k; c++)
            xj[c] /= col[0];
        const int top = kv < j ? kv : j;
        for (int i = 1; i <= top; i++) {
            const double a = col[-i];
            double *xi = x + (size_t)(j - i) * k;
            for (int c = 0; c < k; c++)
                xi[c] -= a * xj[c];
        }
    }
}

void band_solve_t(const Band *b, double *x)
{
    const int n = b->n, kl = b->kl, kv = b->kl + b->ku;
    for (int j = 0; j < n; j++) {              /* U^T */
        const double *col = &AB(j, j);
        double s = x[j];
        const int top = kv < j ? kv : j;
        for (int i = 1; i <= top; i++)
            s -= col[-i] * x[j - i];
        x[j] = s / col[0];
    }
    for (int j = n - 2; j >= 0; j--) {         /* L^T, then the interchanges backwards */
        const int lm = kl < n - 1 - j ? kl : n - 1 - j;
        const double *col = &AB(j, j);
        double s = x[j];
        for (int i = 1; i <= lm; i++)
            s -= col[i] * x[j + i];
        x[j] = s;
        const int l = b->ipiv[j];
        if (l != j) {
            const double t = x[l];
            x[l] = x[j];
            x[j] = t;
        }
    }
}

static double norm1(const double *x, int n)
{
    double s = 0.0;
    for (int i = 0; i < n; i++)
        s += fabs(x[i]);
    return s;
}

double band_min_pivot(const Band *b)
{
    double smallest = INFINITY;
    for (int j = 0; j < b->n; j++) {
        const double u = fabs(AB(j, j));
        if (!(u >= smallest))
            smallest = u;                       /* also NaN */
    }
    return smallest;
}

/* ||A^-1 e_j||_1: the norm of column j of the inverse, one solve (a lower bound of ||A^-1||_1). */
double band_column_norm(Band *b, int j)
{
    double *x = b->work;
    memset(x, 0, sizeof(double) * b->n);
    x[j] = 1.0;
    band_solve(b, x);
    return norm1(x, b->n);
}

/* Hager's method with Higham's refinements (the estimator of LAPACK's dlacn2) for
 * ||A^-1||_1 from solves with A and A^T, plus Higham's alternating-sign vector. `column`
 * is set to the column of the inverse the estimate found largest (-1 when the alternating
 * vector gave it), for band_column_norm to follow later. */
double band_inverse_norm(Band *b, int *column)
{
    const int n = b->n;
    *column = -1;
    if (n == 0)
        return 0.0;
    double *x = b->work, *z = b->work + n;
    for (int i = 0; i < n; i++)
        x[i] = 1.0 / n;
    band_solve(b, x);
    double estimate = norm1(x, n);
    int j = 0;
    for (int iteration = 0; iteration < 5; iteration++) {
        for (int i = 0; i < n; i++)
            z[i] = x[i] >= 0.0 ? 1.0 : -1.0;
        band_solve_t(b, z);
        int jmax = 0;
        for (int i = 1; i < n; i++)
            if (fabs(z[i]) > fabs(z[jmax]))
                jmax = i;
        if (iteration > 0 && jmax == j)
            break;
        j = jmax;
        memset(x, 0, sizeof(double) * n);
        x[j] = 1.0;
        band_solve(b, x);
        const double next = norm1(x, n);
        if (!(next > estimate)) {
            if (next != next)
                estimate = next;                /* NaN */
            break;
        }
        estimate = next;
        *column = j;
    }
    for (int i = 0; i < n; i++)                 /* Higham's extra vector */
        x[i] = (i % 2 ? -1.0 : 1.0) * (1.0 + (n > 1 ? (double)i / (n - 1) : 0.0));
    band_solve(b, x);
    const double alternating = 2.0 * norm1(x, n) / (3.0 * n);
    if (alternating > estimate) {
        *column = -1;
        return alternating;
    }
    return estimate;
}
