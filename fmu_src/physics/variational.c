/* Sensitivities of the blade's state (see variational.h; docs/model-notes.md s.8). */
#include "physics/variational.h"

#include <math.h>
#include <string.h>

#include "physics/dynamics_step.h"

enum { Q = 0, V = 1, W = 2 };          /* rows of S */
enum { P_Q0 = 0, P_V0, P_F0, P_B };    /* columns */
enum { PEAK_POS = 0, PEAK_NEG, PEAK_FLOOR };
/* y = (q, q', w, q_2..q_6, q_2'..q_6') in the state vector x (dynamics.h) */
static const int X_OF_Y[SENS_NY_MAX] = {0, 1, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14};
/* rows of the modal coordinate a (0: the tip u) and of its rate; columns of their start values */
#define ROW_Q(a) ((a) == 0 ? Q : SENS_NY + (a) - 1)
#define ROW_V(a) ((a) == 0 ? V : SENS_NY + MODES_MAX - 2 + (a))
#define COL_Q(a) ((a) == 0 ? P_Q0 : SENS_NP + (a) - 1)
#define COL_V(a) ((a) == 0 ? P_V0 : SENS_NP + MODES_MAX - 2 + (a))

/* rows and columns in use: the one-mode block, or all (those above m stay 0) */
static int rowsOf(const DynModel *m) { return m->modes > 1 ? SENS_NY_MAX : SENS_NY; }
static int colsOf(const DynModel *m) { return m->modes > 1 ? SENS_NP_MAX : SENS_NP; }

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
    for (int j = 0; j < SENS_NP_MAX; ++j) e->gPeak[side][j] = sg * e->S[Q][j];
}

static void clearPeaks(DynSens *e)
{
    for (int k = 0; k < SENS_PEAKS; ++k) {
        e->peak[k] = -1.0;
        for (int j = 0; j < SENS_NP_MAX; ++j) e->gPeak[k][j] = 0.0;
    }
}

