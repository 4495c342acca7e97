/* Integrator of the one-mode blade with shroud contact (docs/model-notes.md s.1-s.3, s.6).
 *
 * Equation of motion (eq. 27, model-notes s.2):
 *   M q'' + C0 q' + K0(Omega) q = G f_w(t) - F_c,   psi' = omega,   E' = C0 q'^2 + P.
 * The discrete state (gate, Jenkins mode, side, slip direction) is pinned during a step, so the
 * right-hand side is smooth inside every step; the switching functions below are checked on the
 * cubic Hermite interpolant of each accepted RK4 step and the step is redone up to the first
 * switching instant. Every switching function g is written so that the current discrete state
 * is consistent while g >= 0; it triggers at the first instant where g < 0. */
#include "solver.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define TWO_PI 6.283185307179586476925286766559
#define NO_EVENT 2.0 /* "theta" of a function that does not trigger in the step */

/* Event codes internal to this file (more specific than SolverEventKind). */
typedef enum {
    EvNone = 0, EvEnterPos, EvEnterNeg, EvLeave, EvSlipPos, EvSlipNeg, EvStick, EvPeriod, EvExtremum
} Ev;

/* ------------------------------------------------------------------------------------------- */
/* Inputs (model-notes s.1): Taylor polynomials in tau = t - t_k.                                 */

void solverSetInputs(SolverInputs *in, const double deriv[SOLVER_NUM_INPUTS][SOLVER_MAX_ORDER + 1])
{
    for (int i = 0; i < SOLVER_NUM_INPUTS; ++i) {
        double fact = 1.0; /* j! */
        in->top[i] = 0;
        for (int j = 0; j <= SOLVER_MAX_ORDER; ++j) {
            if (j > 0) fact *= (double)j;
            in->coef[i][j] = deriv[i][j] / fact;
            if (j > 0 && in->coef[i][j] != 0.0) in->top[i] = j;
        }
    }
}

static inline double inputAt(const SolverInputs *in, int i, double tau)
{
    const double *c = in->coef[i];
    double u = c[in->top[i]];
    for (int j = in->top[i] - 1; j >= 0; --j) u = u * tau + c[j];
    return u;
}

double solverInputAt(const SolverInputs *in, int i, double tau) { return inputAt(in, i, tau); }

/* ------------------------------------------------------------------------------------------- */
/* Model constants                                                                              */

int solverBuildModel(SolverModel *m, const BladeReduction *r, const ContactParams *cp,
                     FrictionModel friction, Projection projection, int gating, int tracked,
                     int engineOrder)
{
    memset(m, 0, sizeof *m);
    if (!(r->M > 0.0) || !isfinite(r->M) || engineOrder < 1) return 1;
    m->friction = friction;
    m->projection = projection;
    m->gating = gating ? 1 : 0;
    m->tracked = tracked ? 1 : 0;
    m->contact = *cp;
    m->invM = 1.0 / r->M;
    m->C0 = r->C0;
    m->K0static = r->K0static;
    m->K0omega2 = r->K0omega2;
    m->G = r->loadGain;
    m->OmegaPerRpm = TWO_PI / 60.0;
    m->omegaPerRpm = (double)engineOrder * TWO_PI / 60.0;
    m->d = cp->d;
    m->sinG = sin(cp->gamma);
    m->cosG = cos(cp->gamma);
    m->kd = cp->kdRatio * cp->kn;
    m->knCos = cp->kn * m->cosG;
    m->muKnCos = cp->mu * cp->kn * m->cosG;
    m->muKnCosPerKd = m->muKnCos / m->kd;
    /* model-notes s.2: slip at entry iff kd sin g > mu kn cos g */
    m->stickAtEntry = !(m->kd * m->sinG > m->muKnCos);
    return 0;
}

SolverStatus solverUpdateDescribe(const SolverModel *m, SolverState *s)
{
    /* the Jenkins element reports the macroslip DF (model-notes s.4) */
    const FrictionModel dfModel = m->friction == FrictionMacroslipTD ? FrictionMacroslipDF : m->friction;
    DescribingFunction df;
    memset(&s->df, 0, sizeof s->df);
    s->df.regime = RegimeOpen;
    if (!(s->B > m->d)) return SolverOk; /* MODEL.md s.3: B <= d is the open regime, all zero */
    /* nonzero also for a non-finite result (contactDescribe checks every field) */
    if (contactDescribe(&m->contact, dfModel, m->projection, s->B, &df) != 0) return SolverDescribeFailed;
    s->df = df;
    return SolverOk;
}

