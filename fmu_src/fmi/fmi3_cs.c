/* The FMI 3.0 co-simulation face: the fmi3* entry points over the generic layer. Here and only
 * here fmi3 types meet the neutral ones: the call-sequence state machine of FMI 3.0 co-simulation
 * (one allowed-states mask per function), pointer and argument checks, type conversion, the
 * logMessage callback. Every FMI 3.0 function is exported; those of model exchange, scheduled
 * execution, event mode, clocks, configuration mode and the types this FMU has no variables of log
 * and return fmi3Error. The model is the one linked in (fmiModel).
 *
 * States of the generic layer as FMI 3.0 co-simulation states: FsmInstantiated = Instantiated,
 * FsmInitializationMode = Initialization Mode, FsmStepComplete = Step Mode (hasEventMode =
 * "false": fmi3ExitInitializationMode enters it directly), FsmTerminated = Terminated, FsmError =
 * the state after a step or the end of initialization returned fmi3Error (left by fmi3Reset or
 * fmi3SetFMUState). A step that returns fmi3Discard restores the state at its start
 * (lastSuccessfulTime = currentCommunicationPoint) and stays in Step Mode: the importer may retry
 * with a smaller step, restore a state or terminate. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "fmi/instance.h"
#include "fmi/log.h"
#include "fmi/state_blob.h"
#include "fmi/variables.h"

/* The face's logger context: the importer's callback. FMI 3.0's message is plain text (no
 * format), and the callback has no instance name argument. */
typedef struct {
    fmi3LogMessageCallback logMessage;
    fmi3InstanceEnvironment env;
} Fmi3Sink;

static void fmi3Sink(void *ctx, const char *instanceName, FmiStatus status, const char *category,
                     const char *message)
{
    Fmi3Sink *k = (Fmi3Sink *)ctx;
    (void)instanceName;
    k->logMessage(k->env, (fmi3Status)status, category, message);
}

static const char *fmi3StateName(int32_t state)
{
    switch (state) {
    case FsmInstantiated: return "Instantiated";
    case FsmInitializationMode: return "Initialization Mode";
    case FsmStepComplete: return "Step Mode";
    case FsmTerminated: return "Terminated";
    case FsmError: return "error (after fmi3Error)";
    default: return fsmStateName(state);
    }
}

/* The names the generic layer's messages use. */
static const FmiFace FMI3_FACE = {"fmi3ExitInitializationMode", "fmi3SerializedFMUStateSize",
                                  {"Float64", "Int32", "Boolean"}, fmi3StateName, 0};

/* Allowed states per function (FMI 3.0 s.4.3 and the common states of s.3.1; only the states this
 * FMU can be in). */
#define ALL_STATES (FsmInstantiated | FsmInitializationMode | FsmStepComplete | FsmTerminated | FsmError)
#define MASK_SetDebugLogging ALL_STATES
#define MASK_EnterInitializationMode FsmInstantiated
#define MASK_ExitInitializationMode FsmInitializationMode
#define MASK_Terminate FsmStepComplete
#define MASK_Reset ALL_STATES
#define MASK_Get (FsmInitializationMode | FsmStepComplete | FsmTerminated | FsmError)
#define MASK_Set (FsmInstantiated | FsmInitializationMode | FsmStepComplete)
#define MASK_FMUState ALL_STATES
#define MASK_GetOutputDerivatives (FsmStepComplete | FsmTerminated | FsmError)
#define MASK_DoStep FsmStepComplete
#define MASK_Unsupported ALL_STATES

static FmiInstance *enter(fmi3Instance instance, const char *fn, int mask) { return fmiEnter(instance, fn, mask, 1); }

/* enter() for a function with a required pointer argument: ok = 0 logs "<fn>: <what> is NULL". */
static FmiInstance *enterNonNull(fmi3Instance instance, const char *fn, int mask, int ok, const char *what)
{
    FmiInstance *inst = enter(instance, fn, mask);
    if (inst != NULL && !ok) {
        fmiLogStatus(inst, FmiError, "%s: %s is NULL", fn, what);
        return NULL;
    }
    return inst;
}

/* enterNonNull() for the FMU state functions, refused when the model cannot get and set its state. */
static FmiInstance *enterState(fmi3Instance instance, const char *fn, int ok, const char *what)
{
    FmiInstance *inst = enterNonNull(instance, fn, MASK_FMUState, ok, what);
    if (inst != NULL && !inst->model->canGetAndSetState) {
        fmiLogStatus(inst, FmiError, "%s: not supported (canGetAndSetFMUState = false)", fn);
        return NULL;
    }
    return inst;
}

