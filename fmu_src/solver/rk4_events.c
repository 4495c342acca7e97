/* The co-simulation integrator (see rk4_events.h): RK4 steps over dynRhs, switching events of
 * dynSwitching located on each step's cubic Hermite interpolant and applied by dynApplyEvent. */
#include "solver/rk4_events.h"

#include <float.h>
#include <math.h>
#include <string.h>

#define NO_EVENT 2.0 /* "theta" of a function that does not trigger in the step */

/* ------------------------------------------------------------------------------------------- */
/* Inputs (model-notes s.1): Taylor polynomials in tau = t - t_k.                                 */

static void setPoly(SolverInputs *in, int i, const double deriv[SOLVER_MAX_ORDER + 1])
{
    double fact = 1.0; /* j! */
    in->top[i] = 0;
    for (int j = 0; j <= SOLVER_MAX_ORDER; ++j) {
        if (j > 0) fact *= (double)j;
        in->coef[i][j] = deriv[j] / fact;
        if (j > 0 && in->coef[i][j] != 0.0) in->top[i] = j;
    }
}

void solverSetInputs(SolverInputs *in, const double deriv[SOLVER_NUM_INPUTS][SOLVER_MAX_ORDER + 1])
{
    static const double zero[SOLVER_MAX_ORDER + 1] = {0.0};
    for (int i = 0; i < SOLVER_NUM_INPUTS; ++i) setPoly(in, i, deriv[i]);
    setPoly(in, SOLVER_INPUT_FORCE, zero);
}

void solverSetForce(SolverInputs *in, const double deriv[SOLVER_MAX_ORDER + 1])
{
    setPoly(in, SOLVER_INPUT_FORCE, deriv);
}

static inline double inputAt(const SolverInputs *in, int i, double tau)
{
    const double *c = in->coef[i];
    double u = c[in->top[i]];
    for (int j = in->top[i] - 1; j >= 0; --j) u = u * tau + c[j];
    return u;
}

double solverInputAt(const SolverInputs *in, int i, double tau) { return inputAt(in, i, tau); }

void solverShiftInput(const SolverInputs *in, int i, double h, double out[SOLVER_MAX_ORDER + 1])
{
    double c[SOLVER_MAX_ORDER + 1];
    const int top = in->top[i];
    double fact = 1.0;
    memcpy(c, in->coef[i], sizeof c);
    for (int j = 0; j < top; ++j) /* repeated synthetic division: Taylor shift */
        for (int k = top - 1; k >= j; --k) c[k] += h * c[k + 1];
    for (int j = 0; j <= SOLVER_MAX_ORDER; ++j) {
        if (j > 0) fact *= (double)j;
        out[j] = j <= top ? c[j] * fact : 0.0;
    }
    out[0] = inputAt(in, i, h);
}

/* ------------------------------------------------------------------------------------------- */
/* RK4                                                                                          */

/* The step functions below take `ext` (1: an external force acts, integrate W too; 0: it is
 * identically 0) and `multi` (1: m > 1 modes, the extra modal coordinates are integrated too) as
 * constants: solverAdvance instantiates them once per pair, so the one-mode blade without a force
 * runs exactly the arithmetic and the cost it had before. */
#if defined(__GNUC__)
#define SOLVER_INLINE static inline __attribute__((always_inline))
#else
#define SOLVER_INLINE static inline
#endif

/* Inputs at one instant. */
typedef struct {
    double fw, n, fe; /* aeroLoad [N/m], rotorSpeed [rpm], external force [N] */
} InputValues;

SOLVER_INLINE InputValues inputsAt(const SolverInputs *in, double tau, const int ext)
{
    InputValues u;
    u.fw = inputAt(in, SOLVER_INPUT_AERO, tau);
    u.n = inputAt(in, SOLVER_INPUT_SPEED, tau);
    u.fe = ext ? inputAt(in, SOLVER_INPUT_FORCE, tau) : 0.0;
    return u;
}

/* dx/dt of the integrated state (dynRhsExt, plus W' = F q'). */
SOLVER_INLINE int rhs(const DynModel *m, const DynState *s, const InputValues *u, const double x[SOLVER_NX],
                      double f[SOLVER_NX], const int ext, const int multi)
{
    const int bad = multi ? dynRhsMulti(m, s, u->fw, u->n, ext ? u->fe : 0.0, x, f)
                          : dynRhsOne(m, s, u->fw, u->n, ext ? u->fe : 0.0, x, f);
    if (ext) f[SOLVER_W] = u->fe * x[1];
    return bad;
}

/* One classical RK4 step from (tau0, x0) to tau1 with k1 = f(tau0, x0) given. Returns the
 * omega flag of dynRhs(); the inputs at tau1 are returned for the FSAL evaluation. stages (may be
 * NULL) receives the states of stages 2-4 for the sensitivities. */