static void enterContact(const SolverModel *m, SolverState *s, int side)
{
    s->side = side;
    s->w = m->sinG * s->q; /* the spring is unloaded on arrival (model-notes s.2) */
    if (m->stickAtEntry) {
        s->mode = ContactStick;
    } else {
        const double L = m->muKnCos * (side * s->q - m->d);
        s->mode = ContactSlip;
        s->slipDir = s->v > 0.0 ? 1 : (s->v < 0.0 ? -1 : side);
        s->w = m->sinG * s->q - s->slipDir * L / m->kd;
    }
}

double solverStartForceLimit(const SolverModel *m, double q0)
{
    const double sig = q0 >= 0.0 ? 1.0 : -1.0;
    if (!(fabs(q0) > m->d)) return -1.0;
    return m->muKnCos * (sig * q0 - m->d); /* L = mu |F_n| (eq. 3) */
}

/* Jenkins element starting in contact with spring force F0 (model-notes s.7). */
static void initContactForce(const SolverModel *m, SolverState *s, double F0)
{
    const double L = solverStartForceLimit(m, s->q);
    s->mode = ContactStick;
    s->w = m->sinG * s->q - F0 / m->kd; /* F_f = kd (Delta_u - w) = F0 */
    if (fabs(F0) >= L * (1.0 - SOLVER_CONE_RTOL)) {
        /* on the cone: slip goes on while the slip rate is >= 0, the test of detect() for EvStick */
        const int dir = F0 > 0.0 ? 1 : -1;
        const double cs = dir * m->kd * m->sinG - s->side * m->muKnCos;
        if (cs * s->v >= 0.0) {
            s->mode = ContactSlip;
            s->slipDir = dir;
            s->w = m->sinG * s->q - dir * L / m->kd; /* F_f = s L exactly */
        }
    }
}

SolverStatus solverInitState(const SolverModel *m, SolverState *s, double q0, double v0, double E0,
                             double F0, double B0, double windowMax0)
{
    memset(s, 0, sizeof *s);
    s->q = q0;
    s->v = v0;
    s->psi = 0.0;
    s->E = E0;
    s->w = m->sinG * q0;
    s->B = B0;
    /* the period before the start may have reached further than |q0| (a restarted run) */
    s->windowMax = fabs(q0);
    if (windowMax0 > s->windowMax) s->windowMax = windowMax0;
    s->periods = 0.0;
    s->side = q0 >= 0.0 ? 1 : -1;
    s->slipDir = s->side;
    s->vdir = v0 >= 0.0 ? 1 : -1;
    if (m->friction == FrictionMacroslipTD) {
        /* inside the contact with the spring unloaded (F0 = 0): inside the cone, so stick, even
         * where an arriving contact would slip (kept as it was before F0 existed) */
        s->mode = fabs(q0) > m->d ? ContactStick : ContactOpen;
        if (s->mode == ContactStick && F0 != 0.0) initContactForce(m, s, F0);
    } else {
        s->mode = (!m->gating || fabs(q0) > m->d) ? 1 : 0;
    }
    return solverUpdateDescribe(m, s);
}

/* 1 if the contact force is switched on in s (DF: gate on or gating off; Jenkins: in contact). */
static int gateOn(const SolverModel *m, const SolverState *s)
{
    if (m->friction == FrictionMacroslipTD) return s->mode != ContactOpen;
    return s->mode == 1;
}

/* ------------------------------------------------------------------------------------------- */
/* Right-hand side (hot: no branches beyond the mode, no calls, no allocation)                  */

/* f = dx/dt at state x for inputs fw [N/m], n [rpm] with the discrete state of s.
 * Returns 1 if omega <= 0 while a describing-function force is needed (model-notes s.2). */
