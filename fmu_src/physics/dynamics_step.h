/* The functions an integrator calls at every step: the contact gate, the right-hand side
 * (eq. 27) and the switching functions (model-notes s.2, s.6). Inline: called several times per
 * RK4 step, a call would cost a third of the step. */
#ifndef DYNAMICS_STEP_H
#define DYNAMICS_STEP_H

#include <math.h>

#include "physics/dynamics.h"

/* 1 if the contact force is switched on in s (DF: gate on; Jenkins element: in contact). */
static inline int dynContactOn(const DynModel *m, const DynState *s)
{
    if (m->friction == FrictionMacroslipTD) return s->mode != ContactOpen;
    return s->mode == GateOn;
}

/* The aerodynamic load [N/m] at phase psi: the input fw plus the built-in F_w0 sin(psi + lead)
 * (skipped when off: bit-identical to the input alone). */
static inline double dynLoad(const DynModel *m, double fw, double psi)
{
    return m->loadAmplitude != 0.0 ? fw + m->loadAmplitude * sin(psi + m->loadLead) : fw;
}

/* The contact force F_c [N] on the contact coordinate q = x[0] (the tip) in the discrete state of s,
 * its dissipated power P [W] and the slider rate dw/dt (eq. 3, 12-14, model-notes s.2). Returns 1 if
 * omega <= 0 while a describing-function force is needed. */
static inline int dynContactForce(const DynModel *m, const DynState *s, double omega, const double x[],
                                  double *FcOut, double *POut, double *dwOut)
{
    const double q = x[0], v = x[1];
    double Fc = 0.0, P = 0.0, dw = 0.0;
    int bad = 0;
    if (m->friction == FrictionMacroslipTD) {
        const double sig = (double)s->side;
        switch (s->mode) {
        case ContactStick: {
            const double Fn = m->knCos * (q - sig * m->contact.d); /* eq. 3 */
            const double Ff = m->kd * (m->sinG * q - x[4]);        /* spring k_d (Delta_u - w) */
            Fc = Fn * m->cosG + Ff * m->sinG;                      /* eq. 14 */
            break;
        }
        case ContactSlip: {
            const double sd = (double)s->slipDir;
            const double Fn = m->knCos * (q - sig * m->contact.d);
            const double Ff = sd * m->muKnCos * (sig * q - m->contact.d); /* F_f = s mu |F_n| */
            Fc = Fn * m->cosG + Ff * m->sinG;
            dw = (m->sinG - sd * sig * m->muKnCosPerKd) * v; /* w = Delta_u - s L / k_d */
            P = Ff * dw;
            break;
        }
        default:
            dw = m->sinG * v; /* open: w follows Delta_u (spring unloaded) */
            break;
        }
    } else if (s->mode == GateOn && s->df.regime != RegimeOpen) {
        /* eq. 27 with eq. 12-13: F_c = K_eq q + C_eq q', C_eq = (C_eq omega) / omega */
        double Ceq = 0.0;
        if (omega > 0.0) Ceq = s->df.CeqOmega / omega;
        else bad = 1;
        Fc = s->df.Keq * q + Ceq * v;
        P = Ceq * v * v;
    }
    *FcOut = Fc;
    *POut = P;
    *dwOut = dw;
    return bad;
}

/* f = dx/dt of the one-mode blade at state x for inputs fw [N/m], n [rpm] and an external force
 * fext [N] on q (positive along q; 0 for ShroudedBlade) with the discrete state of s (eq. 27 plus
 * fext on the right). Returns 1 if omega <= 0 while a describing-function force is needed
 * (model-notes s.2). */
static inline int dynRhsOne(const DynModel *m, const DynState *s, double fw, double n, double fext,
                            const double x[DYN_NX_MAX], double f[DYN_NX_MAX])
{
    const double q = x[0], v = x[1];
    const double Omega = DYN_RAD_PER_RPM * n;
    const double omega = m->omegaPerRpm * n;
    const double K0 = m->K0static + m->K0omega2 * Omega * Omega; /* eq. 26 */
    double Fc, P, dw;
    const int bad = dynContactForce(m, s, omega, x, &Fc, &P, &dw);
    f[0] = v;
    {
        double a = m->G * dynLoad(m, fw, x[2]) - m->C0 * v - K0 * q - Fc; /* generalized force [N] */
        if (fext != 0.0) a += fext; /* skipped for 0: bit-identical to the blade without it */
        f[1] = a * m->invM;
    }
    f[2] = omega;
    f[3] = m->C0 * v * v + P;
    f[4] = dw;
    return bad;
}

