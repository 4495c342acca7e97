/* Dynamics of the one-mode blade with shroud contact (docs/model-notes.md s.1-s.4; see dynamics.h).
 *
 * Equation of motion (eq. 27, model-notes s.2):
 *   M q'' + C0 q' + K0(Omega) q = G f_w(t) - F_c,   psi' = omega,   E' = C0 q'^2 + P.
 * The discrete state (gate, Jenkins mode, side, slip direction) is pinned between events, so the
 * right-hand side is smooth between them; an integrator watches the switching functions and
 * calls dynApplyEvent at the first instant one of them turns negative. */
#include "physics/dynamics_step.h"

#include <math.h>
#include <string.h>


/* ------------------------------------------------------------------------------------------- */
/* Model constants, initial state                                                               */

int dynBuildModel(DynModel *m, const BladeReduction *r, const ContactParams *cp, FrictionModel friction,
                  Projection projection, int gating, int tracked, int engineOrder)
{
    memset(m, 0, sizeof *m);
    if (!(r->M > 0.0) || !isfinite(r->M) || engineOrder < 1) return 1;
    if (friction != FrictionNone && cp == NULL) return 1;
    m->friction = friction;
    m->projection = projection;
    m->gating = gating ? 1 : 0;
    m->tracked = tracked ? 1 : 0;
    m->invM = 1.0 / r->M;
    m->C0 = r->C0;
    m->K0static = r->K0static;
    m->K0omega2 = r->K0omega2;
    m->G = r->loadGain;
    m->omegaPerRpm = (double)engineOrder * DYN_TWO_PI / 60.0;
    m->modes = 1;
    if (friction == FrictionNone) {
        /* no built-in contact: no gate, no amplitude, no contact constants (all 0) */
        m->gating = 0;
        m->tracked = 0;
        return 0;
    }
    m->contact = *cp;
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

/* T^T A T for q = T y, y = (u, q_2..q_m): q_1 = u - sum_{k>=2} q_k (docs/model.md s.2a) */
static void congruence(int n, const double *A, double out[MODES_MAX][MODES_MAX])
{
    double T[MODES_MAX][MODES_MAX] = {{0.0}};
    for (int k = 0; k < n; ++k) T[k][k] = 1.0;
    for (int k = 1; k < n; ++k) T[0][k] = -1.0;
    for (int a = 0; a < n; ++a)
        for (int b = 0; b < n; ++b) {
            double v = 0.0;
            for (int i = 0; i < n; ++i)
                for (int j = 0; j < n; ++j) v += T[i][a] * A[i * MODES_MAX + j] * T[j][b];
            out[a][b] = v;
        }
}

int dynBuildModes(DynModel *m, const ModalReduction *r)
{
    const int n = r->m;
    m->modes = n;
    congruence(n, &r->M[0][0], m->My);
    congruence(n, &r->C[0][0], m->Cy);
    congruence(n, &r->Kstatic[0][0], m->Ky);
    congruence(n, &r->Komega2[0][0], m->Ky2);
    m->Gy[0] = r->load[0];
    for (int k = 1; k < n; ++k) m->Gy[k] = r->load[k] - r->load[0]; /* T^T g */
    return modesInverse(n, &m->My[0][0], m->invMy);
}

double dynTipOf(const DynModel *m, const double a[MODES_MAX])
{
    double u = a[0];
    for (int k = 1; k < m->modes; ++k) u += a[k];
    return u;
}

void dynModalState(const DynModel *m, const DynState *s, double q[MODES_MAX], double v[MODES_MAX])
{
    q[0] = s->q;
    v[0] = s->v;
    for (int k = 1; k < MODES_MAX; ++k) {
        q[k] = k < m->modes ? s->qx[k - 1] : 0.0;
        v[k] = k < m->modes ? s->vx[k - 1] : 0.0;
        q[0] -= q[k];
        v[0] -= v[k];
    }
}

void dynSetModalStart(const DynModel *m, DynState *s, const double qm[MODES_MAX], const double vm[MODES_MAX])
{
    for (int k = 1; k < m->modes; ++k) {
        s->qx[k - 1] = qm[k];
        s->vx[k - 1] = vm[k];
    }
}

void dynSetLoad(DynModel *m, double fw0, int engineOrder, int bladeIndex, int bladeCount)
{
    m->loadAmplitude = fw0;
    m->loadLead = DYN_TWO_PI * (double)engineOrder * (double)bladeIndex / (double)bladeCount;
}

DynStatus dynUpdateDescribe(const DynModel *m, DynState *s)
{
    /* the Jenkins element reports the macroslip DF (model-notes s.4) */
    const FrictionModel dfModel = m->friction == FrictionMacroslipTD ? FrictionMacroslipDF : m->friction;
    DescribingFunction df;
    memset(&s->df, 0, sizeof s->df);
    s->df.regime = RegimeOpen;
    if (m->friction == FrictionNone) return DynOk; /* no contact: nothing to describe */
    if (!(s->B > m->contact.d)) return DynOk; /* docs/model.md s.3: B <= d is the open regime, all zero */
    /* nonzero also for a non-finite result (contactDescribe checks every field) */
    if (contactDescribe(&m->contact, dfModel, m->projection, s->B, &df) != 0) return DynDescribeFailed;
    s->df = df;
    return DynOk;
}

static void enterContact(const DynModel *m, DynState *s, int side)
{
    s->side = side;
    s->w = m->sinG * s->q; /* the spring is unloaded on arrival (model-notes s.2) */
    if (m->stickAtEntry) {
        s->mode = ContactStick;
    } else {
        const double L = m->muKnCos * (side * s->q - m->contact.d);
        s->mode = ContactSlip;
        s->slipDir = s->v > 0.0 ? 1 : (s->v < 0.0 ? -1 : side);
        s->w = m->sinG * s->q - s->slipDir * L / m->kd;
    }
}

double dynStartForceLimit(const DynModel *m, double q0)
{
    const double sig = q0 >= 0.0 ? 1.0 : -1.0;
    if (!(fabs(q0) > m->contact.d)) return -1.0;
    return m->muKnCos * (sig * q0 - m->contact.d); /* L = mu |F_n| (eq. 3) */
}

/* Jenkins element starting in contact with spring force F0 (model-notes s.7). */
static void initContactForce(const DynModel *m, DynState *s, double F0)
{
    const double L = dynStartForceLimit(m, s->q);
    s->mode = ContactStick;
    s->w = m->sinG * s->q - F0 / m->kd; /* F_f = kd (Delta_u - w) = F0 */
    if (fabs(F0) >= L * (1.0 - DYN_CONE_RTOL)) {
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

DynStatus dynInitState(const DynModel *m, DynState *s, double q0, double v0, double E0, double F0, double B0,
                       double windowMax0)
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
        s->mode = fabs(q0) > m->contact.d ? ContactStick : ContactOpen;
        if (s->mode == ContactStick && F0 != 0.0) initContactForce(m, s, F0);
    } else if (m->friction == FrictionNone) {
        s->mode = GateOff; /* no contact force ever */
    } else {
        s->mode = (!m->gating || fabs(q0) > m->contact.d) ? GateOn : GateOff;
    }
    return dynUpdateDescribe(m, s);
}

/* ------------------------------------------------------------------------------------------- */
/* The m-mode right-hand side (out of line: the one-mode dynRhsExt stays small enough to inline) */

/* m > 1 modes (docs/model.md s.2a): y'' = M_y^-1 (G_y load - C_y y' - (K_y + Omega^2 K_y2) y + e_1 F)
 * with y = (x[0], q_2..q_m), y' = (x[1], q_2'..q_m') (dynamics.h), F the force on the tip; sets
 * f[0], f[1], f[3] = y'^T C_y y' (viscous power) and the rates of the extra coordinates (0 above m). */
void dynRhsModes(const DynModel *m, double load, double Omega, double F, const double x[],
                               double f[])
{
    const int n = m->modes, e = DYN_NX - 1, r = DYN_X_RATES - 1; /* y_k = x[e + k], y'_k = x[r + k], k >= 1 */
    const double O2 = Omega * Omega;
    double y[MODES_MAX] = {0.0}, yv[MODES_MAX] = {0.0}, a[MODES_MAX] = {0.0}, power = 0.0;
    y[0] = x[0];
    yv[0] = x[1];
    for (int k = DYN_NX; k < DYN_NX_MAX; ++k) f[k] = 0.0;
    for (int k = 1; k < n; ++k) {
        y[k] = x[e + k];
        yv[k] = x[r + k];
    }
    for (int i = 0; i < n; ++i) {
        double r = m->Gy[i] * load, cv = 0.0;
        for (int j = 0; j < n; ++j) {
            cv += m->Cy[i][j] * yv[j];
            r -= (m->Ky[i][j] + O2 * m->Ky2[i][j]) * y[j];
        }
        a[i] = r - cv;
        power += yv[i] * cv;
    }
    a[0] += F;
    f[0] = yv[0];
    f[3] = power;
    for (int i = 0; i < n; ++i) {
        double acc = 0.0;
        for (int j = 0; j < n; ++j) acc += m->invMy[i][j] * a[j];
        if (i == 0) f[1] = acc;
        else {
            f[e + i] = yv[i];
            f[r + i] = acc;
        }
    }
}

/* ------------------------------------------------------------------------------------------- */
/* Switching functions and events                                                               */

/* ------------------------------------------------------------------------------------------- */
/* Events                                                                                       */

DynStatus dynApplyEvent(const DynModel *m, DynState *s, DynSwitch sw, DynEventKind *kind)
{
    const int contactModel = m->friction == FrictionMacroslipTD;
    switch (sw) {
    case DynSwitchEnterPos:
    case DynSwitchEnterNeg: {
        const int side = sw == DynSwitchEnterPos ? 1 : -1;
        if (contactModel) {
            enterContact(m, s, side);
            *kind = DynEventContact;
        } else {
            s->mode = GateOn;
            s->side = side;
            *kind = DynEventGateOn;
        }
        break;
    }
    case DynSwitchLeave:
        if (contactModel) {
            s->mode = ContactOpen;
            s->w = m->sinG * s->q; /* separation: the spring unloads */
            *kind = DynEventSeparate;
        } else {
            s->mode = GateOff;
            *kind = DynEventGateOff;
        }
        break;
    case DynSwitchSlipPos:
    case DynSwitchSlipNeg: {
        const double L = m->muKnCos * (s->side * s->q - m->contact.d);
        s->mode = ContactSlip;
        s->slipDir = sw == DynSwitchSlipPos ? 1 : -1;
        s->w = m->sinG * s->q - s->slipDir * L / m->kd; /* F_f = s L exactly */
        *kind = DynEventStickToSlip;
        break;
    }
    case DynSwitchStick:
        s->mode = ContactStick;
        *kind = DynEventSlipToStick;
        break;
    case DynSwitchPeriod: {
        /* model-notes s.3: B = max |q| over the period that ends now */
        const double aq = fabs(s->q);
        const double newB = s->windowMax > aq ? s->windowMax : aq;
        s->periods += 1.0;
        s->windowMax = aq;
        *kind = DynEventPeriodEnd;
        if (newB != s->B) {
            s->B = newB;
            return dynUpdateDescribe(m, s);
        }
        break;
    }
    case DynSwitchExtremum: {
        const double aq = fabs(s->q);
        if (aq > s->windowMax) s->windowMax = aq;
        s->vdir = -s->vdir;
        *kind = DynEventExtremum;
        break;
    }
    default:
        break;
    }
    return DynOk;
}

/* ------------------------------------------------------------------------------------------- */
/* Outputs (model-notes s.4)                                                                    */

void dynOutputs(const DynModel *m, const DynState *s, double nRpm, DynOutputs *out)
{
    const double Omega = DYN_RAD_PER_RPM * nRpm;
    const double omega = m->omegaPerRpm * nRpm;
    const double K0 = m->K0static + m->K0omega2 * Omega * Omega;
    /* f_c and C_eq carry 1/omega; with omega = 0 (no rotation) they are reported as 0, and so
     * they are when omega is so small (< ~1e-300 rad/s) that the quotient overflows */
    const double CeqDF = omega > 0.0 && isfinite(s->df.CeqOmega / omega) ? s->df.CeqOmega / omega : 0.0;
    const double fc = omega > 0.0 && isfinite(s->df.fcOmega / omega) ? s->df.fcOmega / omega : 0.0;
    const double sig = (double)s->side;
    /* m > 1: an eigenproblem (dynModeFrequencies), left to the caller (once per rotor speed) */
    out->naturalFrequency = m->modes > 1 ? 0.0 : sqrt((K0 > 0.0 ? K0 : 0.0) * m->invM) / DYN_TWO_PI;
    out->regime = (int)s->df.regime;
    if (m->friction == FrictionMacroslipTD) {
        out->Keq = s->df.Keq; /* information only: the DF at the B in use */
        out->Ceq = CeqDF;
        switch (s->mode) {
        case ContactStick:
            out->normalForce = m->knCos * (s->q - sig * m->contact.d);
            out->frictionForce = m->kd * (m->sinG * s->q - s->w);
            out->jenkinsForce = out->frictionForce;
            out->contactState = ContactStick;
            break;
        case ContactSlip:
            out->normalForce = m->knCos * (s->q - sig * m->contact.d);
            out->frictionForce = s->slipDir * m->muKnCos * (sig * s->q - m->contact.d);
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
        const int g = dynContactOn(m, s);
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
            if (theta < 0.0) theta += DYN_TWO_PI;
            if (theta >= DYN_TWO_PI) theta = 0.0;
            out->contactState = (int)contactLoopState(&m->contact, m->friction, s->B, theta);
        }
    }
}

void dynModeFrequencies(const DynModel *m, double nRpm, double f[MODES_MAX])
{
    const double Omega = DYN_RAD_PER_RPM * nRpm;
    for (int k = 0; k < MODES_MAX; ++k) f[k] = 0.0;
    if (m->modes == 1) {
        const double K0 = m->K0static + m->K0omega2 * Omega * Omega;
        f[0] = sqrt((K0 > 0.0 ? K0 : 0.0) * m->invM) / DYN_TWO_PI; /* as naturalFrequency */
        return;
    }
    {
        double K[MODES_MAX][MODES_MAX] = {{0.0}}, w2[MODES_MAX];
        const int n = m->modes;
        for (int a = 0; a < n; ++a)
            for (int b = 0; b < n; ++b) K[a][b] = m->Ky[a][b] + Omega * Omega * m->Ky2[a][b];
        /* (K_y, M_y) is congruent to the modal (K, M): the same eigenvalues */
        if (modesEigenvalues(n, &m->My[0][0], &K[0][0], w2) != 0) {
            for (int k = 0; k < n; ++k) f[k] = NAN;
            return;
        }
        for (int k = 0; k < n; ++k) f[k] = sqrt(w2[k] > 0.0 ? w2[k] : 0.0) / DYN_TWO_PI;
    }
}

const char *dynNonFiniteOutput(const DynOutputs *o)
{
    if (!isfinite(o->normalForce)) return "normalForce";
    if (!isfinite(o->frictionForce)) return "frictionForce";
    if (!isfinite(o->jenkinsForce)) return "jenkinsForce";
    if (!isfinite(o->Keq)) return "Keq";
    if (!isfinite(o->Ceq)) return "Ceq";
    if (!isfinite(o->naturalFrequency)) return "naturalFrequency";
    return NULL;
}
