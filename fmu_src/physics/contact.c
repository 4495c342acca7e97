/* Shroud contact (paper eq. 1-14, docs/model.md s.3, docs/model-notes.md s.2, s.4, s.5).
 *
 * Notation (per unit v = B cos theta): a = k_d sin g (stick slope of the tangential spring),
 * b = mu k_n cos g (slope of the friction limit), eps = B - d, N* = b eps.
 *
 * Loop angles (eq. 5) without arccos: the printed arguments simplify exactly to
 *   1 - cos th1 = 2 b eps / ((a + b) B),  1 - cos th2 = eps / B,  1 + cos th3 = (a - b) eps / (a B),
 * and an angle t with 1 - cos t = c is 2 asin(sqrt(c / 2)) (accurate also for tiny c, i.e. B -> d).
 * In the stick-slip regime (a >= b) all three lie in [0, 2] and 0 <= th1 <= th2 <= pi - th2 <= th3
 * <= pi; in full stick (a < b) th1 and th3 do not exist and are never formed.
 *
 * Closed forms (derived from eq. 4 over [0, pi], the second half-period being the mirror image
 * F(theta + pi) = -F(theta)); they are eq. 7, 8 (with the docs/model.md fix) and 10 rearranged so that
 * no term cancels as B -> d+ (S1(x) = x - sin x, phi3 = pi - th3):
 *   int_0^pi F cos = (a + b) B S1(2 th1)/4 + a B [S1(2 th2) - S1(2 phi3)]/4 - N* sin th2
 *       (integration by parts: F is linear in cos theta on the stick pieces and jumps by N* at th2)
 *   int_0^pi F sin = -(b eps^2 / B) [(a - b)/(a + b) + (2 a - b)/(2 a)]   (every term >= 0)
 *   p_k = (k_n cos g / pi) S1(2 th2)                                        (eq. 10 with d = B cos th2)
 *   f_k = (2/(pi B)) int_0^pi F cos,  f_c omega = -(2/(pi B)) int_0^pi F sin.
 * Coulomb limit (th1 = 0, th3 = pi - th2): f_k = 0, f_c omega = 4 N* eps / (pi B^2).
 * Full stick: F = (k_d tan g / k_n) F_n, so f_k = (k_d tan g / k_n) p_k and f_c = 0. */
#include "contact.h"

#include <math.h>
#include <stddef.h>

#define CONTACT_PI 3.14159265358979323846
#define CONTACT_HALF_PI 1.57079632679489661923

/* Everything about the loop at one amplitude B > d. */
typedef struct {
    Regime regime;
    int coulomb;    /* 1: Coulomb limit (no stick pieces) */
    double a;       /* k_d sin g [N/m] */
    double b;       /* mu k_n cos g [N/m] */
    double B;       /* amplitude [m] */
    double eps;     /* B - d [m] */
    double r;       /* (B - d) / B [-]: the closed forms use it so they never under/overflow */
    double Nstar;   /* N* = mu k_n cos g (B - d) [N] */
    double th1;     /* eq. 5 [rad] */
    double th2;     /* eq. 5 [rad] */
    double th3;     /* eq. 5 [rad] */
    double phi3;    /* pi - th3 [rad] */
} Loop;

/* x - sin x for x >= 0, by its series below 1 (no cancellation), directly above. */
static double xMinusSin(double x) {
    if (x < 1.0) {
        double x2 = x * x, term = x * x2 / 6.0, sum = 0.0;
        int k;
        for (k = 1; k <= 12; ++k) {
            sum += term;
            term *= -x2 / ((2.0 * k + 2.0) * (2.0 * k + 3.0));
        }
        return sum;
    }
    return x - sin(x);
}

/* The angle t in [0, pi] with 1 - cos t = c, c in [0, 2]. */
static double angleFromVersine(double c) {
    double h = 0.5 * c;
    if (h < 0.0) h = 0.0; /* c >= 0 holds mathematically; guards rounding only */
    if (h > 1.0) h = 1.0;
    return 2.0 * asin(sqrt(h));
}

