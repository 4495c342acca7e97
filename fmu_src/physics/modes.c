/* The blade as m bending modes (see modes.h; docs/model.md s.2a).
 *
 * Mode i of eq. 20 with z = lambda_i x and s = (sinh L + sin L) / (cosh L + cos L), L = lambda_i l,
 * written without the cancellation of cosh z - sinh z at large z (modes 2..6 have L up to ~17):
 *   s - 1 = (sin L - cos L - e^-L) / (cosh L + cos L) =: sm1,
 *   phi        = sm1 cosh z + e^-z - s cos z + sin z,
 *   phi'  / l. = sm1 sinh z - e^-z + s sin z + cos z,
 *   phi'' / l.^2 = sm1 cosh z + e^-z + s cos z - sin z,
 * each divided by phi(l) so that the tip displacement is sum_i q_i. The integrals use composite
 * Gauss-Legendre quadrature (8 panels x 16 nodes: mode 6 oscillates ~3 times over l, the products
 * of two modes ~6 times, each panel sees < 1 period). */
#include "physics/modes.h"
#include "physics/gauss_legendre.h"

#include <math.h>
#include <stddef.h>
#include <string.h>

#define MODES_PI 3.14159265358979323846
#define GL_NODES GAUSS_LEGENDRE_NODES
#define GL_PANELS 8
#define SCAN_STEP 0.01 /* eq. 21's roots are ~pi apart: a scan step far below that misses none */

/* eq. 21 divided by cosh a (same sign, no overflow):
 * 1/cosh a + cos a + R a (cos a tanh a - sin a) */
static double frequencyEquationScaled(double a, double R)
{
    return 1.0 / cosh(a) + cos(a) + R * a * (cos(a) * tanh(a) - sin(a));
}

/* The first m positive roots of eq. 21 (scan for sign changes from a = 0, where the value is 2,
 * then bisection to full precision). Returns 0 or nonzero if fewer than m are found. */
static int roots(double R, int m, double out[MODES_MAX])
{
    double lo = 0.0, flo = 2.0;
    int found = 0;
    for (long k = 1; found < m && k < 100000; ++k) {
        double hi = SCAN_STEP * (double)k, fhi = frequencyEquationScaled(hi, R);
        if (!isfinite(fhi)) return 1;
        if ((fhi > 0.0) != (flo > 0.0) || fhi == 0.0) {
            double a = lo, b = hi, fa = flo;
            for (int it = 0; it < 2200; ++it) {
                double mid = 0.5 * (a + b), fm;
                if (mid <= a || mid >= b) break;
                fm = frequencyEquationScaled(mid, R);
                if (fm == 0.0) { a = b = mid; break; }
                if ((fm > 0.0) == (fa > 0.0)) { a = mid; fa = fm; } else { b = mid; }
            }
            out[found++] = 0.5 * (a + b);
        }
        lo = hi;
        flo = fhi;
    }
    return found == m ? 0 : 1;
}

/* One mode: lambda [1/m], s, s - 1 and 1 / phi(l). */
typedef struct { double lambda, s, sm1, invTip; } Shape;

static Shape shapeOf(double lambdaL, double l)
{
    Shape h;
    const double L = lambdaL;
    h.lambda = lambdaL / l;
    h.sm1 = (sin(L) - cos(L) - exp(-L)) / (cosh(L) + cos(L));
    h.s = 1.0 + h.sm1;
    h.invTip = 1.0 / (h.sm1 * cosh(L) + exp(-L) - h.s * cos(L) + sin(L));
    return h;
}

/* phi, phi', phi'' of a mode at x (scaled to phi(l) = 1) */
static void shapeAt(const Shape *h, double x, double d[3])
{
    const double z = h->lambda * x, ch = cosh(z), sh = sinh(z), e = exp(-z), c = cos(z), s = sin(z);
    d[0] = h->invTip * (h->sm1 * ch + e - h->s * c + s);
    d[1] = h->invTip * h->lambda * (h->sm1 * sh - e + h->s * s + c);
    d[2] = h->invTip * h->lambda * h->lambda * (h->sm1 * ch + e + h->s * c - s);
}

double modesRootCurvature(double lambdaL, double l)
{
    const Shape h = shapeOf(lambdaL, l);
    double d[3];
    shapeAt(&h, 0.0, d);
    return d[2];
}

int modesReduce(const BladeParams *p, int m, ModalReduction *out)
{
    double xs[GL_NODES], ws[GL_NODES], rhoA, l, R;
    Shape shape[MODES_MAX];
    if (p == NULL || out == NULL || m < 1 || m > MODES_MAX) return 1;
    if (!(p->EI > 0.0) || !(p->rho > 0.0) || !(p->A > 0.0) || !(p->l > 0.0) || !(p->c >= 0.0) ||
        !(p->m0 >= 0.0) || !isfinite(p->EI * p->rho * p->A * p->l * p->c * p->m0))
        return 2;
    memset(out, 0, sizeof *out);
    out->m = m;
    l = p->l;
    rhoA = p->rho * p->A;
    R = p->m0 / (rhoA * l); /* eq. 21 mass ratio */
    if (!isfinite(R) || roots(R, m, out->lambdaL) != 0) return 3;
    for (int i = 0; i < m; ++i) {
        shape[i] = shapeOf(out->lambdaL[i], l);
        out->curvature0[i] = modesRootCurvature(out->lambdaL[i], l);
    }
    gaussLegendre16(xs, ws);
    for (int panel = 0; panel < GL_PANELS; ++panel) {
        const double x0 = l * (double)panel / GL_PANELS, half = 0.5 * l / GL_PANELS;
        for (int k = 0; k < GL_NODES; ++k) {
            const double x = x0 + half * (1.0 + xs[k]), w = half * ws[k];
            const double tension = 0.5 * rhoA * (l * l - x * x) + p->m0 * l; /* eq. 16 per Omega^2 */
            double d[MODES_MAX][3];
            for (int i = 0; i < m; ++i) shapeAt(&shape[i], x, d[i]);
            for (int i = 0; i < m; ++i) {
                out->load[i] += w * d[i][0];
                for (int j = 0; j < m; ++j) {
                    out->M[i][j] += w * rhoA * d[i][0] * d[j][0];
                    out->C[i][j] += w * p->c * d[i][0] * d[j][0];
                    out->Kstatic[i][j] += w * p->EI * d[i][2] * d[j][2];
                    out->Komega2[i][j] += w * tension * d[i][1] * d[j][1];
                }
            }
        }
    }
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) out->M[i][j] += p->m0; /* phi_i(l) phi_j(l) = 1 */
    for (int i = 0; i < m; ++i) {
        if (!isfinite(out->load[i]) || !isfinite(out->curvature0[i])) return 4;
        for (int j = 0; j < m; ++j)
            if (!isfinite(out->M[i][j] + out->C[i][j] + out->Kstatic[i][j] + out->Komega2[i][j])) return 4;
    }
    return 0;
}

