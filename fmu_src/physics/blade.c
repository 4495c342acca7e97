/* Galerkin reduction of the rotating cantilever with a tip mass (paper eq. 19-27, docs/model.md s.2).
 *
 * The mode of eq. 20 is written with the four positive-term functions of z = lambda x
 *   chp = cosh z + cos z, shp = sinh z + sin z, chc = cosh z - cos z, shs = sinh z - sin z,
 * evaluated by their power series (every term positive, so no cancellation for small z):
 *   phi    = s chc - shs,              phi'   = lambda   (s shp - chc),
 *   phi''  = lambda^2 (s chp - shp),   phi''' = lambda^3 (s shs - chp),   phi'''' = lambda^4 phi,
 * with s = shp(lambda l) / chp(lambda l) (so phi''(l) = 0). The first root of eq. 21 always lies
 * in (0, 1.8751] (R >= 0 only lowers it), so the series are only ever evaluated for z <= 1.9.
 * Integrals use composite Gauss-Legendre quadrature (the integrands are entire functions of z on
 * a short interval: 2 panels x 16 nodes are exact to rounding). No allocation, no global state. */
#include "blade.h"
#include "physics/gauss_legendre.h"

#include <math.h>
#include <string.h>
#include <stddef.h>

#define GL_NODES GAUSS_LEGENDRE_NODES /* Gauss-Legendre nodes per panel */
#define GL_PANELS 2   /* panels on [0, l] */
#define SERIES_TERMS 34 /* z^n/n!, n < 34: (1.9)^34/34! < 1e-28 */
#define ROOT_SCAN_MAX 1.9  /* eq. 21 changes sign in (0, 1.9] for every R >= 0 */
#define ROOT_SCAN_STEPS 190

typedef struct {
    double chp; /* cosh z + cos z [-] */
    double shp; /* sinh z + sin z [-] */
    double chc; /* cosh z - cos z [-] */
    double shs; /* sinh z - sin z [-] */
} TrigHyp;

/* The four combinations by their Taylor series: term z^n/n! goes to chp (n = 0 mod 4),
 * shp (1 mod 4), chc (2 mod 4), shs (3 mod 4), each doubled. Valid for 0 <= z <= ~3. */
static TrigHyp trigHyp(double z) {
    double sums[4] = {0.0, 0.0, 0.0, 0.0};
    double term = 1.0;
    int n;
    TrigHyp t;
    for (n = 0; n < SERIES_TERMS; ++n) {
        if (n > 0) term *= z / (double)n;
        sums[n % 4] += term;
    }
    t.chp = 2.0 * sums[0];
    t.shp = 2.0 * sums[1];
    t.chc = 2.0 * sums[2];
    t.shs = 2.0 * sums[3];
    return t;
}

/* Eq. 21 with a = lambda l: 1 + cos a cosh a + R a (cos a sinh a - sin a cosh a), written as
 * 1 + (chp^2 - chc^2)/4 + R a (chp shs - chc shp)/2 (both pieces free of small-a cancellation). */
static double frequencyEquation(double a, double R) {
    TrigHyp t = trigHyp(a);
    return 1.0 + 0.25 * (t.chp * t.chp - t.chc * t.chc) + 0.5 * R * a * (t.chp * t.shs - t.chc * t.shp);
}

/* First positive root of eq. 21: scan from a = 0 (value 2 > 0) for the first sign change, then
 * bisect until the midpoint equals an end point (full double precision). Returns -1 on failure. */
static double firstRoot(double R) {
    double lo = 0.0, hi = 0.0, flo = 2.0, fhi = 0.0;
    int k, found = 0;
    for (k = 1; k <= ROOT_SCAN_STEPS; ++k) {
        hi = ROOT_SCAN_MAX * (double)k / (double)ROOT_SCAN_STEPS;
        fhi = frequencyEquation(hi, R);
        if (!isfinite(fhi)) return -1.0;
        if (fhi <= 0.0) { found = 1; break; }
        lo = hi;
        flo = fhi;
    }
    if (!found) return -1.0;
    if (fhi == 0.0) return hi;
    for (k = 0; k < 2200; ++k) {
        double mid = 0.5 * (lo + hi);
        double fm;
        if (mid <= lo || mid >= hi) break;
        fm = frequencyEquation(mid, R);
        if (fm == 0.0) return mid;
        if ((fm > 0.0) == (flo > 0.0)) { lo = mid; flo = fm; } else { hi = mid; }
    }
    return 0.5 * (lo + hi);
}

static int allFinite(const double *v, size_t n) {
    size_t i;
    for (i = 0; i < n; ++i)
        if (!isfinite(v[i])) return 0;
    return 1;
}

