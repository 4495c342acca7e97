/* The shroud-to-shroud contact element on a prescribed relative motion (see contact_element.h,
 * docs/model.md s.8). Jenkins element (model-notes s.2 with v = u):
 *   F_n = kn cos g (u - sigma d) while sigma u > d (eq. 3), L = mu |F_n|;
 *   stick: F_f = kd (u sin g - w), w constant; slip: F_f = s L, w = u sin g - s L / kd;
 *   open: F_f = 0, w = u sin g;   F_c = F_n cos g + F_f sin g (eq. 14).
 * Every switching function is a u(tau) a + b or u'(tau) a: a polynomial, so events are its roots. */
#include "physics/contact_element.h"

#include <math.h>
#include <string.h>

#define NO_EVENT HUGE_VAL

double cePolyAt(const CePoly *p, double tau)
{
    double v = p->c[p->deg];
    for (int j = p->deg - 1; j >= 0; --j) v = v * tau + p->c[j];
    return v;
}

static void derivative(const CePoly *p, CePoly *d)
{
    memset(d, 0, sizeof *d);
    for (int j = 1; j <= p->deg; ++j) d->c[j - 1] = (double)j * p->c[j];
    d->deg = p->deg > 0 ? p->deg - 1 : 0;
}

double cePolySlopeAt(const CePoly *p, double tau)
{
    CePoly d;
    derivative(p, &d);
    return cePolyAt(&d, tau);
}

/* ------------------------------------------------------------------------------------------- */
/* Roots                                                                                        */

static double hornerN(const double *c, int deg, double t)
{
    double v = c[deg];
    for (int j = deg - 1; j >= 0; --j) v = v * t + c[j];
    return v;
}

/* lo: p >= 0, hi: p < 0; bisection to the last double: returns hi (a point where p < 0). */
static double bisect(const double *c, int deg, double lo, double hi)
{
    for (int it = 0; it < 200; ++it) {
        const double mid = lo + 0.5 * (hi - lo);
        if (!(mid > lo && mid < hi)) break;
        if (hornerN(c, deg, mid) < 0.0) hi = mid;
        else lo = mid;
    }
    return hi;
}

/* The critical points of p (roots of p') in (a, b), sorted; p is monotone between them. By
 * recursion: the critical points of p' bound the monotone pieces of p', whose sign changes are
 * bisected. Returns their number. */
static int criticalPoints(const double *c, int deg, double a, double b, double *out)
{
    double dc[CE_MAX_DEG + 1], sub[CE_MAX_DEG + 2];
    int nsub, n = 0, dd = deg - 1;
    if (deg <= 1) return 0;
    for (int j = 1; j <= deg; ++j) dc[j - 1] = (double)j * c[j];
    while (dd > 0 && dc[dd] == 0.0) --dd;
    if (dd == 0) return 0;
    nsub = criticalPoints(dc, dd, a, b, sub);
    {
        double x0 = a, p0 = hornerN(dc, dd, a);
        for (int i = 0; i <= nsub; ++i) {
            const double x1 = i < nsub ? sub[i] : b;
            const double p1 = hornerN(dc, dd, x1);
            if (p0 != 0.0 && p1 != 0.0 && (p0 < 0.0) != (p1 < 0.0)) {
                /* orient so that the bisection sees p' >= 0 at the left end */
                double neg[CE_MAX_DEG + 1];
                if (p0 < 0.0) {
                    for (int j = 0; j <= dd; ++j) neg[j] = -dc[j];
                    out[n++] = bisect(neg, dd, x0, x1);
                } else {
                    out[n++] = bisect(dc, dd, x0, x1);
                }
            } else if (p1 == 0.0 && i < nsub) {
                out[n++] = x1;
            }
            x0 = x1;
            p0 = p1;
        }
    }
    return n;
}

/* First tau in [a, b] where g < -noise (noise = 1e-12 of g's scale, the size of its terms over
 * the step before they cancel: a function
 * that just became active starts a rounding error from 0 and must not switch straight back), on
 * the monotone pieces of g; a itself if g(a) < -noise (the velocity jumped at a communication
 * point, e.g. a slip reversed); NO_EVENT if none. */
static double firstNegative(const CePoly *g, double scale, double a, double b)
{
    double c[CE_MAX_DEG + 1], crit[CE_MAX_DEG + 1], ga, x0;
    int deg = g->deg, nc;
    memcpy(c, g->c, sizeof c);
    while (deg > 0 && c[deg] == 0.0) --deg;
    c[0] += 1e-12 * scale; /* g + noise */
    ga = hornerN(c, deg, a);
    if (ga < 0.0) return a;
    nc = criticalPoints(c, deg, a, b, crit);
    x0 = a;
    for (int i = 0; i <= nc; ++i) {
        const double x1 = i < nc ? crit[i] : b;
        if (x1 > x0 && hornerN(c, deg, x1) < 0.0) return bisect(c, deg, x0, x1);
        if (x1 > x0) x0 = x1;
    }
    return NO_EVENT;
}