static inline int rhs(const SolverModel *m, const SolverState *s, double fw, double n,
                      const double x[SOLVER_NX], double f[SOLVER_NX])
{
    const double q = x[0], v = x[1];
    const double Omega = m->OmegaPerRpm * n;
    const double omega = m->omegaPerRpm * n;
    const double K0 = m->K0static + m->K0omega2 * Omega * Omega; /* eq. 26 */
    double Fc = 0.0, P = 0.0, dw = 0.0;
    int bad = 0;
    if (m->friction == FrictionMacroslipTD) {
        const double sig = (double)s->side;
        switch (s->mode) {
        case ContactStick: {
            const double Fn = m->knCos * (q - sig * m->d);  /* eq. 3 */
            const double Ff = m->kd * (m->sinG * q - x[4]); /* spring k_d (Delta_u - w) */
            Fc = Fn * m->cosG + Ff * m->sinG;               /* eq. 14 */
            break;
        }
        case ContactSlip: {
            const double sd = (double)s->slipDir;
            const double Fn = m->knCos * (q - sig * m->d);
            const double Ff = sd * m->muKnCos * (sig * q - m->d); /* F_f = s mu |F_n| */
            Fc = Fn * m->cosG + Ff * m->sinG;
            dw = (m->sinG - sd * sig * m->muKnCosPerKd) * v; /* w = Delta_u - s L / k_d */
            P = Ff * dw;
            break;
        }
        default:
            dw = m->sinG * v; /* open: w follows Delta_u (spring unloaded) */
            break;
        }
    } else if (s->mode == 1 && s->df.regime != RegimeOpen) {
        /* eq. 27 with eq. 12-13: F_c = K_eq q + C_eq q', C_eq = (C_eq omega) / omega */
        double Ceq = 0.0;
        if (omega > 0.0) Ceq = s->df.CeqOmega / omega;
        else bad = 1;
        Fc = s->df.Keq * q + Ceq * v;
        P = Ceq * v * v;
    }
    f[0] = v;
    f[1] = (m->G * fw - m->C0 * v - K0 * q - Fc) * m->invM;
    f[2] = omega;
    f[3] = m->C0 * v * v + P;
    f[4] = dw;
    return bad;
}

/* One classical RK4 step from (tau0, x0) to tau1 with k1 = f(tau0, x0) given. Returns the
 * omega flag of rhs(); the inputs at tau1 are returned for the FSAL evaluation. */
static int rk4(const SolverModel *m, const SolverState *s, const SolverInputs *in, double tau0,
               double tau1, const double x0[SOLVER_NX], const double k1[SOLVER_NX],
               double x1[SOLVER_NX], double *fw1, double *n1)
{
    double k2[SOLVER_NX], k3[SOLVER_NX], k4[SOLVER_NX], xt[SOLVER_NX];
    const double h = tau1 - tau0, hh = 0.5 * h, h6 = h / 6.0;
    const double tm = tau0 + hh;
    const double fwm = inputAt(in, SOLVER_INPUT_AERO, tm), nm = inputAt(in, SOLVER_INPUT_SPEED, tm);
    const double fwe = inputAt(in, SOLVER_INPUT_AERO, tau1), ne = inputAt(in, SOLVER_INPUT_SPEED, tau1);
    int bad = 0, i;
    for (i = 0; i < SOLVER_NX; ++i) xt[i] = x0[i] + hh * k1[i];
    bad |= rhs(m, s, fwm, nm, xt, k2);
    for (i = 0; i < SOLVER_NX; ++i) xt[i] = x0[i] + hh * k2[i];
    bad |= rhs(m, s, fwm, nm, xt, k3);
    for (i = 0; i < SOLVER_NX; ++i) xt[i] = x0[i] + h * k3[i];
    bad |= rhs(m, s, fwe, ne, xt, k4);
    for (i = 0; i < SOLVER_NX; ++i) x1[i] = x0[i] + h6 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
    *fw1 = fwe;
    *n1 = ne;
    return bad;
}

/* ------------------------------------------------------------------------------------------- */
/* Event location on the cubic Hermite interpolant                                              */

static inline double cubicAt(const double c[4], double t) { return ((c[3] * t + c[2]) * t + c[1]) * t + c[0]; }

/* Illinois (modified regula falsi) on [lo, hi] with p(lo) >= 0 > p(hi): returns the right end of
 * the final bracket (a point where p < 0) once hi - lo <= tol. */