/* A function this FMU does not provide: logs why (if the instance is valid) and returns fmi3Error. */
static fmi3Status unsupported(fmi3Instance instance, const char *fn, const char *why)
{
    FmiInstance *inst = enter(instance, fn, MASK_Unsupported);
    if (inst == NULL) return fmi3Error;
    fmiLogStatus(inst, FmiError, "%s: not supported: %s", fn, why);
    return fmi3Error;
}

#define NO_MODEL_EXCHANGE "this FMU is a co-simulation FMU (no <ModelExchange>)"
#define NO_EVENT_MODE "hasEventMode = false (instantiate with eventModeUsed = false)"
#define NO_CLOCKS "this FMU has no clocks"
#define NO_CONFIGURATION "this FMU has no structural parameters (no Configuration Mode)"

/* fmi3 arrays seen element-wise as doubles by the generic engine */
static double readFloat64(const void *v, size_t i) { return ((const fmi3Float64 *)v)[i]; }
static void writeFloat64(void *v, size_t i, double x) { ((fmi3Float64 *)v)[i] = x; }
static double readInt32(const void *v, size_t i) { return (double)((const fmi3Int32 *)v)[i]; }
static void writeInt32(void *v, size_t i, double x) { ((fmi3Int32 *)v)[i] = (fmi3Int32)x; }
static double readBoolean(const void *v, size_t i) { return ((const fmi3Boolean *)v)[i] ? 1.0 : 0.0; }
static void writeBoolean(void *v, size_t i, double x) { ((fmi3Boolean *)v)[i] = x != 0.0 ? fmi3True : fmi3False; }
static double readDouble(const void *v, size_t i) { return ((const double *)v)[i]; }
static void writeDouble(void *v, size_t i, double x) { ((double *)v)[i] = x; }
static const FmiArray FLOAT64S = {VarReal, readFloat64, writeFloat64};
static const FmiArray INT32S = {VarInteger, readInt32, writeInt32};
static const FmiArray BOOLEANS = {VarBoolean, readBoolean, writeBoolean};

#define VRS(vr) ((const FmiValueRef *)(vr))

/* The argument checks of every get/set: arrays present, and (all variables are scalars)
 * nValues = nValueReferences. Logs and returns 1 if they fail. */
static int badArrays(FmiInstance *inst, const char *fn, size_t nvr, const void *vr, const void *values,
                     size_t nValues)
{
    if (nvr > 0 && (vr == NULL || values == NULL)) {
        fmiLogStatus(inst, FmiError, "%s: NULL array argument with nValueReferences = %lu", fn, (unsigned long)nvr);
        return 1;
    }
    if (nValues != nvr) {
        fmiLogStatus(inst, FmiError, "%s: nValues = %lu must equal nValueReferences = %lu (every variable of this "
                     "FMU is a scalar)", fn, (unsigned long)nValues, (unsigned long)nvr);
        return 1;
    }
    return 0;
}

/* FMI 3.0 requires an independent variable: value reference TIME_VR is the FMU's time, read here
 * (a model's table must leave it free: checked at instantiation). */
#define TIME_VR 0u

static int hasTime(const fmi3ValueReference vr[], size_t nvr)
{
    for (size_t i = 0; i < nvr; ++i)
        if (vr[i] == TIME_VR) return 1;
    return 0;
}

static fmi3Status getValues(fmi3Instance instance, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                            const FmiArray *a, void *values, size_t nValues)
{
    FmiInstance *inst = enter(instance, fn, MASK_Get);
    FmiStatus status = FmiOK;
    if (inst == NULL || badArrays(inst, fn, nvr, vr, values, nValues)) return fmi3Error;
    if (!hasTime(vr, nvr)) return (fmi3Status)fmiGetValues(inst, fn, VRS(vr), nvr, a, values);
    /* element-wise around the time, each other value through a double of the same type */
    for (size_t i = 0; i < nvr; ++i) {
        FmiStatus s = FmiOK;
        double x = 0.0;
        if (vr[i] != TIME_VR) {
            const FmiArray one = {a->type, readDouble, writeDouble};
            s = fmiGetValues(inst, fn, VRS(vr) + i, 1, &one, &x);
        } else if (a->type == VarReal) {
            x = inst->run.time;
        } else {
            fmiLogStatus(inst, FmiError, "%s: time (vr %u) is of type Float64, not %s", fn, TIME_VR,
                         FMI3_FACE.typeNames[a->type]);
            s = FmiError;
        }
        a->write(values, i, x);
        if (s > status) status = s;
    }
    return (fmi3Status)status;
}