/* ------------------------------------------------------------------------------------------- */
/* Build, init                                                                                  */

int ceBuild(CeModel *m, const ContactParams *cp, FrictionModel friction, Projection projection, int gating,
            double B, int engineOrder)
{
    memset(m, 0, sizeof *m);
    if (!contactParamsValid(cp) || !(cp->kn > 0.0) || !(cp->kdRatio > 0.0) || engineOrder < 1) return 1;
    if (friction != FrictionMacroslipDF && friction != FrictionCoulombDF && friction != FrictionMacroslipTD) return 1;
    m->friction = friction;
    m->gating = gating ? 1 : 0;
    m->contact = *cp;
    m->sinG = sin(cp->gamma);
    m->cosG = cos(cp->gamma);
    m->kd = cp->kdRatio * cp->kn;
    m->knCos = cp->kn * m->cosG;
    m->muKnCos = cp->mu * cp->kn * m->cosG;
    m->stickAtEntry = !(m->kd * m->sinG > m->muKnCos); /* model-notes s.2 */
    m->B = B;
    m->omegaPerRpm = (double)engineOrder * 6.283185307179586476925286766559 / 60.0;
    m->df.regime = RegimeOpen;
    if (friction != FrictionMacroslipTD && B > cp->d &&
        contactDescribe(cp, friction, projection, B, &m->df) != 0) return 2;
    return 0;
}

static int sgn(double x, int zero) { return x > 0.0 ? 1 : (x < 0.0 ? -1 : zero); }

void ceInit(const CeModel *m, CeState *s, double u0, double E0)
{
    memset(s, 0, sizeof *s);
    s->E = E0;
    s->uRef = u0;
    s->side = sgn(u0, 1);
    s->slipDir = s->side;
    s->w = m->sinG * u0; /* the spring is unloaded */
    if (m->friction == FrictionMacroslipTD) s->mode = fabs(u0) > m->contact.d ? ContactStick : ContactOpen;
    else s->mode = (!m->gating || fabs(u0) > m->contact.d) ? 1 : 0;
}

/* ------------------------------------------------------------------------------------------- */
/* Switching functions                                                                          */

typedef enum { SwEnterPos = 0, SwEnterNeg, SwLeave, SwSlipPos, SwSlipNeg, SwStick } SwKind;

typedef struct {
    SwKind kind;
    CePoly g;
    double scale; /* |a| max|u| + |b| over the step, bounded by the coefficients */
} Switch;

/* sw->g = a u + b over [0, h] */
static void linearOf(const CePoly *u, double a, double b, double h, Switch *sw)
{
    double tp = 1.0, size = 0.0;
    sw->g = *u;
    for (int j = 0; j <= u->deg; ++j, tp *= h) {
        sw->g.c[j] = a * u->c[j];
        size += fabs(u->c[j]) * tp;
    }
    sw->g.c[0] += b;
    sw->scale = fabs(a) * size + fabs(b);
}

/* The active functions, in priority order (contact loss first), each >= 0 while the state holds. */
static int switching(const CeModel *m, const CeState *s, const CePoly *u, const CePoly *du, double h,
                     Switch out[4])
{
    const double d = m->contact.d, sg = (double)s->side;
    const int td = m->friction == FrictionMacroslipTD;
    int n = 0;
    if (!td && !m->gating) return 0;
    if (s->mode != 0) { /* ContactOpen = gate off = 0 */
        out[n].kind = SwLeave;
        linearOf(u, sg, -d, h, &out[n++]); /* sigma u - d */
    } else {
        out[n].kind = SwEnterPos;
        linearOf(u, -1.0, d, h, &out[n++]); /* d - u */
        out[n].kind = SwEnterNeg;
        linearOf(u, 1.0, d, h, &out[n++]); /* d + u */
    }
    if (td && s->mode == ContactStick) {
        /* L -+ F_f >= 0 with F_f = kd (sin g u - w), L = mu kn cos g (sigma u - d) */
        out[n].kind = SwSlipPos;
        linearOf(u, sg * m->muKnCos - m->kd * m->sinG, -m->muKnCos * d + m->kd * s->w, h, &out[n++]);
        out[n].kind = SwSlipNeg;
        linearOf(u, sg * m->muKnCos + m->kd * m->sinG, -m->muKnCos * d - m->kd * s->w, h, &out[n++]);
    } else if (td && s->mode == ContactSlip) {
        /* slip while (s kd sin g - sigma mu kn cos g) u' >= 0 (model-notes s.2) */
        const double cs = s->slipDir * m->kd * m->sinG - sg * m->muKnCos;
        if (cs != 0.0) {
            out[n].kind = SwStick;
            linearOf(du, cs > 0.0 ? 1.0 : -1.0, 0.0, h, &out[n++]);
        }
    }
    return n;
}