SOLVER_INLINE int rk4(const DynModel *m, const DynState *s, const SolverInputs *in, double tau0,
                      double tau1, const double x0[SOLVER_NX], const double k1[SOLVER_NX],
                      double x1[SOLVER_NX], InputValues *u1, double stages[3][SOLVER_NX], const int ext,
                      const int multi)
{
    double k2[SOLVER_NX], k3[SOLVER_NX], k4[SOLVER_NX], xt[SOLVER_NX];
    const double h = tau1 - tau0, hh = 0.5 * h, h6 = h / 6.0;
    const double tm = tau0 + hh;
    const InputValues um = inputsAt(in, tm, ext), ue = inputsAt(in, tau1, ext);
    const int nx = multi ? DYN_NX_MAX : DYN_NX; /* the blade's states, then W */
    const int W = SOLVER_W;
    int bad = 0, i;
    for (i = 0; i < nx; ++i) xt[i] = x0[i] + hh * k1[i];
    if (ext) xt[W] = x0[W] + hh * k1[W];
    if (stages) memcpy(stages[0], xt, sizeof xt);
    bad |= rhs(m, s, &um, xt, k2, ext, multi);
    for (i = 0; i < nx; ++i) xt[i] = x0[i] + hh * k2[i];
    if (ext) xt[W] = x0[W] + hh * k2[W];
    if (stages) memcpy(stages[1], xt, sizeof xt);
    bad |= rhs(m, s, &um, xt, k3, ext, multi);
    for (i = 0; i < nx; ++i) xt[i] = x0[i] + h * k3[i];
    if (ext) xt[W] = x0[W] + h * k3[W];
    if (stages) memcpy(stages[2], xt, sizeof xt);
    bad |= rhs(m, s, &ue, xt, k4, ext, multi);
    for (i = 0; i < nx; ++i) x1[i] = x0[i] + h6 * (k1[i] + 2.0 * (k2[i] + k3[i]) + k4[i]);
    if (ext) x1[W] = x0[W] + h6 * (k1[W] + 2.0 * (k2[W] + k3[W]) + k4[W]);
    *u1 = ue;
    return bad;
}