int contactParamsValid(const ContactParams *p) {
    if (p == NULL) return 0;
    if (!isfinite(p->kn) || !isfinite(p->kdRatio) || !isfinite(p->mu) || !isfinite(p->gamma) ||
        !isfinite(p->d))
        return 0;
    if (p->kn < 0.0 || p->kdRatio < 0.0 || p->mu < 0.0 || p->d < 0.0) return 0;
    if (p->gamma < 0.0 || p->gamma > CONTACT_HALF_PI) return 0;
    return 1;
}

static int modelValid(FrictionModel model) {
    return model == FrictionMacroslipDF || model == FrictionCoulombDF || model == FrictionMacroslipTD;
}

Regime contactRegime(const ContactParams *p, double B) {
    double kd;
    if (!contactParamsValid(p) || !isfinite(B) || B <= p->d) return RegimeOpen;
    kd = p->kdRatio * p->kn;
    /* docs/model.md s.3: stick-slip iff k_d tan(gamma) >= mu k_n */
    return (kd * tan(p->gamma) >= p->mu * p->kn) ? RegimeStickSlip : RegimeFullStick;
}

Regime contactModelRegime(const ContactParams *p, FrictionModel model, double B) {
    Regime r = contactRegime(p, B);
    if (model == FrictionCoulombDF && r != RegimeOpen) return RegimeStickSlip; /* model-notes s.5 */
    return r;
}

/* Fills the loop for B > d (caller checked params, model and B). */
static void loopSetup(const ContactParams *p, FrictionModel model, double B, Loop *L) {
    double sg = sin(p->gamma), cg = cos(p->gamma);
    L->coulomb = (model == FrictionCoulombDF);
    L->regime = contactModelRegime(p, model, B);
    L->a = p->kdRatio * p->kn * sg;
    L->b = p->mu * p->kn * cg;
    L->B = B;
    L->eps = B - p->d;
    L->r = L->eps / B;
    L->Nstar = L->b * L->eps;
    L->th2 = angleFromVersine(L->r);
    L->th1 = 0.0;
    L->th3 = 0.0;
    L->phi3 = 0.0;
    if (L->coulomb) {
        L->phi3 = L->th2;
        L->th3 = CONTACT_PI - L->th2;
    } else if (L->regime == RegimeStickSlip) {
        double a = L->a, b = L->b;
        if (a > 0.0) {
            double amb = a - b;
            if (amb < 0.0) amb = 0.0; /* a >= b in this regime; guards rounding of the tan test */
            L->th1 = angleFromVersine(2.0 * (b / (a + b)) * L->r);
            L->phi3 = angleFromVersine((amb / a) * L->r);
        } else {
            /* a = 0 here forces b = 0 (a >= b): no friction at all; the pieces collapse */
            L->th1 = 0.0;
            L->phi3 = L->th2;
        }
        if (L->th1 > L->th2) L->th1 = L->th2;     /* th1 <= th2 holds for a >= b */
        if (L->phi3 > L->th2) L->phi3 = L->th2;   /* th3 >= pi - th2 holds always */
        L->th3 = CONTACT_PI - L->phi3;
    }
}

/* S1(2 th2) - S1(2 phi3) without cancellation when phi3 -> th2 (large a/b):
 * with h = 2 (th2 - phi3), m = th2 + phi3: S1(X) - S1(Y) = 2 S1(h/2) + 4 sin(h/2) sin^2(m/2),
 * and th2 - phi3 = 2 (asin x - asin y) = 2 asin((x^2 - y^2)/(x sqrt(1-y^2) + y sqrt(1-x^2))),
 * x^2 = r/2, y^2 = (a-b) r/(2 a), x^2 - y^2 = b r / (2 a), r = eps/B. */