DynStatus sensInit(const DynModel *m, const DynState *s, double windowMax0, DynSens *e)
{
    memset(e, 0, sizeof *e);
    e->S[Q][P_Q0] = 1.0;
    e->S[V][P_V0] = 1.0;
    e->dB[P_B] = 1.0;
    for (int a = 1; a < m->modes; ++a) { /* the modal coordinates q_2..q_m are start values of their own */
        e->S[ROW_Q(a)][COL_Q(a)] = 1.0;
        e->S[ROW_V(a)][COL_V(a)] = 1.0;
    }
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

/* The contact force's slopes in the mode of s: dF_c/d(q, v, w) = kq, kv, kw, the slider's
 * dw/dt = cV v, and (describing function, gate on) the B slopes dKeq, dCeqOmega / omega: df = 1. */
typedef struct { double kq, kv, kw, cV; int df; } ContactSlopes;

static ContactSlopes contactSlopes(const DynModel *m, const DynState *s, double omega)
{
    ContactSlopes c = {0.0, 0.0, 0.0, 0.0, 0};
    if (m->friction == FrictionMacroslipTD) {
        const double sig = (double)s->side, sd = (double)s->slipDir;
        switch (s->mode) {
        case ContactStick:
            c.kq = m->knCos * m->cosG + m->kd * m->sinG * m->sinG;
            c.kw = -m->kd * m->sinG;
            break;
        case ContactSlip:
            c.kq = m->knCos * m->cosG + sd * sig * m->muKnCos * m->sinG;
            c.cV = m->sinG - sd * sig * m->muKnCosPerKd;
            break;
        default:
            c.cV = m->sinG;
            break;
        }
    } else if (s->mode == GateOn && s->df.regime != RegimeOpen && omega > 0.0) {
        c.kq = s->df.Keq;
        c.kv = s->df.CeqOmega / omega;
        c.df = 1;
    }
    return c;
}

static Linear linearAt(const DynModel *m, const DynState *s, const DynSens *e, double n)
{
    const double Omega = DYN_RAD_PER_RPM * n, omega = m->omegaPerRpm * n;
    const double K0 = m->K0static + m->K0omega2 * Omega * Omega;
    const ContactSlopes c = contactSlopes(m, s, omega);
    Linear a = {0.0, 0.0, 0.0, 0.0, 0.0, 0.0};
    a.cV = c.cV;
    if (c.df) {
        a.bQ = -e->dKeq * m->invM;
        a.bV = -e->dCeqOmega / omega * m->invM;
    }
    a.aQ = -(K0 + c.kq) * m->invM;
    a.aV = -(m->C0 + c.kv) * m->invM;
    a.aW = -c.kw * m->invM;
    return a;
}

/* The live block of S: the describing-function models have no w (dw/dt = 0) and no F0 column;
 * the Jenkins element has no B column (B is an output only). The other entries stay 0. */
#define LIVE_COLS 3
static const int DF_COLS[LIVE_COLS] = {P_Q0, P_V0, P_B};
static const int TD_COLS[LIVE_COLS] = {P_Q0, P_V0, P_F0};

/* dS/dt = A S + (df/dB) dB^T on the live block (ny rows, columns col) at the state x */
static inline void sensRhs(const Linear *a, const DynSens *e, const double x[], int ny, const int col[],
                           const double S[][SENS_NP_MAX], double dS[][SENS_NP_MAX])
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
    double L[4][SENS_NY][SENS_NP_MAX], St[SENS_NY][SENS_NP_MAX];
    const double hh = 0.5 * h, c[3] = {hh, hh, h};
    int k, i, j;
    sensRhs(a[0], e, x[0], ny, col, (const double(*)[SENS_NP_MAX])e->S, L[0]);
    for (k = 0; k < 3; ++k) {
        for (i = 0; i < ny; ++i)
            for (j = 0; j < LIVE_COLS; ++j) St[i][col[j]] = e->S[i][col[j]] + c[k] * L[k][i][col[j]];
        sensRhs(a[k + 1], e, x[k + 1], ny, col, (const double(*)[SENS_NP_MAX])St, L[k + 1]);
    }
    for (i = 0; i < ny; ++i)
        for (j = 0; j < LIVE_COLS; ++j) {
            const int jj = col[j];
            e->S[i][jj] += h / 6.0 * (L[0][i][jj] + 2.0 * (L[1][i][jj] + L[2][i][jj]) + L[3][i][jj]);
        }
}

/* m > 1 modes: dS/dt on all rows and columns at rotor speed n, state x (docs/model.md s.2a):
 * Y' = V, M_y V' = -(K_y(Omega) + kq e1 e1^T) Y - (C_y + kv e1 e1^T) V - e1 (kw W + bB dB^T),
 * W' = cV V_1 (V_1 the tip rate), bB = dKeq u + dCeqOmega / omega u'. */
static void sensRhsModes(const DynModel *m, const DynState *s, const DynSens *e, double n, const double x[],
                         const double S[SENS_NY_MAX][SENS_NP_MAX], double dS[SENS_NY_MAX][SENS_NP_MAX])
{
    const double Omega = DYN_RAD_PER_RPM * n, omega = m->omegaPerRpm * n, O2 = Omega * Omega;
    const ContactSlopes c = contactSlopes(m, s, omega);
    const double bB = c.df ? e->dKeq * x[0] + e->dCeqOmega / omega * x[1] : 0.0;
    const int nm = m->modes;
    memset(dS, 0, sizeof(double) * SENS_NY_MAX * SENS_NP_MAX);
    for (int j = 0; j < SENS_NP_MAX; ++j) {
        double force[MODES_MAX];
        for (int a = 0; a < nm; ++a) {
            double f = 0.0;
            for (int b = 0; b < nm; ++b)
                f -= (m->Ky[a][b] + O2 * m->Ky2[a][b]) * S[ROW_Q(b)][j] + m->Cy[a][b] * S[ROW_V(b)][j];
            force[a] = f;
            dS[ROW_Q(a)][j] = S[ROW_V(a)][j];
        }
        force[0] -= c.kq * S[Q][j] + c.kv * S[V][j] + c.kw * S[W][j] + bB * e->dB[j];
        for (int a = 0; a < nm; ++a) {
            double acc = 0.0;
            for (int b = 0; b < nm; ++b) acc += m->invMy[a][b] * force[b];
            dS[ROW_V(a)][j] = acc;
        }
        dS[W][j] = c.cV * S[V][j];
    }
}

