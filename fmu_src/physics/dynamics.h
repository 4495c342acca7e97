/* Dynamics of the one-mode blade with shroud contact (docs/model-notes.md s.1-s.4): the model
 * constants, the right-hand side, the switching functions and the discrete updates at their
 * events, the initial state and the outputs. Public so that any integrator (the co-simulation RK4
 * of solver/rk4_events.c, a Model Exchange master) can use them. Pure C: no FMI types, no
 * allocation, no logging. The functions called at every step (right-hand side, switching
 * functions) are inline in dynamics_step.h. */
#ifndef DYNAMICS_H
#define DYNAMICS_H

#include <stdint.h>

#include "physics/blade.h"
#include "physics/contact.h"
#include "physics/modes.h"

/* Number of continuous states x = (q, v, psi, E, w) of the one-mode blade. With m > 1 modes
 * (docs/model.md s.2a) q, v are the tip displacement u = sum_i q_i and its rate, and the modal
 * coordinates q_2..q_6 and their rates follow at fixed places (those above m held at 0):
 * x[DYN_NX + k] = q_{k+2}, x[DYN_X_RATES + k] = q_{k+2}' (k = 0..4). */
#define DYN_NX 5
#define DYN_NX_MAX (DYN_NX + 2 * (MODES_MAX - 1))
#define DYN_X_RATES (DYN_NX + MODES_MAX - 1)

#define DYN_TWO_PI 6.283185307179586476925286766559
/* Rotor speed conversion: Omega [rad/s] = DYN_RAD_PER_RPM n [rpm]. */
#define DYN_RAD_PER_RPM (DYN_TWO_PI / 60.0)

/* Relative tolerance of |F0| = L at the start (rounding of a force read back from an output). */
#define DYN_CONE_RTOL 1e-12

typedef enum {
    DynOk = 0,
    DynNonFinite = 1,      /* a state became NaN or infinite (reported by an integrator) */
    DynChattering = 2,     /* too many events in one step (reported by an integrator) */
    DynOmegaZero = 3,      /* omega <= 0 while a describing-function contact force is needed */
    DynDescribeFailed = 4  /* contactDescribe refused the amplitude */
} DynStatus;

/* The describing-function models' gate (eq. 12-13): the DF forces act while it is on. */
typedef enum { GateOff = 0, GateOn = 1 } Gate;

/* Constants of the right-hand side, precomputed once per run (after initialization). */
typedef struct {
    FrictionModel friction;   /* 1 macroslip DF, 2 Coulomb DF, 3 time-domain Jenkins element */
    Projection projection;    /* DF projection (docs/model.md s.3) */
    int gating;               /* 1: DF forces only while |q| > d (eq. 12-13) */
    int tracked;              /* 1: amplitudeMode 2 (model-notes s.3) */
    ContactParams contact;    /* kn, kdRatio, mu, gamma, d (the gap is contact.d) */
    /* blade, eq. 26 / docs/model.md s.2 */
    double invM;              /* 1/M, M the generalized mass [1/kg] */
    double C0;                /* generalized viscous damping [N s/m] */
    double K0static;          /* K0 at Omega = 0 [N/m] */
    double K0omega2;          /* dK0/d(Omega^2) [kg] */
    double G;                 /* load gain int phi / phi(l) [m] */
    double omegaPerRpm;       /* excitation omega = omegaPerRpm n = engineOrder 2 pi n / 60 [rad/s per rpm] */
    /* the built-in aerodynamic load (eq. 17), added to the aeroLoad input: F_w0 sin(psi + lead) */
    double loadAmplitude;     /* F_w0 [N/m]; 0: off */
    double loadLead;          /* 2 pi engineOrder i / N: blade i of N in the travelling wave [rad] */
    /* contact constants (eq. 3, 4, 14; model-notes s.2) */
    double sinG, cosG;        /* sin(gamma), cos(gamma) [-] */
    double kd;                /* tangential stiffness kdRatio kn [N/m] */
    double knCos;             /* kn cos(gamma): F_n = knCos (q - sigma d) [N/m] */
    double muKnCos;           /* mu kn cos(gamma): L = muKnCos (sigma q - d) [N/m] */
    double muKnCosPerKd;      /* muKnCos / kd [-]: slip rate w' = (sin g - s sigma muKnCosPerKd) q' */
    int stickAtEntry;         /* 1 if kd tan(gamma) <= mu kn: contact starts in stick */
    /* m > 1 modes (docs/model.md s.2a), in the coordinates y = (u, q_2..q_m) with q = T y:
     * M_y y'' + C_y y' + (K_y + Omega^2 K_y2) y = G_y f_w + e_1 (F_ext - F_c) */
    int modes;                /* m; 1: the one-mode fields above only */
    double My[MODES_MAX][MODES_MAX];    /* T^T M T [kg] */
    double invMy[MODES_MAX][MODES_MAX]; /* M_y^-1 [1/kg] */
    double Cy[MODES_MAX][MODES_MAX];    /* T^T C T [N s/m] */
    double Ky[MODES_MAX][MODES_MAX];    /* T^T Kstatic T [N/m] */
    double Ky2[MODES_MAX][MODES_MAX];   /* T^T Komega2 T [kg] */
    double Gy[MODES_MAX];               /* T^T load [m] */
} DynModel;