/* ------------------------------------------------------------------------------------------- */
/* Pieces between events                                                                        */

static const double GL_X[5] = {0.14887433898163122, 0.4333953941292472, 0.6794095682990244,
                               0.8650633666889845, 0.9739065285171717};
static const double GL_W[5] = {0.2955242247147528, 0.2692667193099965, 0.219086362515982,
                               0.1494513491505804, 0.06667134430868814};

/* int_a^b C_eq(tau) u'(tau)^2 dtau, C_eq = C_eq omega / omega(tau): 10-point Gauss-Legendre
 * (exact for a constant speed: u'^2 has degree <= 16). Returns 1 if omega <= 0 at a node. */
static int dfEnergy(const CeModel *m, const CePoly *du, const CePoly *n, double a, double b, double *E)
{
    const double mid = 0.5 * (a + b), half = 0.5 * (b - a);
    double sum = 0.0;
    if (m->df.regime == RegimeOpen || !(b > a)) return 0;
    for (int i = 0; i < 10; ++i) {
        const double t = mid + (i < 5 ? -half * GL_X[i] : half * GL_X[i - 5]);
        const double wt = GL_W[i < 5 ? i : i - 5];
        const double omega = m->omegaPerRpm * (n ? cePolyAt(n, t) : 0.0);
        const double v = cePolyAt(du, t);
        if (!(omega > 0.0)) return 1;
        sum += wt * (m->df.CeqOmega / omega) * v * v;
    }
    *E += half * sum;
    return 0;
}

/* The state over [a, b] without events: the energy and, at b, the slider. */
static CeStatus piece(const CeModel *m, CeState *s, const CePoly *u, const CePoly *du, const CePoly *n,
                      double a, double b)
{
    const double ub = cePolyAt(u, b);
    if (m->friction != FrictionMacroslipTD) {
        if (s->mode != 0 && dfEnergy(m, du, n, a, b, &s->E)) return CeOmegaZero;
        return CeOk;
    }
    if (s->mode == ContactSlip) {
        /* P = F_f w' = s sigma mu kn cos g (sin g - s sigma mu kn cos g / kd) y y', y = sigma u - d */
        const double sg = (double)s->side, sd = (double)s->slipDir;
        const double ya = sg * cePolyAt(u, a) - m->contact.d, yb = sg * ub - m->contact.d;
        const double k = sd * sg * m->muKnCos * (m->sinG - sd * sg * m->muKnCos / m->kd);
        s->E += 0.5 * k * (yb - ya) * (yb + ya);
        s->w = m->sinG * ub - sd * m->muKnCos * yb / m->kd;
    } else if (s->mode == ContactOpen) {
        s->w = m->sinG * ub;
    }
    return CeOk;
}

/* The discrete update at an event at relative displacement ue, velocity due. */
static void apply(const CeModel *m, CeState *s, SwKind kind, double ue, double due)
{
    const int td = m->friction == FrictionMacroslipTD;
    switch (kind) {
    case SwEnterPos:
    case SwEnterNeg:
        s->side = kind == SwEnterPos ? 1 : -1;
        s->w = m->sinG * ue; /* arrives unloaded */
        if (!td) {
            s->mode = 1;
        } else if (m->stickAtEntry) {
            s->mode = ContactStick;
        } else {
            s->mode = ContactSlip;
            s->slipDir = sgn(due, s->side);
            s->w = m->sinG * ue - s->slipDir * m->muKnCos * (s->side * ue - m->contact.d) / m->kd;
        }
        break;
    case SwLeave:
        s->mode = 0; /* ContactOpen, gate off */
        s->w = m->sinG * ue;
        break;
    case SwSlipPos:
    case SwSlipNeg:
        s->mode = ContactSlip;
        s->slipDir = kind == SwSlipPos ? 1 : -1;
        s->w = m->sinG * ue - s->slipDir * m->muKnCos * (s->side * ue - m->contact.d) / m->kd; /* F_f = s L */
        break;
    case SwStick:
        s->mode = ContactStick;
        break;
    }
}