static double refineRoot(const double c[4], double lo, double plo, double hi, double phi, double tol)
{
    int side = 0;
    for (int it = 0; it < 200 && hi - lo > tol; ++it) {
        double x = lo + plo * (hi - lo) / (plo - phi);
        double px;
        if (!(x > lo && x < hi)) x = 0.5 * (lo + hi);
        if (!(x > lo && x < hi)) break; /* no double strictly inside */
        px = cubicAt(c, x);
        if (px < 0.0) {
            hi = x;
            phi = px;
            if (side == -1) plo *= 0.5;
            side = -1;
        } else {
            lo = x;
            plo = px;
            if (side == 1) phi *= 0.5;
            side = 1;
        }
    }
    return hi;
}

/* First theta in (0, 1] where the cubic Hermite interpolant with values p0, p1 and scaled slopes
 * m0 = h g'(0), m1 = h g'(1) is negative; NO_EVENT if none. p0 < 0 (a state just switched whose
 * function is a rounding error on the wrong side) is clamped to 0, and dips shallower than
 * 1e-12 of the data's scale are ignored: right after a switch a function starts at a rounding
 * error from 0 with a slope that may be a rounding error of the wrong sign (e.g. q' at a
 * slip -> stick switch), which must not switch back. The delay this threshold adds to a real
 * crossing is 1e-12 of the step. */
static double firstNegative(double p0, double m0, double p1, double m1, double tol)
{
    double c[4], br[4], pa, a, noise;
    int nb = 0;
    if (!(p0 >= 0.0)) p0 = 0.0;
    noise = 1e-12 * (fabs(p0) + fabs(p1) + fabs(m0) + fabs(m1));
    p0 += noise;
    p1 += noise;
    /* Bernstein control points >= 0: the cubic is >= 0 on [0, 1] (convex hull) */
    if (p0 + m0 / 3.0 >= 0.0 && p1 - m1 / 3.0 >= 0.0 && p1 >= 0.0) return NO_EVENT;
    c[0] = p0;
    c[1] = m0;
    c[2] = -3.0 * p0 - 2.0 * m0 + 3.0 * p1 - m1;
    c[3] = 2.0 * p0 + m0 - 2.0 * p1 + m1;
    /* monotone pieces: split at the roots of p' = 3 c3 t^2 + 2 c2 t + c1 inside (0, 1) */
    br[nb++] = 0.0;
    {
        const double A = 3.0 * c[3], Bq = 2.0 * c[2], C = c[1];
        double r1 = -1.0, r2 = -1.0;
        if (A != 0.0) {
            const double disc = Bq * Bq - 4.0 * A * C;
            if (disc > 0.0) {
                const double qq = -0.5 * (Bq + copysign(sqrt(disc), Bq));
                r1 = qq / A;
                r2 = qq != 0.0 ? C / qq : -1.0;
            }
        } else if (Bq != 0.0) {
            r1 = -C / Bq;
        }
        if (r1 > r2) { const double t = r1; r1 = r2; r2 = t; }
        if (r1 > 0.0 && r1 < 1.0) br[nb++] = r1;
        if (r2 > 0.0 && r2 < 1.0 && r2 != r1) br[nb++] = r2;
    }
    br[nb++] = 1.0;
    a = 0.0;
    pa = p0;
    for (int i = 1; i < nb; ++i) {
        const double b = br[i];
        const double pb = (i == nb - 1) ? p1 : cubicAt(c, b);
        if (pb < 0.0) return refineRoot(c, a, pa, b, pb, tol);
        a = b;
        pa = pb;
    }
    return NO_EVENT;
}

/* The earliest switching event of the step [tau0, tau0 + h] (model-notes s.6). Functions are
 * listed in priority order: at equal instants the first listed wins (contact loss first). */
