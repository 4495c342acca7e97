/* Integrator of the one-mode blade with shroud contact (docs/model-notes.md s.1-s.3 and s.6).
 *
 * Classical RK4 with internal steps of equal size landing exactly on the end of the communication
 * step; switching functions (gate |q| = d, Jenkins contact open/close, stick/slip, period end
 * psi = 2 pi k, extremum q' = 0) are checked after every internal step, located on the step's
 * cubic Hermite interpolant, the step is redone up to the switching instant, the discrete state
 * is updated and the integration continues.
 * Pure C: no FMI types, no allocation, no logging (events are reported through an optional hook
 * that is NULL on the hot path). */
#ifndef SOLVER_H
#define SOLVER_H

#include <stdint.h>

#include "blade.h"
#include "contact.h"

#define SOLVER_MAX_ORDER 8          /* highest input derivative order (model-notes s.1) */
#define SOLVER_NUM_INPUTS 2
#define SOLVER_INPUT_AERO 0         /* aeroLoad f_w [N/m] */
#define SOLVER_INPUT_SPEED 1        /* rotorSpeed n [rpm] */
#define SOLVER_MAX_EVENTS_PER_STEP 1000 /* more is chattering (model-notes s.6) */

/* Number of continuous states (q, v, psi, E, w). */
#define SOLVER_NX 5

typedef enum {
    SolverOk = 0,
    SolverNonFinite = 1,      /* a state became NaN or infinite */
    SolverChattering = 2,     /* more than SOLVER_MAX_EVENTS_PER_STEP events in one internal step */
    SolverOmegaZero = 3,      /* omega <= 0 while a describing-function contact force is needed */
    SolverDescribeFailed = 4  /* contactDescribe refused the amplitude */
} SolverStatus;

/* Inputs inside a communication step: u(tau) = sum_j coef[j] tau^j, tau = t - t_k [s],
 * coef[j] = u^(j)(t_k) / j! (model-notes s.1). */
typedef struct {
    double coef[SOLVER_NUM_INPUTS][SOLVER_MAX_ORDER + 1]; /* [unit / s^j] */
    int top[SOLVER_NUM_INPUTS];                           /* highest j with coef != 0 (>= 0) */
} SolverInputs;

/* Constants of the right-hand side, precomputed once per run (after initialization). */
typedef struct {
    FrictionModel friction;   /* 1 macroslip DF, 2 Coulomb DF, 3 time-domain Jenkins element */
    Projection projection;    /* DF projection (MODEL.md s.3) */
    int gating;               /* 1: DF forces only while |q| > d (eq. 12-13) */
    int tracked;              /* 1: amplitudeMode 2 (model-notes s.3) */
    ContactParams contact;    /* kn, kdRatio, mu, gamma, d */
    /* blade, eq. 26 / MODEL.md s.2 */
    double invM;              /* 1/M, M the generalized mass [1/kg] */
    double C0;                /* generalized viscous damping [N s/m] */
    double K0static;          /* K0 at Omega = 0 [N/m] */
    double K0omega2;          /* dK0/d(Omega^2) [kg] */
    double G;                 /* load gain int phi / phi(l) [m] */
    double omegaPerRpm;       /* omega = engineOrder 2 pi n / 60: [rad/s per rpm] */
    double OmegaPerRpm;       /* Omega = 2 pi n / 60: [rad/s per rpm] */
    /* contact constants (eq. 3, 4, 14; model-notes s.2) */
    double d;                 /* gap [m] */
    double sinG, cosG;        /* sin(gamma), cos(gamma) [-] */
    double kd;                /* tangential stiffness kdRatio kn [N/m] */
    double knCos;             /* kn cos(gamma): F_n = knCos (q - sigma d) [N/m] */
    double muKnCos;           /* mu kn cos(gamma): L = muKnCos (sigma q - d) [N/m] */
    double muKnCosPerKd;      /* muKnCos / kd [-]: slip rate w' = (sin g - s sigma muKnCosPerKd) q' */
    int stickAtEntry;         /* 1 if kd tan(gamma) <= mu kn: contact starts in stick */
} SolverModel;

/* The integrator state: continuous states, discrete state and the describing-function cache.
 * Plain data (no pointers): a struct copy is a deep copy. */
typedef struct {
    double q;          /* contact coordinate [m] */
    double v;          /* dq/dt [m/s] */
    double psi;        /* excitation phase [rad] */
    double E;          /* dissipated energy [J] */
    double w;          /* Jenkins slider position in the Delta_u coordinate [m] */
    double B;          /* amplitude in use [m] (model-notes s.3) */
    double windowMax;  /* max |q| over the running excitation period [m] */
    double periods;    /* completed excitation periods [-] (an integer) */
    int32_t mode;      /* DF: 0 gate off, 1 gate on. Jenkins: ContactOpen, ContactStick, ContactSlip */
    int32_t side;      /* contact side sigma = +1 (q > d) or -1 (q < -d) */
    int32_t slipDir;   /* Jenkins slip direction s = sign(F_f), +1 or -1 */
    int32_t vdir;      /* sign of q' since the last extremum, +1 or -1 (tracking) */
    DescribingFunction df; /* describing function at B (derived: recomputed when B changes) */
} SolverState;