CeStatus ceAdvance(const CeModel *m, CeState *s, const CePoly *u, const CePoly *nRpm, double h, long *events)
{
    CePoly du;
    double t0 = 0.0;
    long nev = 0;
    derivative(u, &du);
    for (;;) {
        Switch sw[4];
        const int ns = switching(m, s, u, &du, h, sw);
        double best = NO_EVENT;
        SwKind kind = SwLeave;
        CeStatus st;
        for (int i = 0; i < ns; ++i) {
            const double te = firstNegative(&sw[i].g, sw[i].scale, t0, h);
            if (te < best) { best = te; kind = sw[i].kind; }
        }
        st = piece(m, s, u, &du, nRpm, t0, best <= h ? best : h);
        if (st != CeOk) return st;
        if (!(best <= h)) break;
        apply(m, s, kind, cePolyAt(u, best), cePolyAt(&du, best));
        t0 = best;
        if (++nev > CE_MAX_EVENTS_PER_STEP) return CeChattering;
    }
    s->uRef = cePolyAt(u, h);
    if (events) *events += nev;
    return isfinite(s->w) && isfinite(s->E) ? CeOk : CeNonFinite;
}

CeStatus ceProject(const CeModel *m, CeState *s, double u0)
{
    CePoly path;
    CeStatus st;
    if (u0 == s->uRef) return CeOk;
    if (m->friction == FrictionMacroslipTD && fabs(u0 - s->uRef) <= 1e-12 * (fabs(u0) + m->contact.d)) {
        /* a rounding-sized jump (u rebuilt from the master's values): keep the mode, re-anchor */
        if (s->mode == ContactSlip)
            s->w = m->sinG * u0 - s->slipDir * m->muKnCos * (s->side * u0 - m->contact.d) / m->kd;
        else if (s->mode == ContactOpen)
            s->w = m->sinG * u0;
        s->uRef = u0;
        return CeOk;
    }
    if (m->friction != FrictionMacroslipTD) { /* the DF has no memory but its gate */
        s->side = sgn(u0, 1);
        s->mode = (!m->gating || fabs(u0) > m->contact.d) ? 1 : 0;
        s->uRef = u0;
        return CeOk;
    }
    memset(&path, 0, sizeof path);
    path.c[0] = s->uRef;
    path.c[1] = u0 - s->uRef;
    path.deg = 1;
    st = ceAdvance(m, s, &path, NULL, 1.0, NULL);
    if (st == CeOk) {
        if (s->mode == ContactSlip) /* land exactly on u0 (the path's end is u0 up to rounding) */
            s->w = m->sinG * u0 - s->slipDir * m->muKnCos * (s->side * u0 - m->contact.d) / m->kd;
        else if (s->mode == ContactOpen)
            s->w = m->sinG * u0;
        s->uRef = u0;
    }
    return st;
}

void ceOutputs(const CeModel *m, const CeState *s, double u, double du, double nRpm, CeOutputs *o)
{
    const double sg = (double)s->side;
    memset(o, 0, sizeof *o);
    if (m->friction == FrictionMacroslipTD) {
        if (s->mode == ContactOpen) return;
        o->normalForce = m->knCos * (u - sg * m->contact.d); /* eq. 3 */
        o->frictionForce = s->mode == ContactSlip ? s->slipDir * m->muKnCos * (sg * u - m->contact.d)
                                                  : m->kd * (m->sinG * u - s->w);
        o->contactForce = o->normalForce * m->cosG + o->frictionForce * m->sinG; /* eq. 14 */
        o->contactState = s->mode;
        return;
    }
    if (s->mode == 0 || m->df.regime == RegimeOpen) return;
    {
        const double omega = m->omegaPerRpm * nRpm;
        const double Ceq = omega > 0.0 && isfinite(m->df.CeqOmega / omega) ? m->df.CeqOmega / omega : 0.0;
        const double fc = omega > 0.0 && isfinite(m->df.fcOmega / omega) ? m->df.fcOmega / omega : 0.0;
        o->contactForce = m->df.Keq * u + Ceq * du;  /* eq. 12-13 on u */
        o->normalForce = m->df.pk * u;
        o->frictionForce = m->df.fk * u + fc * du;
        if (m->df.regime == RegimeFullStick) {
            o->contactState = ContactStick;
        } else {
            double theta = omega > 0.0 ? atan2(-du / omega, u) : atan2(-du, 0.0);
            if (theta < 0.0) theta += 6.283185307179586476925286766559;
            if (theta >= 6.283185307179586476925286766559) theta = 0.0;
            o->contactState = (int)contactLoopState(&m->contact, m->friction, m->B, theta);
        }
    }
}
