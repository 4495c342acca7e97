/* The co-simulation integrator over physics/dynamics.h (docs/model-notes.md s.1, s.6).
 *
 * Classical RK4 with internal steps of equal size landing exactly on the end of the communication
 * step; the switching functions of dynSwitching are checked after every internal step, located on
 * the step's cubic Hermite interpolant, the step is redone up to the switching instant,
 * dynApplyEvent updates the discrete state and the integration continues. Inputs inside a step
 * are Taylor polynomials of the values and derivatives the master gave.
 * Pure C: no FMI types, no allocation, no logging (events are reported through an optional hook
 * that is NULL on the hot path). */
#ifndef RK4_EVENTS_H
#define RK4_EVENTS_H

#include "physics/dynamics_step.h"
#include "physics/variational.h"

#define SOLVER_MAX_ORDER 8          /* highest input derivative order (model-notes s.1) */
#define SOLVER_NUM_INPUTS 2          /* the blade's inputs (ShroudedBlade) */
#define SOLVER_INPUT_AERO 0         /* aeroLoad f_w [N/m] */
#define SOLVER_INPUT_SPEED 1        /* rotorSpeed n [rpm] */
#define SOLVER_INPUT_FORCE 2        /* external force on q [N] (BladeExternalContact; 0 by default) */
#define SOLVER_NUM_POLY 3           /* input polynomials of a step: the blade's inputs + the force */
#define SOLVER_NX (DYN_NX_MAX + 1)  /* integrated: DynState's x (all modes) plus W, the work of the force [J] */
#define SOLVER_W DYN_NX_MAX          /* index of W in the integrated state */
#define SOLVER_MAX_EVENTS_PER_STEP 1000 /* more is chattering (model-notes s.6) */

/* Inputs inside a communication step: u(tau) = sum_j coef[j] tau^j, tau = t - t_k [s],
 * coef[j] = u^(j)(t_k) / j! (model-notes s.1). */
typedef struct {
    double coef[SOLVER_NUM_POLY][SOLVER_MAX_ORDER + 1]; /* [unit / s^j] */
    int top[SOLVER_NUM_POLY];                           /* highest j with coef != 0 (>= 0) */
} SolverInputs;

/* Optional event hook (for logging; NULL on the hot path). t is the absolute time [s]. */
typedef void (*SolverEventHook)(void *ctx, DynEventKind kind, double t, const DynState *s);

typedef struct {
    long long internalSteps; /* accepted internal steps (pieces between events count once) */
    long long events;        /* located events */
    long long rhsCalls;      /* right-hand-side evaluations */
} SolverCounters;

/* Builds inputs from values and derivatives: deriv[i][j] = u_i^(j) (j = 0 value, 1..8); the
 * external force is 0. */
void solverSetInputs(SolverInputs *in, const double deriv[SOLVER_NUM_INPUTS][SOLVER_MAX_ORDER + 1]);

/* Sets the external force on q [N] from its value and derivatives deriv[j] = F^(j) (after
 * solverSetInputs). Its work W' = F q' is integrated into DynState.W. */
void solverSetForce(SolverInputs *in, const double deriv[SOLVER_MAX_ORDER + 1]);

/* Input polynomial i (SOLVER_INPUT_*) at tau [s] (Horner). */
double solverInputAt(const SolverInputs *in, int i, double tau);

/* Input polynomial i re-expanded at tau = h as values and derivatives out[j] = u^(j)(h) (out[0]
 * exactly solverInputAt(in, i, h)): an input the master does not set again continues as the same
 * polynomial (model-notes s.7). */
void solverShiftInput(const SolverInputs *in, int i, double h, double out[SOLVER_MAX_ORDER + 1]);

/* Advances *s over [0, h] (relative time tau; tStart = absolute time of tau = 0, used for the
 * event-time tolerance and the hook) in nSteps internal steps of size h / nSteps.
 * On failure *s holds a partially advanced state: the caller restores its copy. *tFail receives
 * the relative time reached (may be NULL). sens (may be NULL: the hot path) is advanced with the
 * state: the variational equations and their jumps at the events (physics/variational.h). */
DynStatus solverAdvance(const DynModel *m, DynState *s, const SolverInputs *in, double tStart, double h,
                        long nSteps, SolverEventHook hook, void *ctx, SolverCounters *counters, double *tFail,
                        DynSens *sens);

#endif