/* RK4 of the variational equations of m > 1 modes over the state's stages */
static void rk4Modes(const DynModel *m, const DynState *s, DynSens *e, double h, const double n[3],
                     const double *const x[4])
{
    double L[4][SENS_NY_MAX][SENS_NP_MAX], St[SENS_NY_MAX][SENS_NP_MAX];
    const double hh = 0.5 * h, c[3] = {hh, hh, h}, nk[4] = {n[0], n[1], n[1], n[2]};
    sensRhsModes(m, s, e, nk[0], x[0], (const double(*)[SENS_NP_MAX])e->S, L[0]);
    for (int k = 0; k < 3; ++k) {
        for (int i = 0; i < SENS_NY_MAX; ++i)
            for (int j = 0; j < SENS_NP_MAX; ++j) St[i][j] = e->S[i][j] + c[k] * L[k][i][j];
        sensRhsModes(m, s, e, nk[k + 1], x[k + 1], (const double(*)[SENS_NP_MAX])St, L[k + 1]);
    }
    for (int i = 0; i < SENS_NY_MAX; ++i)
        for (int j = 0; j < SENS_NP_MAX; ++j)
            e->S[i][j] += h / 6.0 * (L[0][i][j] + 2.0 * (L[1][i][j] + L[2][i][j]) + L[3][i][j]);
}

/* One mode: the live block only (rows q, v and, for the Jenkins element, w; LIVE_COLS columns: at
 * most 9 entries per stage against the 15 x 14 of rk4Modes), kept beside rk4Modes for the reasons
 * of the one-mode step path (solverAdvance, rk4_events.c: measured 3x cheaper per step, results
 * bit-identical to the one-mode model, and the printed formulation has no m-mode form). */