/* The variational equations' RK4 step over the same stages (physics/variational.h). */
static void rk4Sens(const DynModel *m, const DynState *s, DynSens *e, const SolverInputs *in, double tau0,
                    double tau1, const double x0[SOLVER_NX], const double stages[3][SOLVER_NX])
{
    const double n[3] = {inputAt(in, SOLVER_INPUT_SPEED, tau0), inputAt(in, SOLVER_INPUT_SPEED, 0.5 * (tau0 + tau1)),
                         inputAt(in, SOLVER_INPUT_SPEED, tau1)};
    const double *const x[4] = {x0, stages[0], stages[1], stages[2]};
    sensRk4(m, s, e, tau1 - tau0, n, x);
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

/* The earliest switching event of the step [tau0, tau0 + h] (model-notes s.6): the switching
 * functions at both ends with their slopes scaled by h, located on the cubic Hermite interpolant.
 * At equal instants the first listed wins (dynSwitching lists them in priority order). */
static DynSwitch detect(const DynModel *m, const DynState *s, double h, const double x0[SOLVER_NX],
                        const double f0[SOLVER_NX], const double x1[SOLVER_NX], const double f1[SOLVER_NX],
                        double tol, double *theta)
{
    DynSwitchValue a[DYN_MAX_SWITCHING], b[DYN_MAX_SWITCHING];
    double best = NO_EVENT;
    DynSwitch sw = DynSwitchNone;
    const int n = dynSwitching(m, s, h, x0, f0, a);
    dynSwitching(m, s, h, x1, f1, b); /* the same functions: the list depends on m and s only */
    for (int i = 0; i < n; ++i) {
        const double th = firstNegative(a[i].g, a[i].hdg, b[i].g, b[i].hdg, tol);
        if (th <= 1.0 && th + 2.0 * tol < best) {
            best = th;
            sw = a[i].kind;
        }
    }
    *theta = best;
    return sw;
}

/* the extra modal coordinates of m > 1 modes (dynamics.h: x[DYN_NX + k], x[DYN_X_RATES + k]) */
static void loadModes(DynState const *s, double x[SOLVER_NX])
{
    for (int k = 0; k < MODES_MAX - 1; ++k) {
        x[DYN_NX + k] = s->qx[k];
        x[DYN_X_RATES + k] = s->vx[k];
    }
}

static void storeModes(DynState *s, const double x[SOLVER_NX])
{
    for (int k = 0; k < MODES_MAX - 1; ++k) {
        s->qx[k] = x[DYN_NX + k];
        s->vx[k] = x[DYN_X_RATES + k];
    }
}

static int modesFinite(const double x[SOLVER_NX])
{
    for (int k = DYN_NX; k < DYN_NX_MAX; ++k)
        if (!isfinite(x[k])) return 0;
    return 1;
}

SOLVER_INLINE void loadX(const DynState *s, double x[SOLVER_NX], const int ext, const int multi)
{
    x[0] = s->q; x[1] = s->v; x[2] = s->psi; x[3] = s->E; x[4] = s->w;
    if (ext) x[SOLVER_W] = s->W;
    if (multi) loadModes(s, x);
}

SOLVER_INLINE void storeX(DynState *s, const double x[SOLVER_NX], const int ext, const int multi)
{
    s->q = x[0]; s->v = x[1]; s->psi = x[2]; s->E = x[3]; s->w = x[4];
    if (ext) s->W = x[SOLVER_W];
    if (multi) storeModes(s, x);
}

/* dst = src on the integrated entries (the blade's, W if ext, the modes if multi) */
SOLVER_INLINE void copyX(double dst[SOLVER_NX], const double src[SOLVER_NX], const int ext, const int multi)
{
    if (multi) memcpy(dst, src, DYN_NX_MAX * sizeof(double));
    else memcpy(dst, src, DYN_NX * sizeof(double));
    if (ext) dst[SOLVER_W] = src[SOLVER_W];
}

SOLVER_INLINE int allFinite(const double x[SOLVER_NX], const int ext, const int multi)
{
    return isfinite(x[0]) && isfinite(x[1]) && isfinite(x[2]) && isfinite(x[3]) && isfinite(x[4]) &&
           (!ext || isfinite(x[SOLVER_W])) && (!multi || modesFinite(x));
}

/* The sensitivities' jump at an event (the discrete state before it in *before, after it in *s,
 * the continuous state xe at the instant te) */
SOLVER_INLINE DynStatus sensJump(const DynModel *m, const DynState *before, const DynState *s, DynSwitch sw,
                                 const SolverInputs *in, double te, const double xe[SOLVER_NX], DynSens *e,
                                 const int ext, const int multi)
{
    double fm[SOLVER_NX], fp[SOLVER_NX], xp[SOLVER_NX];
    const InputValues u = inputsAt(in, te, ext);
    loadX(s, xp, ext, multi);
    if (rhs(m, before, &u, xe, fm, ext, multi) || rhs(m, s, &u, xp, fp, ext, multi)) return DynOmegaZero;
    return sensEvent(m, before, s, sw, fm, fp, e);
}

SOLVER_INLINE DynStatus advance(const DynModel *m, DynState *s, const SolverInputs *in, double tStart, double h,
                                long nSteps, SolverEventHook hook, void *ctx, SolverCounters *counters,
                                double *tFail, DynSens *sens, const int ext, const int multi)
{
    double stages[3][SOLVER_NX];
    const double hi = h / (double)nSteps;
    double x0[SOLVER_NX], x1[SOLVER_NX], f0[SOLVER_NX], f1[SOLVER_NX];
    InputValues uB = {0.0, 0.0, 0.0};
    long long nRhs = 0, nEvents = 0, nAccepted = 0;
    DynStatus status = DynOk;
    double tau0 = 0.0;
    int f0Valid = 0;
    long k;
    loadX(s, x0, ext, multi);
    for (k = 0; k < nSteps && status == DynOk; ++k) {
        const double tauB = (k + 1 == nSteps) ? h : (double)(k + 1) * hi;
        int events = 0;
        tau0 = (double)k * hi;
        for (;;) { /* the internal step [tau0, tauB], cut at every event inside it */
            DynEventKind kind = DynEventGateOn;
            double theta, hs, tAbs, tol, te;
            DynSwitch ev;
            if (!f0Valid) {
                const InputValues u0 = inputsAt(in, tau0, ext);
                ++nRhs;
                if (rhs(m, s, &u0, x0, f0, ext, multi)) { status = DynOmegaZero; break; }
                f0Valid = 1;
            }
            nRhs += 4;
            if (rk4(m, s, in, tau0, tauB, x0, f0, x1, &uB, sens ? stages : NULL, ext, multi)) { status = DynOmegaZero; break; }
            if (!allFinite(x1, ext, multi)) { status = DynNonFinite; break; }
            if (rhs(m, s, &uB, x1, f1, ext, multi)) { status = DynOmegaZero; break; } /* FSAL: next k1 */
            hs = tauB - tau0;
            tAbs = fabs(tStart + tau0);
            tol = 1e-15 * (tAbs > hs ? tAbs : hs) / hs; /* ~1e-15 relative in time */
            if (tol < 4.0 * DBL_EPSILON) tol = 4.0 * DBL_EPSILON;
            ev = detect(m, s, hs, x0, f0, x1, f1, tol, &theta);
            if (ev == DynSwitchNone) { /* no switch: accept the whole step */
                if (sens) rk4Sens(m, s, sens, in, tau0, tauB, x0, (const double(*)[SOLVER_NX])stages);
                storeX(s, x1, ext, multi);
                copyX(x0, x1, ext, multi);
                copyX(f0, f1, ext, multi);
                ++nAccepted;
                break;
            }
            /* redo the step up to the switching instant te, then update the discrete state */
            te = tau0 + theta * hs;
            if (theta >= 1.0 || te >= tauB) {
                te = tauB;
                if (sens) rk4Sens(m, s, sens, in, tau0, tauB, x0, (const double(*)[SOLVER_NX])stages);
                storeX(s, x1, ext, multi);
            } else if (te > tau0) {
                double xe[SOLVER_NX];
                InputValues uE;
                nRhs += 3;
                if (rk4(m, s, in, tau0, te, x0, f0, xe, &uE, sens ? stages : NULL, ext, multi)) { status = DynOmegaZero; break; }
                if (!allFinite(xe, ext, multi)) { status = DynNonFinite; break; }
                if (sens) rk4Sens(m, s, sens, in, tau0, te, x0, (const double(*)[SOLVER_NX])stages);
                storeX(s, xe, ext, multi);
            } /* else: te == tau0, the switch happens at the step start */
            ++nEvents;
            {
                const DynState before = *s;
                double xe[SOLVER_NX];
                loadX(s, xe, ext, multi);
                status = dynApplyEvent(m, s, ev, &kind);
                if (status == DynOk && sens) status = sensJump(m, &before, s, ev, in, te, xe, sens, ext, multi);
            }
            if (status != DynOk) break;
            if (hook) hook(ctx, kind, tStart + te, s);
            loadX(s, x0, ext, multi);
            f0Valid = 0;
            tau0 = te;
            if (++events > SOLVER_MAX_EVENTS_PER_STEP) { status = DynChattering; break; }
            if (te >= tauB) { ++nAccepted; break; }
        }
    }
    if (counters) {
        counters->internalSteps += nAccepted;
        counters->events += nEvents;
        counters->rhsCalls += nRhs;
    }
    if (tFail) *tFail = status == DynOk ? h : tau0;
    return status;
}

#if defined(__GNUC__)
#define SOLVER_NOINLINE __attribute__((noinline))
#else
#define SOLVER_NOINLINE
#endif

/* m > 1 modes: out of line, so that the one-mode instances below are compiled as before.
 * The one-mode path (multi = 0: q, v and dynRhsOne) stays beside it because it pays and because the
 * m-mode path cannot replace it: measured with bench/bench_step.c (`bench_step modes`, Jenkins
 * element, tracked B, best of 3 runs), m = 1 with the consistent formulation costs 111 ns per
 * internal step here and 332 ns through the m-mode path (its one-mode modal reduction forced), 3.0x;
 * the two agree to 1.4e-18 m of a 4.2e-5 m response but not bit for bit (M^-1 applied as a matrix);
 * and the printed formulation (eq. 26, the default) has no m-mode form at all. */
static SOLVER_NOINLINE DynStatus advanceModes(const DynModel *m, DynState *s, const SolverInputs *in, double tStart,
                                              double h, long nSteps, SolverEventHook hook, void *ctx,
                                              SolverCounters *counters, double *tFail, DynSens *sens, int ext)
{
    return ext ? advance(m, s, in, tStart, h, nSteps, hook, ctx, counters, tFail, sens, 1, 1)
               : advance(m, s, in, tStart, h, nSteps, hook, ctx, counters, tFail, sens, 0, 1);
}

DynStatus solverAdvance(const DynModel *m, DynState *s, const SolverInputs *in, double tStart, double h,
                        long nSteps, SolverEventHook hook, void *ctx, SolverCounters *counters, double *tFail,
                        DynSens *sens)
{
    /* the external force is identically 0 unless its polynomial has a nonzero coefficient */
    const int ext = in->top[SOLVER_INPUT_FORCE] > 0 || in->coef[SOLVER_INPUT_FORCE][0] != 0.0;
    if (m->modes > 1) return advanceModes(m, s, in, tStart, h, nSteps, hook, ctx, counters, tFail, sens, ext);
    return ext ? advance(m, s, in, tStart, h, nSteps, hook, ctx, counters, tFail, sens, 1, 0)
               : advance(m, s, in, tStart, h, nSteps, hook, ctx, counters, tFail, sens, 0, 0);
}
