/* What a model gives the generic FMI layer: its identity, variable table, the size of its data,
 * its serialized field list and the few functions only the model knows (build, step, outputs).
 * The layer calls these; a model calls the layer's logging and instance functions, never a face.
 * Its model-exchange part is a separate table (FmiModelExchange) in its own file, reached only
 * through the FMI 2.0 face: a co-simulation binary links none of it. */
#ifndef FMI_MODEL_H
#define FMI_MODEL_H

#include "fmi/fmi_types.h"

struct FmiInstance;

/* Model exchange (FMI 2.0 ME): what a model adds so that a master's integrator advances its
 * continuous states. Time is inst->run.time; inputs are their current values. An instance for
 * model exchange has inst->me and its own data and memory (inst->meData, inst->meMemory). */
typedef struct FmiModelExchange {
    int nx;                    /* continuous states (numberOfContinuousStates) */
    int nz;                    /* event indicators (numberOfEventIndicators) */
    size_t dataSize;           /* bytes of the model-exchange part of the FMU state: copied with an
                                  in-memory FMU state, not serialized (zero in a deserialized one) */
    size_t memorySize;         /* bytes of per-instance memory outside the FMU state (zeroed once) */
    void (*getStates)(const struct FmiInstance *inst, double x[]);
    void (*setStates)(struct FmiInstance *inst, const double x[]);
    void (*nominals)(const struct FmiInstance *inst, double x[]);
    /* dx/dt; FmiDiscard (logged) if the right-hand side is not defined at this state */
    FmiStatus (*derivatives)(struct FmiInstance *inst, const char *fn, double dx[]);
    /* FmiDiscard (logged) if an indicator is not finite at this state */
    FmiStatus (*eventIndicators)(struct FmiInstance *inst, const char *fn, double z[]);
    /* The discrete update at an event, iterated to the end; *statesChanged = 1 if the continuous
     * states changed. FmiError (logged) if it cannot be done. */
    FmiStatus (*eventUpdate)(struct FmiInstance *inst, const char *fn, int *statesChanged);
    /* After every successful FmiModel.build (same arguments): the model-exchange data that follow
     * the model's, and the checks of parameters that model exchange refuses (FmiError, logged). */
    FmiStatus (*built)(struct FmiInstance *inst, const char *fn, int initState);
    /* After FmiModel.outputs: the outputs that model exchange computes otherwise (e.g. a discrete
     * output held between events). */
    void (*outputs)(struct FmiInstance *inst);
} FmiModelExchange;

typedef struct FmiModel {
    const char *name;          /* model name for messages */
    const char *guid;          /* must equal the modelDescription.xml guid */
    const VarInfo *vars;       /* sorted by value reference (bisected) */
    int nVars;
    int maxInputOrder;         /* highest input derivative order (0: none) */
    size_t dataSize;           /* bytes of the model's part of the FMU state (plain data) */
    size_t memorySize;         /* bytes of per-instance memory outside the FMU state */
    int canGetAndSetState;     /* 0: the FMU state functions are refused (as the XML says) */
    int32_t stateVersion;      /* serialized format version: bump when `fields` changes */
    const StateField *fields;  /* serialized part of the data, in blob order */
    int nFields;

    /* After the table's start values are written (data zeroed before): the rest of the data. */
    void (*startValues)(struct FmiInstance *inst);
    /* Derived data from the parameters; initState: also the initial state (end of
     * initialization). Logs and returns FmiError if the parameters cannot be used. */
    FmiStatus (*build)(struct FmiInstance *inst, const char *fn, int initState);
    /* Called once after a successful build at the end of initialization (may be NULL). */
    FmiStatus (*initialized)(struct FmiInstance *inst, const char *fn);
    /* Evaluates the calculated outputs (into the model's memory) for `output` below. */
    void (*outputs)(struct FmiInstance *inst);
    double (*output)(const struct FmiInstance *inst, int id);
    /* Appends why a calculated output may be non-finite to a warning (may be NULL). */
    void (*nonFiniteHint)(const struct FmiInstance *inst, char *buf, size_t n);
    /* The model's part of a communication step from tc to tc + h, after the layer checked the
     * arguments and the time. FmiDiscard: the model's state is as at tc. */
    FmiStatus (*doStep)(struct FmiInstance *inst, const char *fn, double tc, double h);
    /* Checks the model-specific fields of deserialized data (1: usable); the table's variables
     * were checked already. initialized: the state evolves (else only parameters matter). */
    int (*validData)(struct FmiInstance *inst, const char *fn, const void *data, int initialized);
} FmiModel;

/* The one model a binary is built from: defined by the model folder (models/<Name>/) linked in. */
extern const FmiModel fmiModel;
/* Its model-exchange part, read by the FMI 2.0 face only (fmi2_cs.c, fmi2_me.c; never by the FMI 3.0
 * co-simulation face): defined by the model's model-exchange file, or as NULL next to fmiModel by a
 * co-simulation-only model (fmi2Instantiate then refuses fmi2ModelExchange). */
extern const FmiModelExchange *const fmiModelExchange;

#endif