void sensRk4(const DynModel *m, const DynState *s, DynSens *e, double h, const double n[3],
             const double *const x[4])
{
    if (m->modes > 1) {
        rk4Modes(m, s, e, h, n, x);
        return;
    }
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

void sensPeakGradient(const DynSens *e, double g[SENS_NP_MAX])
{
    int top = PEAK_POS, other = PEAK_NEG;
    for (int k = 0; k < SENS_PEAKS; ++k)
        if (e->peak[k] > e->peak[top]) top = k;
    if (top == PEAK_NEG) other = PEAK_POS;
    for (int j = 0; j < SENS_NP_MAX; ++j) g[j] = e->gPeak[top][j];
    if (top != PEAK_FLOOR && e->peak[other] >= 0.0 &&
        e->peak[top] - e->peak[other] <= SENS_SYMMETRIC_RTOL * e->peak[top])
        for (int j = 0; j < SENS_NP_MAX; ++j) g[j] = 0.5 * (e->gPeak[top][j] + e->gPeak[other][j]);
}

DynStatus sensEvent(const DynModel *m, const DynState *before, const DynState *after, DynSwitch sw,
                    const double fMinus[DYN_NX_MAX], const double fPlus[DYN_NX_MAX], DynSens *e)
{
    double gy[SENS_NY], gf = 0.0, dt[SENS_NP_MAX], slope;
    const int ny = rowsOf(m), np = colsOf(m);
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
    /* the event time moves by dt = -(grad g . S) / (grad g . f-) (g depends on q, q', w only) */
    for (j = 0; j < np; ++j) {
        double gs = 0.0;
        for (i = 0; i < SENS_NY; ++i) gs += gy[i] * e->S[i][j];
        dt[j] = gf != 0.0 ? -gs / gf : 0.0;
        if (!isfinite(dt[j])) dt[j] = 0.0;
    }
    if (gf == 0.0) e->grazing += 1;
    /* S+ = H (S- + f- dt) - f+ dt, H the derivative of the discrete update */
    slope = resetSlope(m, after, sw);
    for (j = 0; j < np; ++j) {
        double y[SENS_NY_MAX];
        for (i = 0; i < ny; ++i) y[i] = e->S[i][j] + fMinus[X_OF_Y[i]] * dt[j];
        if (!isnan(slope)) y[W] = slope * y[Q];
        for (i = 0; i < ny; ++i) e->S[i][j] = y[i] - fPlus[X_OF_Y[i]] * dt[j];
    }
    if (sw == DynSwitchExtremum) offerPeak(after, e);
    return DynOk;
}

void sensJenkinsForceGradient(const DynModel *m, const DynState *s, const DynSens *e, double g[SENS_NP_MAX])
{
    const int on = m->friction == FrictionMacroslipTD && s->mode != ContactOpen;
    for (int j = 0; j < SENS_NP_MAX; ++j) g[j] = on ? m->kd * (m->sinG * e->S[Q][j] - e->S[W][j]) : 0.0;
}

/* The columns of the modal start values from the internal ones: u0 = sum_a q_a(0), so
 * d/dq_1(0) = d/du0 and d/dq_a(0) = d/du0 + d/dq_a(0)|_u0 (a >= 2); F0 and B as they are. */
static void modalColumns(const DynModel *m, const double g[SENS_NP_MAX], double out[SENS_MODAL_COLS])
{
    for (int c = 0; c < SENS_MODAL_COLS; ++c) out[c] = 0.0;
    for (int a = 0; a < m->modes; ++a) {
        out[a] = a == 0 ? g[P_Q0] : g[P_Q0] + g[COL_Q(a)];
        out[MODES_MAX + a] = a == 0 ? g[P_V0] : g[P_V0] + g[COL_V(a)];
    }
    out[2 * MODES_MAX] = g[P_F0];
    out[2 * MODES_MAX + 1] = g[P_B];
}

void sensModalJacobian(const DynModel *m, const DynState *s, const DynSens *e,
                       double J[SENS_MODAL_ROWS][SENS_MODAL_COLS])
{
    double g[SENS_NP_MAX];
    memset(J, 0, sizeof(double) * SENS_MODAL_ROWS * SENS_MODAL_COLS);
    for (int a = 0; a < m->modes; ++a) { /* q_1 = u - sum_{a >= 2} q_a, q_a (a >= 2) as they are */
        double gq[SENS_NP_MAX], gv[SENS_NP_MAX];
        for (int j = 0; j < SENS_NP_MAX; ++j) {
            gq[j] = e->S[ROW_Q(a)][j];
            gv[j] = e->S[ROW_V(a)][j];
            if (a == 0)
                for (int b = 1; b < m->modes; ++b) {
                    gq[j] -= e->S[ROW_Q(b)][j];
                    gv[j] -= e->S[ROW_V(b)][j];
                }
        }
        modalColumns(m, gq, J[a]);
        modalColumns(m, gv, J[MODES_MAX + a]);
    }
    sensJenkinsForceGradient(m, s, e, g);
    modalColumns(m, g, J[2 * MODES_MAX]);
    sensPeakGradient(e, g);
    modalColumns(m, g, J[2 * MODES_MAX + 1]);
    modalColumns(m, e->dB, J[2 * MODES_MAX + 2]);
}

int sensFinite(const DynSens *e)
{
    const double *p = &e->S[0][0];
    for (int k = 0; k < SENS_NY_MAX * SENS_NP_MAX; ++k)
        if (!isfinite(p[k])) return 0;
    for (int j = 0; j < SENS_NP_MAX; ++j)
        if (!isfinite(e->dB[j])) return 0;
    return isfinite(e->dKeq) && isfinite(e->dCeqOmega);
}
