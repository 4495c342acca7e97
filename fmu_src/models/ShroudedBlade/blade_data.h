/* The ShroudedBlade model's data (its part of the FMU state) and per-instance memory, shared by
 * model.c (variables, build, outputs, the step) and model_me.c (model exchange, which keeps its
 * own data: the co-simulation structs have no model-exchange field). */
#ifndef SHROUDED_BLADE_DATA_H
#define SHROUDED_BLADE_DATA_H

#include "fmi/instance.h"
#include "models/ShroudedBlade/variables.h"
#include "physics/dynamics.h"
#include "solver/blade_modes.h"
#include "solver/rk4_events.h"

/* The parameter slots par[] and ipar[] (RealParam, IntParam) and the value references are generated
 * from model.toml into variables.h. */

/* Everything of the model an FMU state captures. Plain data (no pointers). The last block is
 * derived from the rest (rebuilt after deserialization, not serialized). */
typedef struct {
    double par[PAR_NUM];         /* real parameters [units of the XML] */
    int32_t ipar[IPAR_NUM];      /* integer and Boolean parameters */
    double in[SOLVER_NUM_INPUTS][SOLVER_MAX_ORDER + 1]; /* input value and derivatives 1..8
                                                          [unit/s^j] at the communication point */
    int32_t warnedFullStick;     /* the full-stick warning was given in this run */
    DynState state;              /* continuous and discrete state */
    DynSens sens;                /* sensitivities to the start values and B (if sensitivities) */
    /* derived */
    BladeReduction blade;
    DynModel model;
    double curvature[MODES_MAX]; /* phi_i''(0) of the modes scaled to phi_i(l) = 1 [1/m^2] */
} BladeData;

/* Per-instance memory outside the FMU state. */
typedef struct {
    SolverCounters counters;     /* work statistics */
    /* the last Galerkin reduction and what it was built from: a master that resets and restarts
     * with the same blade (shooting) skips eq. 19-26 */
    BladeReductionCache reductionCache;
    DynOutputs out;              /* outputs of the current get call */
    BladeModesCache modesCache;  /* the last modal reduction (m > 1) */
    double frequencies[MODES_MAX]; /* modeFrequency at frequencySpeed [Hz] */
    double frequencySpeed;       /* [rpm] */
    int32_t frequencyValid;      /* 0: to be computed (after every build) */
    double jacobian[SENS_MODAL_ROWS][SENS_MODAL_COLS]; /* sensitivity[r,c] of the current get call */
    int32_t jacobianValid;       /* 0: jacobian not yet computed in this get call */
} BladeMemory;

#define BLADE_DATA(inst) ((BladeData *)(inst)->data)
#define BLADE_MEMORY(inst) ((BladeMemory *)(inst)->memory)

/* Warns once per run when the describing function is in full stick (docs/model.md s.3). */
FmiStatus bladeWarnFullStickOnce(FmiInstance *inst, const char *fn);

#endif