static fmi3Status setValues(fmi3Instance instance, const char *fn, const fmi3ValueReference vr[], size_t nvr,
                            const FmiArray *a, const void *values, size_t nValues)
{
    FmiInstance *inst = enter(instance, fn, MASK_Set);
    if (inst == NULL || badArrays(inst, fn, nvr, vr, values, nValues)) return fmi3Error;
    if (hasTime(vr, nvr)) {
        fmiLogStatus(inst, FmiError, "%s: time (vr %u) is the independent variable and cannot be set", fn, TIME_VR);
        return fmi3Error;
    }
    return (fmi3Status)fmiSetValues(inst, fn, VRS(vr), nvr, a, values);
}

/* A type this FMU has no variables of: every value reference is refused (none: fmi3OK). */
static fmi3Status noVariables(fmi3Instance instance, const char *fn, int mask, const fmi3ValueReference vr[],
                              size_t nvr, const void *values, const char *type)
{
    FmiInstance *inst = enter(instance, fn, mask);
    const VarInfo *v;
    if (inst == NULL) return fmi3Error;
    if (nvr == 0) return fmi3OK;
    if (vr == NULL || values == NULL) {
        fmiLogStatus(inst, FmiError, "%s: NULL array argument with nValueReferences = %lu", fn, (unsigned long)nvr);
        return fmi3Error;
    }
    v = fmiFaceVar(inst, vr[0]);
    if (v != NULL)
        fmiLogStatus(inst, FmiError, "%s: %s (vr %u) is of type %s, not %s", fn, v->name, (unsigned)vr[0],
                     FMI3_FACE.typeNames[v->type], type);
    else
        fmiLogStatus(inst, FmiError, "%s: unknown value reference %u (this FMU has no %s variables)", fn,
                     (unsigned)vr[0], type);
    return fmi3Error;
}

/* ------------------------------------------------------------------------------------------- */
/* Common functions                                                                             */

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    const char *fn = "fmi3SetDebugLogging";
    FmiInstance *inst = fmiEnter(instance, fn, MASK_SetDebugLogging, 0); /* logs the call after the change */
    if (inst == NULL) return fmi3Error;
    if (fmiSetDebugLogging(inst, fn, loggingOn ? 1 : 0, nCategories, categories) != FmiOK) return fmi3Error;
    fmiLog(inst, FmiOK, LogCalls, "%s (state: %s)", fn, fmi3StateName(inst->fsm));
    return fmi3OK;
}

/* Logs a refused instantiation to the importer's callback, if it gave one (errors are reported
 * whatever loggingOn says). */