/* Continuous states, discrete state and the describing-function cache. Plain data (no
 * pointers): a struct copy is a deep copy. */
typedef struct {
    double q;          /* contact coordinate [m] */
    double v;          /* dq/dt [m/s] */
    double psi;        /* excitation phase [rad] */
    double E;          /* dissipated energy [J] */
    double w;          /* Jenkins slider position in the Delta_u coordinate [m] */
    double B;          /* amplitude in use [m] (model-notes s.3) */
    double windowMax;  /* max |q| over the running excitation period [m] */
    double periods;    /* completed excitation periods [-] (an integer) */
    int32_t mode;      /* DF models: a Gate. Jenkins element: a ContactState */
    int32_t side;      /* contact side sigma = +1 (q > d) or -1 (q < -d) */
    int32_t slipDir;   /* Jenkins slip direction s = sign(F_f), +1 or -1 */
    int32_t vdir;      /* sign of q' since the last extremum, +1 or -1 (tracking) */
    DescribingFunction df; /* describing function at B (derived: recomputed when B changes) */
    double W;          /* work done on q by the external force (solver/rk4_events.h) [J]; 0 without one */
    double qx[MODES_MAX - 1]; /* m > 1: modal coordinates q_2..q_m [m] (q is then the tip u) */
    double vx[MODES_MAX - 1]; /* their rates [m/s] */
} DynState;

/* Builds the model constants. friction, projection, gating, tracked as the FMU parameters;
 * engineOrder >= 1. FrictionNone (no built-in contact, the blade of BladeExternalContact): cp may be
 * NULL, gating and tracking are off, the contact force is 0. Returns 0 on success. */
int dynBuildModel(DynModel *m, const BladeReduction *r, const ContactParams *cp, FrictionModel friction,
                  Projection projection, int gating, int tracked, int engineOrder);

/* The m > 1 part of the model from the modal reduction (after dynBuildModel, which sets m = 1).
 * Returns 0, or nonzero if the modal mass matrix is not positive definite. */
int dynBuildModes(DynModel *m, const ModalReduction *r);

/* Modal coordinates q_1..q_m and rates of state s (q_1 = u - sum q_k; m = 1: q_1 = q). */
void dynModalState(const DynModel *m, const DynState *s, double q[MODES_MAX], double v[MODES_MAX]);

/* The built-in load F_w0 sin(psi + 2 pi engineOrder bladeIndex / bladeCount) [N/m] (eq. 17 on a
 * disk of bladeCount blades; psi = engineOrder int Omega dt is the integrated state, so the load
 * is exact at any communication step and follows any speed history). Call after dynBuildModel. */
void dynSetLoad(DynModel *m, double fw0, int engineOrder, int bladeIndex, int bladeCount);

/* (Re)computes s->df for s->B (macroslip DF for the Jenkins element: outputs only). Returns
 * DynOk or DynDescribeFailed. */
DynStatus dynUpdateDescribe(const DynModel *m, DynState *s);

/* Initial state at rest or at (q0 [m], v0 [m/s], E0 [J]) (model-notes s.7): psi = 0, B = B0 [m],
 * describing function at B0, windowMax = max(|q0|, windowMax0 [m]). Jenkins element (frictionModel
 * 3) in contact (|q0| > d): spring force F0 [N], w = q0 sin(gamma) - F0 / kd; stick if |F0| < L,
 * on the cone |F0| = L (relative DYN_CONE_RTOL) slip in direction sign(F0) if the slip rate
 * (s kd sin g - sigma mu kn cos g) v0 >= 0, else stick. F0 = 0 is the unloaded spring (stick).
 * The caller checks F0 against the cone first (dynStartForceLimit). */