static Ev detect(const SolverModel *m, const SolverState *s, double h, const double x0[SOLVER_NX],
                 const double f0[SOLVER_NX], const double x1[SOLVER_NX], const double f1[SOLVER_NX],
                 double tol, double *theta)
{
    double best = NO_EVENT;
    Ev ev = EvNone;
    const double q0 = x0[0], v0 = x0[1], q1 = x1[0], v1 = x1[1];
#define CANDIDATE(kind, p0, m0, p1, m1)                                    \
    do {                                                                   \
        const double th_ = firstNegative((p0), (m0), (p1), (m1), tol);    \
        if (th_ <= 1.0 && th_ + 2.0 * tol < best) { best = th_; ev = (kind); } \
    } while (0)

    const int contactModel = m->friction == FrictionMacroslipTD;
    if (contactModel || m->gating) {
        const int inside = gateOn(m, s);
        const double d = m->d;
        if (inside) {
            const double sg = (double)s->side;
            /* |q| > d while in contact: sigma q - d >= 0 (eq. 3, 12-13) */
            CANDIDATE(EvLeave, sg * q0 - d, sg * h * v0, sg * q1 - d, sg * h * v1);
        } else {
            CANDIDATE(EvEnterPos, d - q0, -h * v0, d - q1, -h * v1);
            CANDIDATE(EvEnterNeg, d + q0, h * v0, d + q1, h * v1);
        }
    }
    if (contactModel && s->mode == ContactStick) {
        /* stick while |F_f| <= L: L -+ F_f >= 0, F_f = kd (sin g q - w), L = mu kn cos g (sigma q - d) */
        const double sg = (double)s->side, w = x0[4];
        const double aP = sg * m->muKnCos - m->kd * m->sinG, bP = -m->muKnCos * m->d + m->kd * w;
        const double aN = sg * m->muKnCos + m->kd * m->sinG, bN = -m->muKnCos * m->d - m->kd * w;
        CANDIDATE(EvSlipPos, aP * q0 + bP, aP * h * v0, aP * q1 + bP, aP * h * v1);
        CANDIDATE(EvSlipNeg, aN * q0 + bN, aN * h * v0, aN * q1 + bN, aN * h * v1);
    } else if (contactModel && s->mode == ContactSlip) {
        /* slip while s kd sin g q' - L' >= 0 (model-notes s.2): (s kd sin g - sigma mu kn cos g) q' */
        const double cs = s->slipDir * m->kd * m->sinG - s->side * m->muKnCos;
        if (cs != 0.0) {
            const double sg = cs > 0.0 ? 1.0 : -1.0;
            CANDIDATE(EvStick, sg * v0, sg * h * f0[1], sg * v1, sg * h * f1[1]);
        }
    }
    if (m->tracked) {
        const double target = TWO_PI * (s->periods + 1.0); /* period k ends at psi = 2 pi k */
        CANDIDATE(EvPeriod, target - x0[2], -h * f0[2], target - x1[2], -h * f1[2]);
        CANDIDATE(EvExtremum, s->vdir * v0, s->vdir * h * f0[1], s->vdir * v1, s->vdir * h * f1[1]);
    }
#undef CANDIDATE
    *theta = best;
    return ev;
}

/* Discrete update at an event (model-notes s.2, s.3). */
static SolverStatus applyEvent(const SolverModel *m, SolverState *s, Ev ev, SolverEventKind *kind)
{
    const int contactModel = m->friction == FrictionMacroslipTD;
    switch (ev) {
    case EvEnterPos:
    case EvEnterNeg: {
        const int side = ev == EvEnterPos ? 1 : -1;
        if (contactModel) {
            enterContact(m, s, side);
            *kind = SolverEventContact;
        } else {
            s->mode = 1;
            s->side = side;
            *kind = SolverEventGateOn;
        }
        break;
    }
    case EvLeave:
        if (contactModel) {
            s->mode = ContactOpen;
            s->w = m->sinG * s->q; /* separation: the spring unloads */
            *kind = SolverEventSeparate;
        } else {
            s->mode = 0;
            *kind = SolverEventGateOff;
        }
        break;
    case EvSlipPos:
    case EvSlipNeg: {
        const double L = m->muKnCos * (s->side * s->q - m->d);
        s->mode = ContactSlip;
        s->slipDir = ev == EvSlipPos ? 1 : -1;
        s->w = m->sinG * s->q - s->slipDir * L / m->kd; /* F_f = s L exactly */
        *kind = SolverEventStickToSlip;
        break;
    }
    case EvStick:
        s->mode = ContactStick;
        *kind = SolverEventSlipToStick;
        break;
    case EvPeriod: {
        /* model-notes s.3: B = max |q| over the period that ends now */
        const double aq = fabs(s->q);
        const double newB = s->windowMax > aq ? s->windowMax : aq;
        s->periods += 1.0;
        s->windowMax = aq;
        *kind = SolverEventPeriodEnd;
        if (newB != s->B) {
            s->B = newB;
            return solverUpdateDescribe(m, s);
        }
        break;
    }
    case EvExtremum: {
        const double aq = fabs(s->q);
        if (aq > s->windowMax) s->windowMax = aq;
        s->vdir = -s->vdir;
        *kind = SolverEventExtremum;
        break;
    }
    default:
        break;
    }
    return SolverOk;
}