static void instantiateFailed(fmi3LogMessageCallback logMessage, fmi3InstanceEnvironment env,
                              fmi3Status status, const char *message)
{
    if (logMessage != NULL)
        logMessage(env, status, status == fmi3Fatal ? "logStatusFatal" : "logStatusError", message);
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment,
                                         fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate)
{
    char text[400];
    FmiInstance *inst;
    Fmi3Sink *sink = NULL;
    /* visible: no user interface; earlyReturnAllowed: steps never return early; intermediateUpdate:
     * never called (providesIntermediateUpdate = false) */
    (void)visible; (void)earlyReturnAllowed; (void)requiredIntermediateVariables; (void)intermediateUpdate;
    if (instanceName == NULL || instanceName[0] == '\0') {
        instantiateFailed(logMessage, instanceEnvironment, fmi3Error,
                          "fmi3InstantiateCoSimulation: instanceName must be a non-empty string");
        return NULL;
    }
    if (instantiationToken == NULL || strcmp(instantiationToken, fmiModel.guid) != 0) {
        snprintf(text, sizeof text, "fmi3InstantiateCoSimulation: instantiationToken %s does not match the token "
                 "%s of this FMU binary", instantiationToken ? instantiationToken : "(NULL)", fmiModel.guid);
        instantiateFailed(logMessage, instanceEnvironment, fmi3Error, text);
        return NULL;
    }
    if (fmiFindVar(&fmiModel, TIME_VR) != NULL) { /* a build defect, not the importer's */
        instantiateFailed(logMessage, instanceEnvironment, fmi3Fatal,
                          "fmi3InstantiateCoSimulation: the model uses value reference 0, which the FMI 3.0 face "
                          "reserves for the independent variable time");
        return NULL;
    }
    if (eventModeUsed) {
        instantiateFailed(logMessage, instanceEnvironment, fmi3Error,
                          "fmi3InstantiateCoSimulation: eventModeUsed = true is not supported: this FMU has "
                          "hasEventMode = false (no events to handle)");
        return NULL;
    }
    if (nRequiredIntermediateVariables > 0) {
        instantiateFailed(logMessage, instanceEnvironment, fmi3Error,
                          "fmi3InstantiateCoSimulation: requiredIntermediateVariables given, but this FMU has "
                          "providesIntermediateUpdate = false");
        return NULL;
    }
    if (logMessage != NULL) {
        sink = (Fmi3Sink *)calloc(1, sizeof *sink);
        if (sink == NULL) {
            instantiateFailed(logMessage, instanceEnvironment, fmi3Fatal,
                              "fmi3InstantiateCoSimulation: out of memory");
            return NULL;
        }
        sink->logMessage = logMessage;
        sink->env = instanceEnvironment;
    }
    /* resourcePath (a native path in FMI 3.0, may be NULL) is kept; this FMU has no resources */
    inst = fmiNew(&fmiModel, NULL, &FMI3_FACE, instanceName, resourcePath, sink ? fmi3Sink : NULL, sink, loggingOn);
    if (inst == NULL) {
        instantiateFailed(logMessage, instanceEnvironment, fmi3Fatal,
                          "fmi3InstantiateCoSimulation: out of memory");
        return NULL;
    }
    return (fmi3Instance)inst;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage)
{
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    instantiateFailed(logMessage, instanceEnvironment, fmi3Error,
                      "fmi3InstantiateModelExchange: not supported: " NO_MODEL_EXCHANGE);
    return NULL;
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instanceName; (void)instantiationToken; (void)resourcePath; (void)visible; (void)loggingOn;
    (void)clockUpdate; (void)lockPreemption; (void)unlockPreemption;
    instantiateFailed(logMessage, instanceEnvironment, fmi3Error,
                      "fmi3InstantiateScheduledExecution: not supported: this FMU is a co-simulation FMU "
                      "(no <ScheduledExecution>)");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance)
{
    FmiInstance *inst = (FmiInstance *)instance;
    if (inst == NULL || inst->magic != FMI_INSTANCE_MAGIC) return;
    fmiLog(inst, FmiOK, LogCalls, "fmi3FreeInstance");
    fmiFree(inst);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    const char *fn = "fmi3EnterInitializationMode";
    FmiInstance *inst = enter(instance, fn, MASK_EnterInitializationMode);
    FmiStatus status;
    if (inst == NULL) return fmi3Error;
    status = fmiSetupExperiment(inst, fn, toleranceDefined ? 1 : 0, tolerance, startTime, stopTimeDefined ? 1 : 0,
                                stopTime);
    if (status <= FmiWarning) inst->fsm = FsmInitializationMode;
    return (fmi3Status)status;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance)
{
    const char *fn = "fmi3ExitInitializationMode";
    FmiInstance *inst = enter(instance, fn, MASK_ExitInitializationMode);
    FmiStatus status;
    if (inst == NULL) return fmi3Error;
    status = fmiExitInitialization(inst, fn);
    inst->fsm = status <= FmiWarning ? FsmStepComplete : FsmError;
    return (fmi3Status)status;
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterEventMode", NO_EVENT_MODE);
}

fmi3Status fmi3Terminate(fmi3Instance instance)
{
    FmiInstance *inst = enter(instance, "fmi3Terminate", MASK_Terminate);
    if (inst == NULL) return fmi3Error;
    inst->fsm = FsmTerminated;
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance instance)
{
    FmiInstance *inst = enter(instance, "fmi3Reset", MASK_Reset);
    if (inst == NULL) return fmi3Error;
    fmiReset(inst);
    return fmi3OK;
}

/* ------------------------------------------------------------------------------------------- */
/* Getting and setting variables                                                                */

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float64 values[], size_t nValues)
{
    return getValues(instance, "fmi3GetFloat64", valueReferences, nValueReferences, &FLOAT64S, values, nValues);
}