static double stickDifference(const Loop *L) {
    double x2 = 0.5 * L->r, y2 = 0.5 * ((L->a - L->b) / L->a) * L->r;
    double dx2 = 0.5 * (L->b / L->a) * L->r, x, y, den, half, m, sh;
    if (y2 < 0.0) y2 = 0.0;
    if (y2 > x2) y2 = x2;
    x = sqrt(x2);
    y = sqrt(y2);
    den = x * sqrt(1.0 - y2) + y * sqrt(1.0 - x2);
    if (!(den > 0.0)) return 0.0;
    half = 2.0 * asin(fmin(1.0, dx2 / den)); /* th2 - phi3 = h/2 */
    m = L->th2 + L->phi3;
    sh = sin(0.5 * m);
    return 2.0 * xMinusSin(half) + 4.0 * sin(half) * sh * sh;
}

static void zeroDF(DescribingFunction *out) {
    out->regime = RegimeOpen;
    out->theta1 = out->theta2 = out->theta3 = 0.0;
    out->fk = out->fcOmega = out->pk = out->Keq = out->CeqOmega = 0.0;
}

int contactDescribe(const ContactParams *p, FrictionModel model, Projection projection, double B,
                    DescribingFunction *out) {
    Loop L;
    double sg, cg, fk, fcOmega, pk;
    if (out == NULL) return 1;
    zeroDF(out);
    if (!contactParamsValid(p)) return 2;
    if (!modelValid(model)) return 3;
    if (projection != ProjectionPaper && projection != ProjectionConsistent) return 4;
    if (!isfinite(B) || B < 0.0) return 5;
    if (B <= p->d) return 0; /* open: all zero, the limit B -> d+ is continuous */

    loopSetup(p, model, B, &L);
    sg = sin(p->gamma);
    cg = cos(p->gamma);
    pk = p->kn * cg * xMinusSin(2.0 * L.th2) / CONTACT_PI; /* eq. 10 */
    if (L.coulomb) {
        fk = 0.0;
        fcOmega = 4.0 * L.b * L.r * L.r / CONTACT_PI; /* 4 N* (B - d) / (pi B^2) */
    } else if (L.regime == RegimeFullStick) {
        fk = p->kdRatio * tan(p->gamma) * pk;
        fcOmega = 0.0;
    } else if (L.a > 0.0) {
        double a = L.a, b = L.b;
        /* (int_0^pi F cos) / B, eq. 7 */
        double IcOverB = (a + b) * xMinusSin(2.0 * L.th1) / 4.0 + a * stickDifference(&L) / 4.0 -
                         b * L.r * sin(L.th2);
        double bracket = (a - b) / (a + b) + (2.0 * a - b) / (2.0 * a);
        if (bracket < 0.5) bracket = 0.5; /* >= 1/2 for a >= b; guards rounding only */
        fk = 2.0 * IcOverB / CONTACT_PI;
        fcOmega = 2.0 * b * L.r * L.r * bracket / CONTACT_PI;  /* eq. 8 fixed: 2 b eps^2 [.]/(pi B^2) */
    } else {
        fk = 0.0;
        fcOmega = 0.0;
    }

    out->regime = L.regime;
    out->theta1 = L.th1;
    out->theta2 = L.th2;
    out->theta3 = L.th3;
    out->fk = fk;
    out->fcOmega = fcOmega;
    out->pk = pk;
    if (projection == ProjectionPaper) {
        out->Keq = (fk + pk) * sg; /* eq. 12 */
    } else {
        out->Keq = fk * sg + pk * cg; /* from eq. 18: F_n cos g + F_f sin g */
    }
    out->CeqOmega = fcOmega * sg; /* eq. 13, p_c = 0 (eq. 11) */
    if (!isfinite(out->fk) || !isfinite(out->fcOmega) || !isfinite(out->pk) || !isfinite(out->Keq) ||
        !isfinite(out->CeqOmega) || !isfinite(out->theta1) || !isfinite(out->theta2) ||
        !isfinite(out->theta3)) {
        zeroDF(out);
        return 6;
    }
    return 0;
}

double contactNormalForce(const ContactParams *p, double v) {
    if (!contactParamsValid(p) || !isfinite(v)) return NAN;
    if (v > p->d) return p->kn * (v - p->d) * cos(p->gamma);  /* eq. 3 */
    if (v < -p->d) return p->kn * (v + p->d) * cos(p->gamma);
    return 0.0;
}