DynStatus dynInitState(const DynModel *m, DynState *s, double q0, double v0, double E0, double F0, double B0,
                       double windowMax0);

/* sum_i a_i, i < m: the tip displacement (rate) of modal coordinates a (phi_i(l) = 1). */
double dynTipOf(const DynModel *m, const double a[MODES_MAX]);

/* m > 1: the modal coordinates q_2..q_m and rates of s from qm, vm (after dynInitState with
 * q0 = dynTipOf(qm), v0 = dynTipOf(vm)). */
void dynSetModalStart(const DynModel *m, DynState *s, const double qm[MODES_MAX], const double vm[MODES_MAX]);

/* Friction limit L = mu kn cos(gamma) (|q0| - d) [N] of the Jenkins element at q0 [m]; -1 if the
 * contact is open there (|q0| <= d). */
double dynStartForceLimit(const DynModel *m, double q0);

/* Switching functions (model-notes s.6). Each is written so that the discrete state of s is
 * consistent while g >= 0; its event is the first instant where g < 0. */
typedef enum {
    DynSwitchNone = 0, DynSwitchEnterPos, DynSwitchEnterNeg, DynSwitchLeave, DynSwitchSlipPos, DynSwitchSlipNeg,
    DynSwitchStick, DynSwitchPeriod, DynSwitchExtremum
} DynSwitch;

#define DYN_MAX_SWITCHING 6 /* at most active at once: gate or contact 2, stick/slip 2, tracking 2 */

typedef struct {
    DynSwitch kind;
    double g;   /* value of the switching function */
    double hdg; /* h dg/dt: its time derivative scaled by the caller's h (1 for the plain slope) */
} DynSwitchValue;

/* Event kinds as reported (for logging). */
typedef enum {
    DynEventGateOn = 1, DynEventGateOff, DynEventContact, DynEventSeparate, DynEventStickToSlip,
    DynEventSlipToStick, DynEventPeriodEnd, DynEventExtremum
} DynEventKind;

/* The discrete update at the event of switching function `sw`, with the continuous state of s at
 * the event instant (model-notes s.2, s.3). *kind receives what happened. */
DynStatus dynApplyEvent(const DynModel *m, DynState *s, DynSwitch sw, DynEventKind *kind);

/* Output values (model-notes s.4). */
typedef struct {
    double normalForce;      /* [N] */
    double frictionForce;    /* [N] */
    double jenkinsForce;     /* Jenkins spring force kd (sin g q - w) in contact, else 0 [N] */
    double Keq;              /* [N/m] */
    double Ceq;              /* [N s/m] */
    double naturalFrequency; /* [Hz]; m > 1: 0, the caller sets modeFrequency[1] (dynModeFrequencies) */
    int regime;              /* Regime */
    int contactState;        /* ContactState */
} DynOutputs;

/* Outputs for state s at rotor speed nRpm [rpm]. */
void dynOutputs(const DynModel *m, const DynState *s, double nRpm, DynOutputs *out);

/* m > 1 modes (docs/model.md s.2a): the linear part of dx/dt, y'' = M_y^-1 (G_y load - C_y y' -
 * (K_y + Omega^2 K_y2) y + e_1 F) with y = (x[0], q_2..q_m), y' = (x[1], q_2'..q_m') (x as above),
 * F the force on the tip; sets f[0], f[1], f[3] = y'^T C_y y' (viscous power) and the rates of the
 * extra coordinates (0 above m). Called by dynRhsExt (dynamics_step.h). */
void dynRhsModes(const DynModel *m, double load, double Omega, double F, const double x[], double f[]);

/* Contact-free natural frequencies [Hz] of modes 1..m at rotor speed nRpm (the generalized
 * eigenproblem K(Omega) x = w^2 M x; m = 1: naturalFrequency's formula), ascending; 0 above m. */
void dynModeFrequencies(const DynModel *m, double nRpm, double f[MODES_MAX]);

/* Name of the first output of o that is not finite (a force of a huge state times a huge
 * coefficient overflows), or NULL if all are finite. */
const char *dynNonFiniteOutput(const DynOutputs *o);

#endif