fmi3Status fmi3GetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Int32 values[], size_t nValues)
{
    return getValues(instance, "fmi3GetInt32", valueReferences, nValueReferences, &INT32S, values, nValues);
}

fmi3Status fmi3GetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Boolean values[], size_t nValues)
{
    return getValues(instance, "fmi3GetBoolean", valueReferences, nValueReferences, &BOOLEANS, values, nValues);
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Float64 values[], size_t nValues)
{
    return setValues(instance, "fmi3SetFloat64", valueReferences, nValueReferences, &FLOAT64S, values, nValues);
}

fmi3Status fmi3SetInt32(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Int32 values[], size_t nValues)
{
    return setValues(instance, "fmi3SetInt32", valueReferences, nValueReferences, &INT32S, values, nValues);
}

fmi3Status fmi3SetBoolean(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Boolean values[], size_t nValues)
{
    return setValues(instance, "fmi3SetBoolean", valueReferences, nValueReferences, &BOOLEANS, values, nValues);
}

/* The types without variables here. */
#define NO_GET(T, CT)                                                                                          \
    fmi3Status fmi3Get##T(fmi3Instance instance, const fmi3ValueReference valueReferences[],                    \
                          size_t nValueReferences, CT values[], size_t nValues)                                 \
    {                                                                                                          \
        (void)nValues;                                                                                         \
        return noVariables(instance, "fmi3Get" #T, MASK_Get, valueReferences, nValueReferences, values, #T);    \
    }
#define NO_SET(T, CT)                                                                                          \
    fmi3Status fmi3Set##T(fmi3Instance instance, const fmi3ValueReference valueReferences[],                    \
                          size_t nValueReferences, const CT values[], size_t nValues)                           \
    {                                                                                                          \
        (void)nValues;                                                                                         \
        return noVariables(instance, "fmi3Set" #T, MASK_Set, valueReferences, nValueReferences, values, #T);    \
    }

NO_GET(Float32, fmi3Float32)
NO_GET(Int8, fmi3Int8)
NO_GET(UInt8, fmi3UInt8)
NO_GET(Int16, fmi3Int16)
NO_GET(UInt16, fmi3UInt16)
NO_GET(UInt32, fmi3UInt32)
NO_GET(Int64, fmi3Int64)
NO_GET(UInt64, fmi3UInt64)
NO_GET(String, fmi3String)
NO_SET(Float32, fmi3Float32)
NO_SET(Int8, fmi3Int8)
NO_SET(UInt8, fmi3UInt8)
NO_SET(Int16, fmi3Int16)
NO_SET(UInt16, fmi3UInt16)
NO_SET(UInt32, fmi3UInt32)
NO_SET(Int64, fmi3Int64)
NO_SET(UInt64, fmi3UInt64)
NO_SET(String, fmi3String)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         size_t valueSizes[], fmi3Binary values[], size_t nValues)
{
    (void)valueSizes; (void)nValues;
    return noVariables(instance, "fmi3GetBinary", MASK_Get, valueReferences, nValueReferences, values, "Binary");
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                         const size_t valueSizes[], const fmi3Binary values[], size_t nValues)
{
    (void)valueSizes; (void)nValues;
    return noVariables(instance, "fmi3SetBinary", MASK_Set, valueReferences, nValueReferences, values, "Binary");
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                        fmi3Clock values[])
{
    (void)valueReferences; (void)nValueReferences; (void)values;
    return unsupported(instance, "fmi3GetClock", NO_CLOCKS);
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[], size_t nValueReferences,
                        const fmi3Clock values[])
{
    (void)valueReferences; (void)nValueReferences; (void)values;
    return unsupported(instance, "fmi3SetClock", NO_CLOCKS);
}

/* ------------------------------------------------------------------------------------------- */
/* Variable dependencies, partial derivatives                                                   */

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference valueReference,
                                               size_t *nDependencies)
{
    (void)valueReference; (void)nDependencies;
    return unsupported(instance, "fmi3GetNumberOfVariableDependencies",
                       "providesPerElementDependencies = false (the dependencies are in <ModelStructure>)");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[], fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[], fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies)
{
    (void)dependent; (void)elementIndicesOfDependent; (void)independents; (void)elementIndicesOfIndependents;
    (void)dependencyKinds; (void)nDependencies;
    return unsupported(instance, "fmi3GetVariableDependencies",
                       "providesPerElementDependencies = false (the dependencies are in <ModelStructure>)");
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed; (void)sensitivity;
    (void)nSensitivity;
    return unsupported(instance, "fmi3GetDirectionalDerivative", "providesDirectionalDerivatives = false");
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns; (void)nUnknowns; (void)knowns; (void)nKnowns; (void)seed; (void)nSeed; (void)sensitivity;
    (void)nSensitivity;
    return unsupported(instance, "fmi3GetAdjointDerivative", "providesAdjointDerivatives = false");
}

