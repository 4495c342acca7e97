/* Sensitivities of the blade's state (see variational.h; docs/model-notes.md s.8). */
#include "physics/variational.h"

#include <math.h>
#include <string.h>

#include "physics/dynamics_step.h"

enum { Q = 0, V = 1, W = 2 };          /* rows of S */
enum { P_Q0 = 0, P_V0, P_F0, P_B };    /* columns */
enum { PEAK_POS = 0, PEAK_NEG, PEAK_FLOOR };
static const int X_OF_Y[SENS_NY] = {0, 1, 4}; /* y = (q, q', w) in the state vector x */

/* dK_eq/dB and d(C_eq omega)/dB of the describing function at s->B by central differences
 * (forward ones within a step of d, where the contact opens): relative accuracy ~1e-10. */
static DynStatus describeSlope(const DynModel *m, const DynState *s, DynSens *e)
{
    const FrictionModel dfModel = m->friction == FrictionMacroslipTD ? FrictionMacroslipDF : m->friction;
    DescribingFunction lo, hi;
    double B0 = s->B, h = 1e-6 * s->B, Blo;
    e->dKeq = e->dCeqOmega = 0.0;
    if (m->friction == FrictionMacroslipTD || !(s->B > m->contact.d)) return DynOk; /* no B in eq. 27 */
    Blo = B0 - h > m->contact.d ? B0 - h : B0;
    if (contactDescribe(&m->contact, dfModel, m->projection, B0 + h, &hi) != 0) return DynDescribeFailed;
    if (Blo == B0) lo = s->df;
    else if (contactDescribe(&m->contact, dfModel, m->projection, Blo, &lo) != 0) return DynDescribeFailed;
    e->dKeq = (hi.Keq - lo.Keq) / (B0 + h - Blo);
    e->dCeqOmega = (hi.CeqOmega - lo.CeqOmega) / (B0 + h - Blo);
    return DynOk;
}

/* A candidate for max |q|: |q| at this instant on the side of q, gradient sign(q) dq/dp (exact at
 * an extremum, where q' = 0, and at the start). Keeps the larger per side. */
static void offerPeak(const DynState *s, DynSens *e)
{
    const int side = s->q >= 0.0 ? PEAK_POS : PEAK_NEG;
    const double sg = s->q >= 0.0 ? 1.0 : -1.0;
    if (fabs(s->q) <= e->peak[side]) return;
    e->peak[side] = fabs(s->q);
    for (int j = 0; j < SENS_NP; ++j) e->gPeak[side][j] = sg * e->S[Q][j];
}

static void clearPeaks(DynSens *e)
{
    for (int k = 0; k < SENS_PEAKS; ++k) {
        e->peak[k] = -1.0;
        for (int j = 0; j < SENS_NP; ++j) e->gPeak[k][j] = 0.0;
    }
}

DynStatus sensInit(const DynModel *m, const DynState *s, double windowMax0, DynSens *e)
{
    memset(e, 0, sizeof *e);
    e->S[Q][P_Q0] = 1.0;
    e->S[V][P_V0] = 1.0;
    e->dB[P_B] = 1.0;
    if (m->friction == FrictionMacroslipTD) {
        /* w0 = sin g q0 - F0 / kd (dynInitState); open: w0 = sin g q0; in slip on the cone w0 =
         * sin g q0 - s L(q0) / kd, F0 = s L(q0) moves with q0 (an inward F0 only delays the slip
         * by a stick time O(dF0): no first-order effect) */
        e->S[W][P_Q0] = m->sinG;
        if (s->mode == ContactStick) e->S[W][P_F0] = -1.0 / m->kd;
        else if (s->mode == ContactSlip) e->S[W][P_Q0] = m->sinG - s->slipDir * s->side * m->muKnCosPerKd;
    }
    clearPeaks(e);
    offerPeak(s, e);
    if (windowMax0 > fabs(s->q)) e->peak[PEAK_FLOOR] = windowMax0; /* a constant: gradient 0 */
    return describeSlope(m, s, e);
}

/* The nonzero part of A = d(dy/dt)/dy in the mode of s at rotor speed n: dv/dt = aQ q + aV v +
 * aW w + ..., dw/dt = cV v (eq. 27 and the Jenkins element of model-notes s.2), and d(dv/dt)/dB =
 * bQ q + bV v. */
typedef struct { double aQ, aV, aW, cV, bQ, bV; } Linear;

