/* ShroudedBlade FMU instance: all state of one instance (no globals) and what the FMI 2.0 entry
 * points (fmi2_api.c) call after checking call sequence and pointers. Implemented in instance.c
 * (lifecycle, initialization, the communication step), variables.c (start values, validation,
 * get/set), fmu_state.c (FMU state copies, serialization) and logging.c. */
#ifndef INSTANCE_H
#define INSTANCE_H

#include <stddef.h>
#include <stdint.h>

#include "fmi2Functions.h"
#include "solver.h"

/* States of the FMI 2.0 co-simulation state machine (one bit each, for allowed-state masks). */
typedef enum {
    FsmStartEnd = 1 << 0,
    FsmInstantiated = 1 << 1,
    FsmInitializationMode = 1 << 2,
    FsmStepComplete = 1 << 3,
    FsmStepInProgress = 1 << 4,
    FsmStepFailed = 1 << 5,
    FsmStepCanceled = 1 << 6,
    FsmTerminated = 1 << 7,
    FsmError = 1 << 8,
    FsmFatal = 1 << 9
} FsmState;

const char *fsmStateName(int32_t state);

/* Log categories (modelDescription.xml <LogCategories>, same order). */
typedef enum {
    LogEvents = 0, LogStatusWarning, LogStatusDiscard, LogStatusError, LogStatusFatal, LogAll,
    LogCalls, LOG_NUM_CATEGORIES
} LogCategory;

const char *logCategoryName(int category);

/* Real parameter slots (units as in modelDescription.xml) */
typedef enum {
    ParEI = 0, ParRho, ParA, ParL, ParC, ParM0, ParKn, ParKdRatio, ParMu, ParGamma, ParD, ParB,
    ParMaxStep,
    ParQ0, ParV0, ParE0, /* start values of the initial="exact" outputs q [m], q' [m/s], E [J] */
    ParF0,               /* start value of jenkinsForce: Jenkins spring force k_d (Delta_u - w) [N] */
    ParWindowMax0,       /* start value of runningMaximum: max |q| over the running period [m] */
    PAR_NUM
} RealParam;

typedef enum {
    IparFrictionModel = 0, IparFormulation, IparProjection, IparAmplitudeMode, IparEngineOrder,
    IparGating, IPAR_NUM
} IntParam;

/* Everything an FMU state captures. Plain data (no pointers). The last block is derived from
 * the rest (rebuilt after deserialization, not serialized). */
typedef struct {
    int32_t fsm;                 /* FsmState */
    double par[PAR_NUM];         /* real parameters [units of the XML] */
    int32_t ipar[IPAR_NUM];      /* integer and Boolean parameters */
    double in[SOLVER_NUM_INPUTS][SOLVER_MAX_ORDER + 1]; /* input value and derivatives 1..8
                                                          [unit/s^j] at time */
    double time;                 /* current communication point [s] */
    double startTime;            /* [s] */
    double stopTime;             /* [s], if stopTimeDefined */
    int32_t stopTimeDefined;
    int32_t lastDoStepStatus;    /* fmi2Status of the last fmi2DoStep */
    int32_t warnedFullStick;     /* the full-stick warning was given in this run */
    SolverState solver;          /* continuous and discrete state */
    /* derived */
    int32_t modelValid;          /* blade and model are built from par/ipar */
    BladeReduction blade;
    SolverModel model;
} InstanceData;

typedef struct StateBlob StateBlob;

typedef struct {
    uint64_t magic;
    InstanceData d;
    char *instanceName;
    char *resourceLocation;
    fmi2CallbackLogger logger;
    fmi2ComponentEnvironment componentEnvironment;
    int logOn[LOG_NUM_CATEGORIES];      /* enabled categories */
    StateBlob *states;                  /* FMU states allocated for this instance (freed with it) */
    SolverCounters counters;            /* work statistics (not part of the FMU state) */
    /* the last Galerkin reduction and what it was built from (not part of the FMU state): a
     * master that resets and restarts with the same blade (shooting) skips eq. 19-26 */
    int32_t bladeCacheValid;
    int32_t bladeCacheFormulation;
    BladeParams bladeCacheParams;
    BladeReduction bladeCache;
    char message[1024];                 /* formatting buffer of the logger */
    char escaped[2100];
} Instance;

#define INSTANCE_MAGIC 0x53426c6164654931ULL /* "SBladeI1" */

/* Lifecycle. instanceNew copies the strings; NULL on allocation failure. */
Instance *instanceNew(const char *instanceName, const char *resourceLocation,
                      fmi2CallbackLogger logger, fmi2ComponentEnvironment env, int loggingOn);
void instanceFree(Instance *inst);
void instanceReset(Instance *inst); /* start values, solver memory, time 0; keeps logging */

/* Logging (logging.c): only enabled categories reach the logger (logAll enables all). */
int instanceLogEnabled(const Instance *inst, int category);
#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
void instanceLog(Instance *inst, fmi2Status status, int category, const char *fmt, ...);
/* Logs with the category of the status (logStatusWarning/Discard/Error/Fatal). */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
void instanceLogStatus(Instance *inst, fmi2Status status, const char *fmt, ...);

/* Variable access (variables.c; arrays; fn names the FMI function for messages). Set* is atomic:
 * either all values are valid and applied, or nothing changes. */
fmi2Status instanceGetReal(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[]);
fmi2Status instanceGetInteger(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[]);
fmi2Status instanceGetBoolean(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[]);
fmi2Status instanceSetReal(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[]);
fmi2Status instanceSetInteger(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[]);
fmi2Status instanceSetBoolean(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[]);
fmi2Status instanceSetInputDerivatives(Instance *inst, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]);
/* Name of vr for messages, or NULL if unknown. */
const char *instanceVariableName(fmi2ValueReference vr);

/* Experiment and initialization. */
fmi2Status instanceSetupExperiment(Instance *inst, int toleranceDefined, double tolerance,
                                   double startTime, int stopTimeDefined, double stopTime);
fmi2Status instanceExitInitialization(Instance *inst);

/* The communication step (model-notes s.1, s.6). fmi2Discard: state restored to the step start. */
fmi2Status instanceDoStep(Instance *inst, double currentCommunicationPoint, double h);

/* FMU states (fmu_state.c). */
fmi2Status instanceGetState(Instance *inst, fmi2FMUstate *state);
fmi2Status instanceSetState(Instance *inst, fmi2FMUstate state);
fmi2Status instanceFreeState(Instance *inst, fmi2FMUstate *state);
fmi2Status instanceSerializedSize(Instance *inst, fmi2FMUstate state, size_t *size);
fmi2Status instanceSerialize(Instance *inst, fmi2FMUstate state, fmi2Byte buffer[], size_t size);
fmi2Status instanceDeserialize(Instance *inst, const fmi2Byte buffer[], size_t size, fmi2FMUstate *state);

#endif