/* ------------------------------------------------------------------------------------------- */
/* FMU state                                                                                    */

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    const char *fn = "fmi3GetFMUState";
    FmiInstance *inst = enterState(instance, fn, FMUState != NULL, "FMUState");
    if (inst == NULL) return fmi3Error;
    return (fmi3Status)fmiStateGet(inst, fn, FMUState);
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState)
{
    const char *fn = "fmi3SetFMUState";
    FmiInstance *inst = enterState(instance, fn, FMUState != NULL, "FMUState");
    if (inst == NULL) return fmi3Error;
    return (fmi3Status)fmiStateSet(inst, fn, FMUState);
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState)
{
    const char *fn = "fmi3FreeFMUState";
    FmiInstance *inst = enterState(instance, fn, FMUState != NULL, "FMUState");
    if (inst == NULL) return fmi3Error;
    return (fmi3Status)fmiStateFree(inst, fn, FMUState);
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState, size_t *size)
{
    const char *fn = "fmi3SerializedFMUStateSize";
    FmiInstance *inst = enterState(instance, fn, FMUState != NULL && size != NULL, "FMUState or size");
    if (inst == NULL) return fmi3Error;
    return (fmi3Status)fmiStateSize(inst, fn, FMUState, size);
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState, fmi3Byte serializedState[],
                                 size_t size)
{
    const char *fn = "fmi3SerializeFMUState";
    FmiInstance *inst = enterState(instance, fn, FMUState != NULL && serializedState != NULL,
                                   "FMUState or serializedState");
    if (inst == NULL) return fmi3Error;
    return (fmi3Status)fmiStateSerialize(inst, fn, FMUState, serializedState, size);
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[], size_t size,
                                   fmi3FMUState *FMUState)
{
    const char *fn = "fmi3DeserializeFMUState";
    FmiInstance *inst = enterState(instance, fn, serializedState != NULL && FMUState != NULL,
                                   "serializedState or FMUState");
    if (inst == NULL) return fmi3Error;
    return (fmi3Status)fmiStateDeserialize(inst, fn, serializedState, size, FMUState);
}