static Linear linearAt(const DynModel *m, const DynState *s, const DynSens *e, double n)
{
    const double Omega = DYN_RAD_PER_RPM * n, omega = m->omegaPerRpm * n;
    const double K0 = m->K0static + m->K0omega2 * Omega * Omega;
    double kq = 0.0, kv = 0.0, kw = 0.0; /* dF_c/d(q, v, w) */
    Linear a = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    if (m->friction == FrictionMacroslipTD) {
        const double sig = (double)s->side, sd = (double)s->slipDir;
        switch (s->mode) {
        case ContactStick:
            kq = m->knCos * m->cosG + m->kd * m->sinG * m->sinG;
            kw = -m->kd * m->sinG;
            break;
        case ContactSlip:
            kq = m->knCos * m->cosG + sd * sig * m->muKnCos * m->sinG;
            a.cV = m->sinG - sd * sig * m->muKnCosPerKd;
            break;
        default:
            a.cV = m->sinG;
            break;
        }
    } else if (s->mode == GateOn && s->df.regime != RegimeOpen && omega > 0.0) {
        kq = s->df.Keq;
        kv = s->df.CeqOmega / omega;
        a.bQ = -e->dKeq * m->invM;
        a.bV = -e->dCeqOmega / omega * m->invM;
    }
    a.aQ = -(K0 + kq) * m->invM;
    a.aV = -(m->C0 + kv) * m->invM;
    a.aW = -kw * m->invM;
    return a;
}

/* The live block of S: the describing-function models have no w (dw/dt = 0) and no F0 column;
 * the Jenkins element has no B column (B is an output only). The other entries stay 0. */
#define LIVE_COLS 3
static const int DF_COLS[LIVE_COLS] = {P_Q0, P_V0, P_B};
static const int TD_COLS[LIVE_COLS] = {P_Q0, P_V0, P_F0};

/* dS/dt = A S + (df/dB) dB^T on the live block (ny rows, columns col) at the state x */
static inline void sensRhs(const Linear *a, const DynSens *e, const double x[], int ny, const int col[],
                           const double S[SENS_NY][SENS_NP], double dS[SENS_NY][SENS_NP])
{
    const double bB = a->bQ * x[0] + a->bV * x[1];
    for (int k = 0; k < LIVE_COLS; ++k) {
        const int j = col[k];
        dS[Q][j] = S[V][j];
        dS[V][j] = a->aQ * S[Q][j] + a->aV * S[V][j] + bB * e->dB[j];
        if (ny == SENS_NY) {
            dS[V][j] += a->aW * S[W][j];
            dS[W][j] = a->cV * S[V][j];
        }
    }
}

/* RK4 on the live block; inlined with constant ny and col, so the loops unroll */
static inline void rk4Block(const Linear *const a[4], DynSens *e, double h, const double *const x[4], int ny,
                            const int col[])
{
    double L[4][SENS_NY][SENS_NP], St[SENS_NY][SENS_NP];
    const double hh = 0.5 * h, c[3] = {hh, hh, h};
    int k, i, j;
    sensRhs(a[0], e, x[0], ny, col, (const double(*)[SENS_NP])e->S, L[0]);
    for (k = 0; k < 3; ++k) {
        for (i = 0; i < ny; ++i)
            for (j = 0; j < LIVE_COLS; ++j) St[i][col[j]] = e->S[i][col[j]] + c[k] * L[k][i][col[j]];
        sensRhs(a[k + 1], e, x[k + 1], ny, col, (const double(*)[SENS_NP])St, L[k + 1]);
    }
    for (i = 0; i < ny; ++i)
        for (j = 0; j < LIVE_COLS; ++j) {
            const int jj = col[j];
            e->S[i][jj] += h / 6.0 * (L[0][i][jj] + 2.0 * (L[1][i][jj] + L[2][i][jj]) + L[3][i][jj]);
        }
}

void sensRk4(const DynModel *m, const DynState *s, DynSens *e, double h, const double n[3],
             const double *const x[4])
{
    const Linear a0 = linearAt(m, s, e, n[0]);
    const Linear am = n[1] == n[0] ? a0 : linearAt(m, s, e, n[1]);
    const Linear a1 = n[2] == n[1] ? am : linearAt(m, s, e, n[2]);
    const Linear *const a[4] = {&a0, &am, &am, &a1};
    if (m->friction == FrictionMacroslipTD) rk4Block(a, e, h, x, SENS_NY, TD_COLS);
    else rk4Block(a, e, h, x, 2, DF_COLS);
}

/* grad g over y of the switching function sw in the discrete state s (dynSwitching's functions). */
static void switchGradient(const DynModel *m, const DynState *s, DynSwitch sw, double gy[SENS_NY])
{
    const double sig = (double)s->side;
    gy[Q] = gy[V] = gy[W] = 0.0;
    switch (sw) {
    case DynSwitchEnterPos: gy[Q] = -1.0; break;             /* d - q */
    case DynSwitchEnterNeg: gy[Q] = 1.0; break;              /* d + q */
    case DynSwitchLeave: gy[Q] = sig; break;                 /* sigma q - d */
    case DynSwitchSlipPos:                                   /* L - F_f */
        gy[Q] = sig * m->muKnCos - m->kd * m->sinG;
        gy[W] = m->kd;
        break;
    case DynSwitchSlipNeg:                                   /* L + F_f */
        gy[Q] = sig * m->muKnCos + m->kd * m->sinG;
        gy[W] = -m->kd;
        break;
    case DynSwitchStick: gy[V] = 1.0; break;                 /* +-q' (the sign cancels) */
    case DynSwitchExtremum: gy[V] = 1.0; break;
    default: break;                                          /* period end: psi only */
    }
}