/* Reduces theta to [0, 2 pi). */
static double wrapPhase(double theta) {
    double t = fmod(theta, 2.0 * CONTACT_PI);
    if (t < 0.0) t += 2.0 * CONTACT_PI;
    if (t >= 2.0 * CONTACT_PI) t = 0.0;
    return t;
}

/* Eq. 4 on the first half-period [0, pi); the second half is -F(theta - pi). The stick pieces use
 * B cos t - d = eps - 2 B sin^2(t/2) (exact, no cancellation near t = 0). */
static double halfLoopFriction(const Loop *L, double t) {
    double s, sp;
    if (L->regime == RegimeFullStick && !L->coulomb) {
        if (t < L->th2) {
            s = sin(0.5 * t);
            return L->a * (L->eps - 2.0 * L->B * s * s);         /* k_d (Delta_u - d sin g) */
        }
        if (t < CONTACT_PI - L->th2) return 0.0;
        sp = sin(0.5 * (CONTACT_PI - t));
        return -L->a * (L->eps - 2.0 * L->B * sp * sp);           /* k_d (Delta_u + d sin g) */
    }
    if (t < L->th1) { /* interval 1: k_d (Delta_u - B sin g) + mu k_n cos g (v - d) */
        s = sin(0.5 * t);
        return L->b * L->eps - (L->a + L->b) * 2.0 * L->B * s * s;
    }
    if (t < L->th2) return -L->Nstar;                 /* interval 2 */
    if (t < CONTACT_PI - L->th2) return 0.0;          /* interval 3 */
    if (t < L->th3) {                                 /* interval 4: k_d (Delta_u + d sin g) */
        sp = sin(0.5 * (CONTACT_PI - t));
        return -L->a * (L->eps - 2.0 * L->B * sp * sp);
    }
    return -L->Nstar;                                 /* interval 5 */
}

double contactLoopFriction(const ContactParams *p, FrictionModel model, double B, double theta) {
    Loop L;
    double t;
    if (!contactParamsValid(p) || !modelValid(model) || !isfinite(B) || B < 0.0 || !isfinite(theta)) return NAN;
    if (B <= p->d) return 0.0;
    loopSetup(p, model, B, &L);
    t = wrapPhase(theta);
    if (t < CONTACT_PI) return halfLoopFriction(&L, t);
    return -halfLoopFriction(&L, t - CONTACT_PI);
}

int contactLoopSwitchAngles(const ContactParams *p, FrictionModel model, double B, double angle[5]) {
    Loop L;
    if (!contactParamsValid(p) || !modelValid(model) || !isfinite(B) || B <= p->d) return 0;
    loopSetup(p, model, B, &L);
    if (L.regime != RegimeStickSlip) return 0; /* full stick: always 1, no phase dependence */
    /* the interval ends of contactLoopState, in the same order */
    angle[0] = 0.0;
    angle[1] = L.th1;
    angle[2] = L.th2;
    angle[3] = CONTACT_PI - L.th2;
    angle[4] = L.th3;
    return 5;
}

ContactState contactLoopState(const ContactParams *p, FrictionModel model, double B, double theta) {
    Loop L;
    double t;
    if (!contactParamsValid(p) || !modelValid(model) || !isfinite(B) || B < 0.0 || !isfinite(theta))
        return ContactOpen;
    if (B <= p->d) return ContactOpen;
    loopSetup(p, model, B, &L);
    if (L.regime == RegimeFullStick) return ContactStick; /* model-notes s.4: always 1 */
    t = wrapPhase(theta);
    if (t >= CONTACT_PI) t -= CONTACT_PI; /* interval k + 5 mirrors interval k */
    if (t < L.th1) return ContactStick;                 /* 1, 6 */
    if (t < L.th2) return ContactSlip;                  /* 2, 7 */
    if (t < CONTACT_PI - L.th2) return ContactOpen;     /* 3, 8 */
    if (t < L.th3) return ContactStick;                 /* 4, 9 */
    return ContactSlip;                                 /* 5, 10 */
}