/* ------------------------------------------------------------------------------------------- */
/* Configuration mode, clocks, discrete states: none here                                       */

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterConfigurationMode", NO_CONFIGURATION);
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3ExitConfigurationMode", NO_CONFIGURATION);
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Float64 intervals[],
                                  fmi3IntervalQualifier qualifiers[])
{
    (void)valueReferences; (void)nValueReferences; (void)intervals; (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalDecimal", NO_CLOCKS);
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[],
                                   fmi3IntervalQualifier qualifiers[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions; (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalFraction", NO_CLOCKS);
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, fmi3Float64 shifts[])
{
    (void)valueReferences; (void)nValueReferences; (void)shifts;
    return unsupported(instance, "fmi3GetShiftDecimal", NO_CLOCKS);
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
    return unsupported(instance, "fmi3GetShiftFraction", NO_CLOCKS);
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Float64 intervals[])
{
    (void)valueReferences; (void)nValueReferences; (void)intervals;
    return unsupported(instance, "fmi3SetIntervalDecimal", NO_CLOCKS);
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
    return unsupported(instance, "fmi3SetIntervalFraction", NO_CLOCKS);
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, const fmi3Float64 shifts[])
{
    (void)valueReferences; (void)nValueReferences; (void)shifts;
    return unsupported(instance, "fmi3SetShiftDecimal", NO_CLOCKS);
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, const fmi3UInt64 counters[],
                                const fmi3UInt64 resolutions[])
{
    (void)valueReferences; (void)nValueReferences; (void)counters; (void)resolutions;
    return unsupported(instance, "fmi3SetShiftFraction", NO_CLOCKS);
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EvaluateDiscreteStates", NO_EVENT_MODE);
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime)
{
    (void)discreteStatesNeedUpdate; (void)terminateSimulation; (void)nominalsOfContinuousStatesChanged;
    (void)valuesOfContinuousStatesChanged; (void)nextEventTimeDefined; (void)nextEventTime;
    return unsupported(instance, "fmi3UpdateDiscreteStates", NO_EVENT_MODE);
}

/* ------------------------------------------------------------------------------------------- */
/* Model exchange: not supported                                                                */

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterContinuousTimeMode", NO_MODEL_EXCHANGE);
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint; (void)enterEventMode; (void)terminateSimulation;
    return unsupported(instance, "fmi3CompletedIntegratorStep", NO_MODEL_EXCHANGE);
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    (void)time;
    return unsupported(instance, "fmi3SetTime", NO_MODEL_EXCHANGE);
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates)
{
    (void)continuousStates; (void)nContinuousStates;
    return unsupported(instance, "fmi3SetContinuousStates", NO_MODEL_EXCHANGE);
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates)
{
    (void)derivatives; (void)nContinuousStates;
    return unsupported(instance, "fmi3GetContinuousStateDerivatives", NO_MODEL_EXCHANGE);
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[], size_t nEventIndicators)
{
    (void)eventIndicators; (void)nEventIndicators;
    return unsupported(instance, "fmi3GetEventIndicators", NO_MODEL_EXCHANGE);
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[], size_t nContinuousStates)
{
    (void)continuousStates; (void)nContinuousStates;
    return unsupported(instance, "fmi3GetContinuousStates", NO_MODEL_EXCHANGE);
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t nContinuousStates)
{
    (void)nominals; (void)nContinuousStates;
    return unsupported(instance, "fmi3GetNominalsOfContinuousStates", NO_MODEL_EXCHANGE);
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators)
{
    (void)nEventIndicators;
    return unsupported(instance, "fmi3GetNumberOfEventIndicators", NO_MODEL_EXCHANGE);
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates)
{
    (void)nContinuousStates;
    return unsupported(instance, "fmi3GetNumberOfContinuousStates", NO_MODEL_EXCHANGE);
}

/* ------------------------------------------------------------------------------------------- */
/* Co-simulation                                                                                */

fmi3Status fmi3EnterStepMode(fmi3Instance instance)
{
    return unsupported(instance, "fmi3EnterStepMode",
                       NO_EVENT_MODE ": fmi3ExitInitializationMode enters Step Mode directly");
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues)
{
    const char *fn = "fmi3GetOutputDerivatives";
    FmiInstance *inst = enter(instance, fn, MASK_GetOutputDerivatives);
    (void)valueReferences; (void)orders; (void)values; (void)nValues;
    if (inst == NULL) return fmi3Error;
    if (nValueReferences == 0) return fmi3OK;
    fmiLogStatus(inst, FmiError, "%s: output derivatives are not provided (maxOutputDerivativeOrder = 0)", fn);
    return fmi3Error;
}

/* Input derivatives: FMI 3.0 has no function to set them (fmi2SetRealInputDerivatives has no
 * successor; intermediate values would come through intermediate update, not provided here), so
 * every input is held over a communication step: the layer's derivative slots stay zero. */
fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn,
                      fmi3Float64 *lastSuccessfulTime)
{
    const char *fn = "fmi3DoStep";
    FmiInstance *inst = enterNonNull(instance, fn, MASK_DoStep,
                                     eventHandlingNeeded != NULL && terminateSimulation != NULL &&
                                         earlyReturn != NULL && lastSuccessfulTime != NULL,
                                     "eventHandlingNeeded, terminateSimulation, earlyReturn or lastSuccessfulTime");
    FmiStatus status;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (inst == NULL) return fmi3Error;
    status = fmiDoStep(inst, fn, currentCommunicationPoint, communicationStepSize);
    /* fmi3Discard: the state at currentCommunicationPoint is restored, Step Mode continues;
     * fmi3Error: terminal until fmi3Reset or fmi3SetFMUState */
    inst->fsm = status <= FmiDiscard ? FsmStepComplete : FsmError;
    *eventHandlingNeeded = fmi3False;
    *terminateSimulation = status >= FmiError ? fmi3True : fmi3False;
    *earlyReturn = fmi3False;
    *lastSuccessfulTime = inst->run.time;
    return (fmi3Status)status;
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime)
{
    (void)clockReference; (void)activationTime;
    return unsupported(instance, "fmi3ActivateModelPartition",
                       "this FMU is a co-simulation FMU (no <ScheduledExecution>)");
}