/* Cholesky M = L L^T (lower). Returns 0 or nonzero if M is not positive definite. */
static int cholesky(int m, const double *M, double L[MODES_MAX][MODES_MAX])
{
    memset(L, 0, sizeof(double) * MODES_MAX * MODES_MAX);
    for (int j = 0; j < m; ++j) {
        double d = M[j * MODES_MAX + j];
        for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
        if (!(d > 0.0)) return 1;
        L[j][j] = sqrt(d);
        for (int i = j + 1; i < m; ++i) {
            double v = M[i * MODES_MAX + j];
            for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
            L[i][j] = v / L[j][j];
        }
    }
    return 0;
}

/* X = L^-1 B (forward substitution, column by column) */
static void lowerSolve(int m, double L[MODES_MAX][MODES_MAX], const double *B,
                       double X[MODES_MAX][MODES_MAX])
{
    for (int c = 0; c < m; ++c)
        for (int i = 0; i < m; ++i) {
            double v = B[i * MODES_MAX + c];
            for (int k = 0; k < i; ++k) v -= L[i][k] * X[k][c];
            X[i][c] = v / L[i][i];
        }
}

int modesInverse(int m, const double *M, double inv[MODES_MAX][MODES_MAX])
{
    double L[MODES_MAX][MODES_MAX], I[MODES_MAX][MODES_MAX], Y[MODES_MAX][MODES_MAX];
    if (cholesky(m, M, L) != 0) return 1;
    memset(I, 0, sizeof I);
    for (int i = 0; i < m; ++i) I[i][i] = 1.0;
    lowerSolve(m, L, &I[0][0], Y); /* Y = L^-1; M^-1 = Y^T Y */
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) {
            double v = 0.0;
            for (int k = 0; k < m; ++k) v += Y[k][i] * Y[k][j];
            inv[i][j] = v;
        }
    return 0;
}

int modesEigenvalues(int m, const double *M, const double *K,
                     double lambda[MODES_MAX])
{
    double L[MODES_MAX][MODES_MAX], X[MODES_MAX][MODES_MAX], XT[MODES_MAX][MODES_MAX], A[MODES_MAX][MODES_MAX];
    if (cholesky(m, M, L) != 0) return 1;
    lowerSolve(m, L, K, X); /* X = L^-1 K */
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < m; ++j) XT[i][j] = X[j][i];
    lowerSolve(m, L, &XT[0][0], A); /* A = L^-1 K L^-T (symmetric) */
    for (int i = 0; i < m; ++i)
        for (int j = 0; j < i; ++j) A[i][j] = A[j][i] = 0.5 * (A[i][j] + A[j][i]);
    for (int sweep = 0; sweep < 100; ++sweep) { /* cyclic Jacobi rotations */
        double off = 0.0, diag = 0.0;
        for (int i = 0; i < m; ++i) {
            diag += A[i][i] * A[i][i];
            for (int j = i + 1; j < m; ++j) off += A[i][j] * A[i][j];
        }
        if (off <= 1e-32 * diag) break;
        for (int p = 0; p < m; ++p)
            for (int q = p + 1; q < m; ++q) {
                double th, t, c, s;
                if (A[p][q] == 0.0) continue;
                th = (A[q][q] - A[p][p]) / (2.0 * A[p][q]);
                t = (th >= 0.0 ? 1.0 : -1.0) / (fabs(th) + sqrt(th * th + 1.0));
                c = 1.0 / sqrt(t * t + 1.0);
                s = t * c;
                for (int k = 0; k < m; ++k) { /* A <- A J (columns p, q) */
                    const double akp = A[k][p], akq = A[k][q];
                    A[k][p] = c * akp - s * akq;
                    A[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < m; ++k) { /* A <- J^T A (rows p, q) */
                    const double apk = A[p][k], aqk = A[q][k];
                    A[p][k] = c * apk - s * aqk;
                    A[q][k] = s * apk + c * aqk;
                }
            }
    }
    for (int i = 0; i < m; ++i) lambda[i] = A[i][i];
    for (int i = 1; i < m; ++i) /* ascending (insertion sort) */
        for (int j = i; j > 0 && lambda[j - 1] > lambda[j]; --j) {
            const double t = lambda[j];
            lambda[j] = lambda[j - 1];
            lambda[j - 1] = t;
        }
    return 0;
}