static inline void loadX(const SolverState *s, double x[SOLVER_NX])
{
    x[0] = s->q; x[1] = s->v; x[2] = s->psi; x[3] = s->E; x[4] = s->w;
}

static inline void storeX(SolverState *s, const double x[SOLVER_NX])
{
    s->q = x[0]; s->v = x[1]; s->psi = x[2]; s->E = x[3]; s->w = x[4];
}

static inline int allFinite(const double x[SOLVER_NX])
{
    return isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]) && isfinite(x[3]) && isfinite(x[4]);
}

SolverStatus solverAdvance(const SolverModel *m, SolverState *s, const SolverInputs *in,
                           double tStart, double h, long nSteps, SolverEventHook hook, void *ctx,
                           SolverCounters *counters, double *tFail)
{
    const double hi = h / (double)nSteps;
    double x0[SOLVER_NX], x1[SOLVER_NX], f0[SOLVER_NX], f1[SOLVER_NX];
    double fwB = 0.0, nB = 0.0;
    long long nRhs = 0, nEvents = 0, nAccepted = 0;
    SolverStatus status = SolverOk;
    double tau0 = 0.0;
    int f0Valid = 0;
    long k;
    loadX(s, x0);
    for (k = 0; k < nSteps && status == SolverOk; ++k) {
        const double tauB = (k + 1 == nSteps) ? h : (double)(k + 1) * hi;
        int events = 0;
        tau0 = (double)k * hi;
        for (;;) { /* the internal step [tau0, tauB], cut at every event inside it */
            SolverEventKind kind = SolverEventGateOn;
            double theta, hs, tAbs, tol, te;
            Ev ev;
            if (!f0Valid) {
                const double fw0 = inputAt(in, SOLVER_INPUT_AERO, tau0), n0 = inputAt(in, SOLVER_INPUT_SPEED, tau0);
                ++nRhs;
                if (rhs(m, s, fw0, n0, x0, f0)) { status = SolverOmegaZero; break; }
                f0Valid = 1;
            }
            nRhs += 4;
            if (rk4(m, s, in, tau0, tauB, x0, f0, x1, &fwB, &nB)) { status = SolverOmegaZero; break; }
            if (!allFinite(x1)) { status = SolverNonFinite; break; }
            if (rhs(m, s, fwB, nB, x1, f1)) { status = SolverOmegaZero; break; } /* FSAL: next k1 */
            hs = tauB - tau0;
            tAbs = fabs(tStart + tau0);
            tol = 1e-15 * (tAbs > hs ? tAbs : hs) / hs; /* ~1e-15 relative in time */
            if (tol < 4.0 * DBL_EPSILON) tol = 4.0 * DBL_EPSILON;
            ev = detect(m, s, hs, x0, f0, x1, f1, tol, &theta);
            if (ev == EvNone) { /* no switch: accept the whole step */
                storeX(s, x1);
                memcpy(x0, x1, sizeof x0);
                memcpy(f0, f1, sizeof f0);
                ++nAccepted;
                break;
            }
            /* redo the step up to the switching instant te, then update the discrete state */
            te = tau0 + theta * hs;
            if (theta >= 1.0 || te >= tauB) {
                te = tauB;
                storeX(s, x1);
            } else if (te > tau0) {
                double xe[SOLVER_NX], fwE, nE;
                nRhs += 3;
                if (rk4(m, s, in, tau0, te, x0, f0, xe, &fwE, &nE)) { status = SolverOmegaZero; break; }
                if (!allFinite(xe)) { status = SolverNonFinite; break; }
                storeX(s, xe);
            } /* else: te == tau0, the switch happens at the step start */
            ++nEvents;
            status = applyEvent(m, s, ev, &kind);
            if (status != SolverOk) break;
            if (hook) hook(ctx, kind, tStart + te, s);
            loadX(s, x0);
            f0Valid = 0;
            tau0 = te;
            if (++events > SOLVER_MAX_EVENTS_PER_STEP) { status = SolverChattering; break; }
            if (te >= tauB) { ++nAccepted; break; }
        }
    }
    if (counters) {
        counters->internalSteps += nAccepted;
        counters->events += nEvents;
        counters->rhsCalls += nRhs;
    }
    if (tFail) *tFail = status == SolverOk ? h : tau0;
    return status;
}