int bladeReduce(const BladeParams *p, Formulation formulation, BladeReduction *out) {
    double R, aL, lambda, s, l, rhoA, xs[GL_NODES], ws[GL_NODES];
    double U1 = 0.0, U3 = 0.0, U4 = 0.0, U5 = 0.0, intPhi = 0.0, intD2sq = 0.0;
    double intD1sq = 0.0, intD1sqW = 0.0; /* int phi'^2, int (l^2 - x^2) phi'^2 */
    double u2, lam2;
    TrigHyp tl;
    int panel, i;
    if (p == NULL || out == NULL) return 1;
    if (formulation != FormulationPrinted && formulation != FormulationConsistent) return 2;
    {
        double v[6];
        v[0] = p->EI; v[1] = p->rho; v[2] = p->A; v[3] = p->l; v[4] = p->c; v[5] = p->m0;
        if (!allFinite(v, 6)) return 3;
    }
    if (!(p->EI > 0.0) || !(p->rho > 0.0) || !(p->A > 0.0) || !(p->l > 0.0)) return 3;
    if (p->c < 0.0 || p->m0 < 0.0) return 3;

    l = p->l;
    rhoA = p->rho * p->A;
    R = p->m0 / (rhoA * l); /* eq. 21 mass ratio [-] */
    if (!isfinite(R) || !(rhoA > 0.0)) return 3;
    aL = firstRoot(R);
    if (!(aL > 0.0)) return 4;
    lambda = aL / l;
    lam2 = lambda * lambda;
    tl = trigHyp(aL);
    s = tl.shp / tl.chp;        /* eq. 20 coefficient */
    u2 = s * tl.chc - tl.shs;   /* phi(l), eq. 24 */

    gaussLegendre16(xs, ws);
    for (panel = 0; panel < GL_PANELS; ++panel) {
        double x0 = l * (double)panel / GL_PANELS, half = 0.5 * l / GL_PANELS;
        for (i = 0; i < GL_NODES; ++i) {
            double x = x0 + half * (1.0 + xs[i]), w = half * ws[i];
            TrigHyp t = trigHyp(lambda * x);
            double ph = s * t.chc - t.shs;                 /* phi   (eq. 20) */
            double d1 = lambda * (s * t.shp - t.chc);      /* phi'  */
            double d2 = lam2 * (s * t.chp - t.shp);        /* phi'' */
            U1 += w * ph * ph;
            U3 += w * x * ph * d1;
            U4 += w * d2 * ph * (l * l - x * x);
            U5 += w * ph * d2;
            intPhi += w * ph;
            intD2sq += w * d2 * d2;
            intD1sq += w * d1 * d1;
            intD1sqW += w * (l * l - x * x) * d1 * d1;
        }
    }

    out->lambdaL = aL;
    out->U1 = U1;
    out->U2 = lam2 * lam2 * U1; /* docs/model.md fix of eq. 24: int phi phi'''' = lambda^4 U1 */
    out->U3 = U3;
    out->U4 = U4;
    out->U5 = U5;
    out->intPhi = intPhi;
    out->u2 = u2;
    out->loadGain = intPhi / u2; /* docs/model-notes.md s.2: G in both formulations */
    if (formulation == FormulationPrinted) {
        /* eq. 26 */
        out->M = rhoA * U1 / u2;
        out->C0 = p->c * U1 / u2;
        out->K0static = p->EI * out->U2 / u2;
        out->K0omega2 = (rhoA * U3 - 0.5 * rhoA * U4 - p->m0 * l * U5) / u2;
    } else {
        /* docs/model.md s.2 consistent (energy) form with phi / phi(l): centrifugal prestress eq. 16 */
        double u22 = u2 * u2;
        out->M = rhoA * U1 / u22 + p->m0;
        out->C0 = p->c * U1 / u22;
        out->K0static = p->EI * intD2sq / u22;
        out->K0omega2 = (0.5 * rhoA * intD1sqW + p->m0 * l * intD1sq) / u22;
    }
    {
        double v[13];
        v[0] = out->lambdaL; v[1] = out->U1; v[2] = out->U2; v[3] = out->U3; v[4] = out->U4;
        v[5] = out->U5; v[6] = out->intPhi; v[7] = out->u2; v[8] = out->M; v[9] = out->C0;
        v[10] = out->K0static; v[11] = out->K0omega2; v[12] = out->loadGain;
        if (!allFinite(v, 13) || !(out->M > 0.0) || !(u2 > 0.0)) return 5;
    }
    return 0;
}

double bladeK0(const BladeReduction *r, double Omega) {
    if (r == NULL) return NAN;
    return r->K0static + r->K0omega2 * Omega * Omega;
}

BladeParams bladeParamsOf(const double v[6])
{
    BladeParams bp;
    bp.EI = v[0];
    bp.rho = v[1];
    bp.A = v[2];
    bp.l = v[3];
    bp.c = v[4];
    bp.m0 = v[5];
    return bp;
}

int bladeReduceReusing(BladeReductionCache *c, const BladeParams *p, Formulation formulation, BladeReduction *out)
{
    int rc;
    if (c->valid && c->formulation == formulation && memcmp(&c->params, p, sizeof *p) == 0) {
        *out = c->reduction;
        return 0;
    }
    c->valid = 0;
    rc = bladeReduce(p, formulation, out);
    if (rc == 0) {
        c->params = *p;
        c->formulation = formulation;
        c->reduction = *out;
        c->valid = 1;
    }
    return rc;
}
