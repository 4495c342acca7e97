/* The generic FMU instance: lifecycle, the co-simulation state machine, experiment setup and the
 * checks of a communication step that every model shares. The model's data and memory hang off
 * the instance (sizes from the FmiModel); nothing here knows a model's variables. */
#ifndef FMI_INSTANCE_H
#define FMI_INSTANCE_H

#include "fmi/fsm.h"
#include "fmi/model.h"

/* Log categories (modelDescription.xml <LogCategories>, same order). */
typedef enum {
    LogEvents = 0, LogStatusWarning, LogStatusDiscard, LogStatusError, LogStatusFatal, LogAll,
    LogCalls, LOG_NUM_CATEGORIES
} LogCategory;

/* The face's logger: receives finished messages (no format characters left to expand). */
typedef void (*FmiLogSink)(void *ctx, const char *instanceName, FmiStatus status, const char *category,
                           const char *message);

/* What the layer's messages need from the face serving an instance: the face's names of the
 * functions a message points to, of the variable types (indexed by VarType) and of the states. */
typedef struct {
    const char *exitInitializationMode;   /* e.g. "fmi2ExitInitializationMode" */
    const char *serializedStateSize;      /* e.g. "fmi2SerializedFMUstateSize" */
    const char *typeNames[3];             /* VarReal, VarInteger, VarBoolean: "Real", ... */
    const char *(*stateName)(int32_t state);
    int declaresLocals;                   /* 0: the face's model description has none of the model's
                                             model-exchange locals (FMI 3.0 CS; VarInfo.meOnly):
                                             their value references are unknown there */
} FmiFace;

/* The generic part of an FMU state. */
typedef struct {
    double time;               /* current communication point [s] */
    double startTime;          /* [s] */
    double stopTime;           /* [s], if stopTimeDefined */
    int32_t stopTimeDefined;
    int32_t lastDoStepStatus;  /* FmiStatus of the last step */
    int32_t initialized;       /* 1 once initialization ended: the model's state evolves */
} FmiRun;

typedef struct FmiStateCopy FmiStateCopy;

typedef struct FmiInstance {
    uint64_t magic;
    const FmiModel *model;
    const FmiFace *face;       /* names for messages (static storage of the face) */
    int32_t fsm;               /* FsmState */
    const FmiModelExchange *me; /* instantiated for model exchange with this table; NULL: co-simulation */
    FmiRun run;
    int32_t built;             /* the model's derived data follow its parameters */
    void *data;                /* model->dataSize bytes: the model's part of the FMU state */
    void *memory;              /* model->memorySize bytes: per-instance memory, not state */
    void *meData;              /* me->dataSize bytes (model exchange): its part of the FMU state */
    void *meMemory;            /* me->memorySize bytes (model exchange): per-instance memory */
    char *instanceName;
    char *resourceLocation;
    FmiLogSink sink;
    void *sinkCtx;             /* owned: freed with the instance */
    int logOn[LOG_NUM_CATEGORIES];
    FmiStateCopy *states;      /* FMU states allocated for this instance (freed with it) */
    char message[1024];        /* formatting buffer of the logger */
} FmiInstance;

#define FMI_INSTANCE_MAGIC 0x53426c6164654932ULL /* "SBladeI2" */

/* Copies the strings; takes sinkCtx (freed with the instance, also on failure). sink may be NULL
 * (nothing is logged). me: the model-exchange table for a model-exchange instance, else NULL.
 * NULL on allocation failure. */
FmiInstance *fmiNew(const FmiModel *model, const FmiModelExchange *me, const FmiFace *face,
                    const char *instanceName, const char *resourceLocation, FmiLogSink sink, void *sinkCtx,
                    int loggingOn);
void fmiFree(FmiInstance *inst);
void fmiReset(FmiInstance *inst); /* start values, time 0, state machine instantiated; keeps logging */

/* The instance behind a face's handle, if it is one and the call is allowed in its state (a mask of
 * FsmState bits); else NULL, with "<fn>: Illegal call sequence (state: <the face's state name>)"
 * logged when the handle is an instance. logCall: log the call (category logCalls) first. */
FmiInstance *fmiEnter(void *handle, const char *fn, int mask, int logCall);


FmiStatus fmiSetupExperiment(FmiInstance *inst, const char *fn, int toleranceDefined, double tolerance,
                             double startTime, int stopTimeDefined, double stopTime);
FmiStatus fmiExitInitialization(FmiInstance *inst, const char *fn);
/* Checks the communication point, the step size and the stop time, then lets the model step. */
FmiStatus fmiDoStep(FmiInstance *inst, const char *fn, double tc, double h);

/* Tolerance of a time comparison at time t [s]: 1e-9 max(1, |t|). */
double fmiTimeTolerance(double t);

#endif