/* Event kinds reported to the hook. */
typedef enum {
    SolverEventGateOn = 1, SolverEventGateOff, SolverEventContact, SolverEventSeparate,
    SolverEventStickToSlip, SolverEventSlipToStick, SolverEventPeriodEnd, SolverEventExtremum
} SolverEventKind;

/* Optional event hook (for logging; NULL on the hot path). t is the absolute time [s]. */
typedef void (*SolverEventHook)(void *ctx, SolverEventKind kind, double t, const SolverState *s);

typedef struct {
    long long internalSteps; /* accepted internal steps (pieces between events count once) */
    long long events;        /* located events */
    long long rhsCalls;      /* right-hand-side evaluations */
} SolverCounters;

/* Builds the model constants. friction, projection, gating, tracked as the FMU parameters;
 * engineOrder >= 1. Returns 0 on success. */
int solverBuildModel(SolverModel *m, const BladeReduction *r, const ContactParams *cp,
                     FrictionModel friction, Projection projection, int gating, int tracked,
                     int engineOrder);

/* (Re)computes s->df for s->B (macroslip DF for the Jenkins element: outputs only). Returns
 * SolverOk or SolverDescribeFailed. */
SolverStatus solverUpdateDescribe(const SolverModel *m, SolverState *s);

/* Initial state at rest or at (q0 [m], v0 [m/s], E0 [J]) (model-notes s.7): psi = 0, B = B0 [m],
 * describing function at B0, windowMax = max(|q0|, windowMax0 [m]). Jenkins element (frictionModel
 * 3) in contact (|q0| > d): spring force F0 [N], w = q0 sin(gamma) - F0 / kd; stick if |F0| < L,
 * on the cone |F0| = L (relative 1e-12) slip in direction sign(F0) if the slip rate
 * (s kd sin g - sigma mu kn cos g) v0 >= 0, else stick. F0 = 0 is the unloaded spring (stick).
 * The caller checks F0 against the cone first (solverStartForceLimit). */
SolverStatus solverInitState(const SolverModel *m, SolverState *s, double q0, double v0, double E0,
                             double F0, double B0, double windowMax0);

/* Friction limit L = mu kn cos(gamma) (|q0| - d) [N] of the Jenkins element at q0 [m]; -1 if the
 * contact is open there (|q0| <= d). */
double solverStartForceLimit(const SolverModel *m, double q0);

/* Relative tolerance of |F0| = L at the start (rounding of a force read back from an output). */
#define SOLVER_CONE_RTOL 1e-12

/* Builds inputs from values and derivatives: deriv[i][j] = u_i^(j) (j = 0 value, 1..8). */
void solverSetInputs(SolverInputs *in, const double deriv[SOLVER_NUM_INPUTS][SOLVER_MAX_ORDER + 1]);

/* Input i at tau [s] (Horner). */
double solverInputAt(const SolverInputs *in, int i, double tau);

/* Advances *s over [0, h] (relative time tau; tStart = absolute time of tau = 0, used for the
 * event-time tolerance and the hook) in nSteps internal steps of size h / nSteps.
 * On failure *s holds a partially advanced state: the caller restores its copy. *tFail receives
 * the relative time reached (may be NULL). */
SolverStatus solverAdvance(const SolverModel *m, SolverState *s, const SolverInputs *in,
                           double tStart, double h, long nSteps, SolverEventHook hook, void *ctx,
                           SolverCounters *counters, double *tFail);

/* Output values (model-notes s.4). */
typedef struct {
    double normalForce;      /* [N] */
    double frictionForce;    /* [N] */
    double jenkinsForce;     /* Jenkins spring force kd (sin g q - w) in contact, else 0 [N] */
    double Keq;              /* [N/m] */
    double Ceq;              /* [N s/m] */
    double naturalFrequency; /* [Hz] */
    int regime;              /* Regime */
    int contactState;        /* ContactState */
} SolverOutputs;

/* Outputs for state s at rotor speed nRpm [rpm]. */
void solverOutputs(const SolverModel *m, const SolverState *s, double nRpm, SolverOutputs *out);

/* Name of the first output of o that is not finite (a force of a huge state times a huge
 * coefficient overflows), or NULL if all are finite. */
const char *solverNonFiniteOutput(const SolverOutputs *o);

#endif