/* ------------------------------------------------------------------------------------------- */
/* Outputs (model-notes s.4)                                                                    */

void solverOutputs(const SolverModel *m, const SolverState *s, double nRpm, SolverOutputs *out)
{
    const double Omega = m->OmegaPerRpm * nRpm;
    const double omega = m->omegaPerRpm * nRpm;
    const double K0 = m->K0static + m->K0omega2 * Omega * Omega;
    /* f_c and C_eq carry 1/omega; with omega = 0 (no rotation) they are reported as 0, and so
     * they are when omega is so small (< ~1e-300 rad/s) that the quotient overflows */
    const double CeqDF = omega > 0.0 && isfinite(s->df.CeqOmega / omega) ? s->df.CeqOmega / omega : 0.0;
    const double fc = omega > 0.0 && isfinite(s->df.fcOmega / omega) ? s->df.fcOmega / omega : 0.0;
    const double sig = (double)s->side;
    out->naturalFrequency = sqrt((K0 > 0.0 ? K0 : 0.0) * m->invM) / TWO_PI;
    out->regime = (int)s->df.regime;
    if (m->friction == FrictionMacroslipTD) {
        out->Keq = s->df.Keq; /* information only: the DF at the B in use */
        out->Ceq = CeqDF;
        switch (s->mode) {
        case ContactStick:
            out->normalForce = m->knCos * (s->q - sig * m->d);
            out->frictionForce = m->kd * (m->sinG * s->q - s->w);
            out->jenkinsForce = out->frictionForce;
            out->contactState = ContactStick;
            break;
        case ContactSlip:
            out->normalForce = m->knCos * (s->q - sig * m->d);
            out->frictionForce = s->slipDir * m->muKnCos * (sig * s->q - m->d);
            /* the spring state itself (= s L up to rounding): a restart from it is consistent */
            out->jenkinsForce = m->kd * (m->sinG * s->q - s->w);
            out->contactState = ContactSlip;
            break;
        default:
            out->normalForce = 0.0;
            out->frictionForce = 0.0;
            out->jenkinsForce = 0.0;
            out->contactState = ContactOpen;
            break;
        }
    } else {
        const int g = gateOn(m, s);
        out->jenkinsForce = 0.0; /* no Jenkins element in the describing-function models */
        out->normalForce = g ? s->df.pk * s->q : 0.0;
        out->frictionForce = g ? s->df.fk * s->q + fc * s->v : 0.0;
        out->Keq = g ? s->df.Keq : 0.0;
        out->Ceq = g ? CeqDF : 0.0;
        if (!g || s->df.regime == RegimeOpen) {
            out->contactState = ContactOpen;
        } else if (s->df.regime == RegimeFullStick) {
            out->contactState = ContactStick;
        } else {
            double theta = omega > 0.0 ? atan2(-s->v / omega, s->q) : atan2(-s->v, 0.0);
            if (theta < 0.0) theta += TWO_PI;
            if (theta >= TWO_PI) theta = 0.0;
            out->contactState = (int)contactLoopState(&m->contact, m->friction, s->B, theta);
        }
    }
}

const char *solverNonFiniteOutput(const SolverOutputs *o)
{
    if (!isfinite(o->normalForce)) return "normalForce";
    if (!isfinite(o->frictionForce)) return "frictionForce";
    if (!isfinite(o->jenkinsForce)) return "jenkinsForce";
    if (!isfinite(o->Keq)) return "Keq";
    if (!isfinite(o->Ceq)) return "Ceq";
    if (!isfinite(o->naturalFrequency)) return "naturalFrequency";
    return NULL;
}