/* dynRhsOne for m > 1 modes (docs/model.md s.2a): the contact acts on the tip u = x[0]. */
static inline int dynRhsMulti(const DynModel *m, const DynState *s, double fw, double n, double fext,
                              const double x[DYN_NX_MAX], double f[DYN_NX_MAX])
{
    const double Omega = DYN_RAD_PER_RPM * n;
    const double omega = m->omegaPerRpm * n;
    double Fc, P, dw;
    const int bad = dynContactForce(m, s, omega, x, &Fc, &P, &dw);
    dynRhsModes(m, dynLoad(m, fw, x[2]), Omega, fext - Fc, x, f);
    f[2] = omega;
    f[3] += P;
    f[4] = dw;
    return bad;
}

/* dx/dt for any number of modes. */
static inline int dynRhsExt(const DynModel *m, const DynState *s, double fw, double n, double fext,
                            const double x[DYN_NX_MAX], double f[DYN_NX_MAX])
{
    return m->modes > 1 ? dynRhsMulti(m, s, fw, n, fext, x, f) : dynRhsOne(m, s, fw, n, fext, x, f);
}

/* dynRhsExt without an external force (ShroudedBlade, model exchange). */
static inline int dynRhs(const DynModel *m, const DynState *s, double fw, double n, const double x[DYN_NX_MAX],
                         double f[DYN_NX_MAX])
{
    return dynRhsExt(m, s, fw, n, 0.0, x, f);
}

/* The switching functions active in the discrete state of s, at state x with f = dx/dt, in
 * priority order (at equal instants the first wins: contact loss first). The list depends only
 * on m and s. The stick functions use s->w (w is constant in stick). Returns their number. */
static inline int dynSwitching(const DynModel *m, const DynState *s, double h, const double x[DYN_NX],
                               const double f[DYN_NX], DynSwitchValue out[DYN_MAX_SWITCHING])
{
    const double q = x[0], v = x[1];
    const int contactModel = m->friction == FrictionMacroslipTD;
    int n = 0;
#define SWITCH(k, value, slope) \
    do { out[n].kind = (k); out[n].g = (value); out[n].hdg = (slope); ++n; } while (0)
    if (contactModel || m->gating) {
        const double d = m->contact.d;
        if (dynContactOn(m, s)) {
            const double sg = (double)s->side;
            /* |q| > d while in contact: sigma q - d >= 0 (eq. 3, 12-13) */
            SWITCH(DynSwitchLeave, sg * q - d, sg * h * v);
        } else {
            SWITCH(DynSwitchEnterPos, d - q, -h * v);
            SWITCH(DynSwitchEnterNeg, d + q, h * v);
        }
    }
    if (contactModel && s->mode == ContactStick) {
        /* stick while |F_f| <= L: L -+ F_f >= 0, F_f = kd (sin g q - w), L = mu kn cos g (sigma q - d) */
        const double sg = (double)s->side, w = s->w;
        const double aP = sg * m->muKnCos - m->kd * m->sinG, bP = -m->muKnCos * m->contact.d + m->kd * w;
        const double aN = sg * m->muKnCos + m->kd * m->sinG, bN = -m->muKnCos * m->contact.d - m->kd * w;
        SWITCH(DynSwitchSlipPos, aP * q + bP, aP * h * v);
        SWITCH(DynSwitchSlipNeg, aN * q + bN, aN * h * v);
    } else if (contactModel && s->mode == ContactSlip) {
        /* slip while s kd sin g q' - L' >= 0 (model-notes s.2): (s kd sin g - sigma mu kn cos g) q' */
        const double cs = s->slipDir * m->kd * m->sinG - s->side * m->muKnCos;
        if (cs != 0.0) {
            const double sg = cs > 0.0 ? 1.0 : -1.0;
            SWITCH(DynSwitchStick, sg * v, sg * h * f[1]);
        }
    }
    if (m->tracked) {
        const double target = DYN_TWO_PI * (s->periods + 1.0); /* period k ends at psi = 2 pi k */
        SWITCH(DynSwitchPeriod, target - x[2], -h * f[2]);
        SWITCH(DynSwitchExtremum, s->vdir * v, s->vdir * h * f[1]);
    }
#undef SWITCH
    return n;
}

#endif
