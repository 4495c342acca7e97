/* The communication step of a blade FMU (ShroudedBlade, BladeExternalContact; model-notes s.1,
 * s.6, s.7) over the integrator of rk4_events.h: the internal step count from maxStep, the input
 * polynomials, the rotor speed range, solverAdvance with the events logged, the state restored
 * and the step discarded on numerical trouble, and the inputs carried to the next point. A
 * model fills a BladeStep from its data and calls bladeStep from its FmiModel.doStep. */
#ifndef BLADE_STEP_H
#define BLADE_STEP_H

#include "fmi/instance.h"
#include "solver/rk4_events.h"

#define BLADE_STEP_MAX_FORCES 2 /* external force inputs summed into the force on q */

typedef struct {
    const DynModel *model;
    DynState *state;
    DynSens *sens;               /* NULL: no sensitivities (the hot path) */
    /* the inputs' values and derivatives [unit/s^j] at the communication point, carried to the
     * next one: aeroLoad, rotorSpeed (SOLVER_INPUT_AERO, _SPEED), then nForces force inputs [N] */
    double (*in)[SOLVER_MAX_ORDER + 1];
    int nForces;                 /* 0 .. BLADE_STEP_MAX_FORCES */
    double maxStep;              /* [s] */
    double speedMax;             /* rotorSpeed must stay in [0, speedMax] rpm (model-notes s.1) */
    const char *instabilityHint; /* what else to try when the state overflows (NULL: nothing) */
    SolverCounters *counters;
} BladeStep;

/* The step from tc to tc + h (after the layer's checks): FmiOK, or FmiDiscard / FmiError (logged)
 * with the state and the inputs as at tc. */
FmiStatus bladeStep(FmiInstance *inst, const char *fn, const BladeStep *b, double tc, double h);

/* The logEvents message of an event (ctx: the FmiInstance); also the model-exchange event log. */
void bladeLogEvent(void *ctx, DynEventKind kind, double t, const DynState *s);

#endif