/* dw+/dq- of the discrete update (w is reset as a function of q; rows q, q' pass unchanged). */
static double resetSlope(const DynModel *m, const DynState *after, DynSwitch sw)
{
    if (m->friction != FrictionMacroslipTD) return NAN;
    switch (sw) {
    case DynSwitchEnterPos:
    case DynSwitchEnterNeg:
    case DynSwitchSlipPos:
    case DynSwitchSlipNeg:
        if (after->mode == ContactSlip) return m->sinG - after->slipDir * after->side * m->muKnCosPerKd;
        return m->sinG;
    case DynSwitchLeave:
        return m->sinG;
    default:
        return NAN;
    }
}

void sensPeakGradient(const DynSens *e, double g[SENS_NP])
{
    int top = PEAK_POS, other = PEAK_NEG;
    for (int k = 0; k < SENS_PEAKS; ++k)
        if (e->peak[k] > e->peak[top]) top = k;
    if (top == PEAK_NEG) other = PEAK_POS;
    for (int j = 0; j < SENS_NP; ++j) g[j] = e->gPeak[top][j];
    if (top != PEAK_FLOOR && e->peak[other] >= 0.0 &&
        e->peak[top] - e->peak[other] <= SENS_SYMMETRIC_RTOL * e->peak[top])
        for (int j = 0; j < SENS_NP; ++j) g[j] = 0.5 * (e->gPeak[top][j] + e->gPeak[other][j]);
}

DynStatus sensEvent(const DynModel *m, const DynState *before, const DynState *after, DynSwitch sw,
                    const double fMinus[DYN_NX], const double fPlus[DYN_NX], DynSens *e)
{
    double gy[SENS_NY], gf = 0.0, dt[SENS_NP], slope;
    int i, j;
    if (sw == DynSwitchPeriod) {
        /* model-notes s.3: B = max |q| over the period that ends now (|q| at its end included) */
        offerPeak(after, e);
        sensPeakGradient(e, e->dB);
        clearPeaks(e);
        offerPeak(after, e);
        return after->B != before->B ? describeSlope(m, after, e) : DynOk;
    }
    switchGradient(m, before, sw, gy);
    for (i = 0; i < SENS_NY; ++i) gf += gy[i] * fMinus[X_OF_Y[i]];
    /* the event time moves by dt = -(grad g . S) / (grad g . f-) */
    for (j = 0; j < SENS_NP; ++j) {
        double gs = 0.0;
        for (i = 0; i < SENS_NY; ++i) gs += gy[i] * e->S[i][j];
        dt[j] = gf != 0.0 ? -gs / gf : 0.0;
        if (!isfinite(dt[j])) dt[j] = 0.0;
    }
    if (gf == 0.0) e->grazing += 1;
    /* S+ = H (S- + f- dt) - f+ dt, H the derivative of the discrete update */
    slope = resetSlope(m, after, sw);
    for (j = 0; j < SENS_NP; ++j) {
        double y[SENS_NY];
        for (i = 0; i < SENS_NY; ++i) y[i] = e->S[i][j] + fMinus[X_OF_Y[i]] * dt[j];
        if (!isnan(slope)) y[W] = slope * y[Q];
        for (i = 0; i < SENS_NY; ++i) e->S[i][j] = y[i] - fPlus[X_OF_Y[i]] * dt[j];
    }
    if (sw == DynSwitchExtremum) offerPeak(after, e);
    return DynOk;
}

void sensJenkinsForceGradient(const DynModel *m, const DynState *s, const DynSens *e, double g[SENS_NP])
{
    const int on = m->friction == FrictionMacroslipTD && s->mode != ContactOpen;
    for (int j = 0; j < SENS_NP; ++j) g[j] = on ? m->kd * (m->sinG * e->S[Q][j] - e->S[W][j]) : 0.0;
}

int sensFinite(const DynSens *e)
{
    const double *p = &e->S[0][0];
    for (int k = 0; k < SENS_NY * SENS_NP; ++k)
        if (!isfinite(p[k])) return 0;
    for (int j = 0; j < SENS_NP; ++j)
        if (!isfinite(e->dB[j])) return 0;
    return isfinite(e->dKeq) && isfinite(e->dCeqOmega);
}
