/* The FMI 2.0 face: the common and co-simulation fmi2* entry points over the generic layer (the
 * model-exchange ones are in fmi2_me.c). Here and in fmi2_me.c only, fmi2 types meet the neutral
 * ones: call-sequence state machine (one allowed-states mask per function, from the state tables
 * of the FMI 2.0 standard, sections 3.2.3 and 4.2.4), pointer and argument checks, type conversion,
 * the logger callback. The model is the one linked in (fmiModel); an instance is for model
 * exchange only if the model has a model-exchange part (fmiModelExchange). */
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "fmi/instance.h"
#include "fmi/log.h"
#include "fmi/state_blob.h"
#include "fmi/variables.h"

/* The face's logger context: the master's callback, and a buffer for the escaped message. */
typedef struct {
    fmi2CallbackLogger logger;
    fmi2ComponentEnvironment env;
    char escaped[2100];
} Fmi2Sink;

/* The logger's message is a printf format: '%' is escaped. */
static void fmi2Sink(void *ctx, const char *instanceName, FmiStatus status, const char *category,
                     const char *message)
{
    Fmi2Sink *k = (Fmi2Sink *)ctx;
    size_t j = 0;
    for (size_t i = 0; message[i] != '\0' && j + 2 < sizeof k->escaped; ++i) {
        if (message[i] == '%') k->escaped[j++] = '%';
        k->escaped[j++] = message[i];
    }
    k->escaped[j] = '\0';
    k->logger(k->env, instanceName, (fmi2Status)status, category, k->escaped);
}

/* The names the generic layer's messages use. */
static const FmiFace FMI2_FACE = {"fmi2ExitInitializationMode", "fmi2SerializedFMUstateSize",
                                  {"Real", "Integer", "Boolean"}, fsmStateName, 1};

/* Allowed states per function (co-simulation and model-exchange states: an instance reaches only
 * those of its kind). The error state additionally allows fmi2GetStatus and friends. */
#define ME_STATES (FsmEventMode | FsmContinuousTimeMode)
#define ALL_BUT_START (FsmInstantiated | FsmInitializationMode | FsmStepComplete | FsmStepInProgress | \
                       FsmStepFailed | FsmStepCanceled | FsmTerminated | FsmError | ME_STATES)
#define MASK_SetDebugLogging ALL_BUT_START
#define MASK_SetupExperiment FsmInstantiated
#define MASK_EnterInitializationMode FsmInstantiated
#define MASK_ExitInitializationMode FsmInitializationMode
#define MASK_Terminate (FsmStepComplete | FsmStepFailed | ME_STATES)
#define MASK_Reset (FsmInstantiated | FsmInitializationMode | FsmStepComplete | FsmStepFailed | \
                    FsmStepCanceled | FsmTerminated | FsmError | ME_STATES)
#define MASK_Get (FsmInitializationMode | FsmStepComplete | FsmStepFailed | FsmStepCanceled | \
                  FsmTerminated | FsmError | ME_STATES)
#define MASK_Set (FsmInstantiated | FsmInitializationMode | FsmStepComplete | ME_STATES)
#define MASK_FMUstate MASK_Reset
#define MASK_GetDirectionalDerivative MASK_Get
#define MASK_SetRealInputDerivatives (FsmInstantiated | FsmInitializationMode | FsmStepComplete)
#define MASK_GetRealOutputDerivatives (FsmStepComplete | FsmStepFailed | FsmStepCanceled | FsmTerminated | \
                                       FsmError)
#define MASK_DoStep FsmStepComplete
#define MASK_CancelStep FsmStepInProgress
#define MASK_GetStatus (FsmStepComplete | FsmStepInProgress | FsmStepFailed | FsmTerminated | FsmError)

static FmiInstance *enter(fmi2Component c, const char *fn, int mask) { return fmiEnter(c, fn, mask, 1); }

/* enter() for a co-simulation function: refused for a model-exchange instance. */
static FmiInstance *enterCS(fmi2Component c, const char *fn, int mask)
{
    FmiInstance *inst = (FmiInstance *)c;
    if (inst != NULL && inst->magic == FMI_INSTANCE_MAGIC && inst->me) {
        fmiLog(inst, FmiOK, LogCalls, "%s (state: %s)", fn, fsmStateName(inst->fsm));
        fmiLogStatus(inst, FmiError, "%s: not available: the instance was instantiated for model exchange "
                     "(fmuType = fmi2ModelExchange)", fn);
        return NULL;
    }
    return enter(c, fn, mask);
}

/* enter() for a function with a required pointer argument: ok = 0 logs "<fn>: <what> is NULL". */
static FmiInstance *enterNonNull(fmi2Component c, const char *fn, int mask, int ok, const char *what)
{
    FmiInstance *inst = enter(c, fn, mask);
    if (inst != NULL && !ok) {
        fmiLogStatus(inst, FmiError, "%s: %s is NULL", fn, what);
        return NULL;
    }
    return inst;
}

/* enterNonNull() for fmi2Get*Status (co-simulation only). */
static FmiInstance *enterStatus(fmi2Component c, const char *fn, int ok)
{
    FmiInstance *inst = (FmiInstance *)c;
    if (inst != NULL && inst->magic == FMI_INSTANCE_MAGIC && inst->me)
        return enterCS(c, fn, 0); /* logs why */
    return enterNonNull(c, fn, MASK_GetStatus, ok, "value");
}

/* enterNonNull() for the FMU state functions, refused when the model declares
 * canGetAndSetFMUstate="false". */
static FmiInstance *enterState(fmi2Component c, const char *fn, int ok, const char *what)
{
    FmiInstance *inst = enterNonNull(c, fn, MASK_FMUstate, ok, what);
    if (inst != NULL && !inst->model->canGetAndSetState) {
        fmiLogStatus(inst, FmiError, "%s: not supported (canGetAndSetFMUstate = false)", fn);
        return NULL;
    }
    return inst;
}

/* fmi2 arrays seen element-wise as doubles by the generic engine */
static double readReal(const void *v, size_t i) { return ((const fmi2Real *)v)[i]; }
static void writeReal(void *v, size_t i, double x) { ((fmi2Real *)v)[i] = x; }
static double readInteger(const void *v, size_t i) { return (double)((const fmi2Integer *)v)[i]; }
static void writeInteger(void *v, size_t i, double x) { ((fmi2Integer *)v)[i] = (fmi2Integer)x; }
/* any nonzero fmi2Boolean is true */
static double readBoolean(const void *v, size_t i) { return ((const fmi2Boolean *)v)[i] ? 1.0 : 0.0; }
static void writeBoolean(void *v, size_t i, double x) { ((fmi2Boolean *)v)[i] = x != 0.0 ? fmi2True : fmi2False; }
static const FmiArray REALS = {VarReal, readReal, writeReal};
static const FmiArray INTEGERS = {VarInteger, readInteger, writeInteger};
static const FmiArray BOOLEANS = {VarBoolean, readBoolean, writeBoolean};

#define VRS(vr) ((const FmiValueRef *)(vr))

static int nullArgs(FmiInstance *inst, const char *fn, size_t nvr, const void *a, const void *b)
{
    if (nvr > 0 && (a == NULL || b == NULL)) {
        fmiLogStatus(inst, FmiError, "%s: NULL array argument with nvr = %lu", fn, (unsigned long)nvr);
        return 1;
    }
    return 0;
}

/* ------------------------------------------------------------------------------------------- */
/* Common functions                                                                             */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    const char *fn = "fmi2SetDebugLogging";
    FmiInstance *inst = fmiEnter(c, fn, MASK_SetDebugLogging, 0); /* logs the call after the change */
    if (inst == NULL) return fmi2Error;
    /* FMI 2.0 s.2.1.5: nCategories = 0 switches all categories; with loggingOn = fmi2True and a
     * list, only the listed categories are output; with fmi2False the listed ones are switched off */
    if (fmiSetDebugLogging(inst, fn, loggingOn != fmi2False, nCategories, categories) != FmiOK) return fmi2Error;
    fmiLog(inst, FmiOK, LogCalls, "%s (state: %s)", fn, fsmStateName(inst->fsm));
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    const char *fn = "fmi2Instantiate";
    FmiInstance *inst;
    fmi2CallbackLogger log;
    Fmi2Sink *sink;
    const char *name = (instanceName != NULL) ? instanceName : "";
    (void)visible;
    if (functions == NULL || functions->logger == NULL) return NULL; /* no way to report anything */
    log = functions->logger;
    if (instanceName == NULL || instanceName[0] == '\0') {
        log(functions->componentEnvironment, name, fmi2Error, "logStatusError",
                           "fmi2Instantiate: instanceName must be a non-empty string");
        return NULL;
    }
    if (fmuType != fmi2CoSimulation && !(fmuType == fmi2ModelExchange && fmiModelExchange != NULL)) {
        if (fmiModelExchange != NULL) {
            log(functions->componentEnvironment, name, fmi2Error, "logStatusError",
                               "fmi2Instantiate: fmuType = %d is not supported: %s is instantiated for "
                               "fmi2ModelExchange = %d or fmi2CoSimulation = %d", (int)fmuType, fmiModel.name,
                               (int)fmi2ModelExchange, (int)fmi2CoSimulation);
        } else {
            log(functions->componentEnvironment, name, fmi2Error, "logStatusError",
                "fmi2Instantiate: fmuType = %d is not supported: %s is a co-simulation "
                "FMU (fmi2CoSimulation = %d)", (int)fmuType, fmiModel.name, (int)fmi2CoSimulation);
        }
        return NULL;
    }
    if (fmuGUID == NULL || strcmp(fmuGUID, fmiModel.guid) != 0) {
        log(functions->componentEnvironment, name, fmi2Error, "logStatusError",
                           "fmi2Instantiate: GUID %s does not match the GUID %s of this FMU binary",
                           fmuGUID ? fmuGUID : "(NULL)", fmiModel.guid);
        return NULL;
    }
    sink = (Fmi2Sink *)calloc(1, sizeof *sink);
    if (sink != NULL) {
        sink->logger = log;
        sink->env = functions->componentEnvironment;
    }
    inst = sink ? fmiNew(&fmiModel, fmuType == fmi2ModelExchange ? fmiModelExchange : NULL, &FMI2_FACE, instanceName,
                         fmuResourceLocation, fmi2Sink, sink, loggingOn) : NULL;
    if (inst == NULL) {
        log(functions->componentEnvironment, name, fmi2Fatal, "logStatusFatal",
                           "fmi2Instantiate: out of memory");
        return NULL;
    }
    /* resources are not used; file:///, file:/ (and file://host/) URIs and NULL are accepted */
    if (fmuResourceLocation != NULL && strncmp(fmuResourceLocation, "file:", 5) != 0)
        fmiLogStatus(inst, FmiWarning, "%s: fmuResourceLocation is not a file: URI (ignored: this FMU has "
                          "no resources)", fn);
    return (fmi2Component)inst;
}

void fmi2FreeInstance(fmi2Component c)
{
    FmiInstance *inst = (FmiInstance *)c;
    if (inst == NULL || inst->magic != FMI_INSTANCE_MAGIC) return;
    fmiLog(inst, FmiOK, LogCalls, "fmi2FreeInstance");
    fmiFree(inst);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    FmiInstance *inst = enter(c, "fmi2SetupExperiment", MASK_SetupExperiment);
    if (inst == NULL) return fmi2Error;
    return (fmi2Status)fmiSetupExperiment(inst, "fmi2SetupExperiment", toleranceDefined, tolerance, startTime,
                                          stopTimeDefined, stopTime);
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    FmiInstance *inst = enter(c, "fmi2EnterInitializationMode", MASK_EnterInitializationMode);
    if (inst == NULL) return fmi2Error;
    inst->fsm = FsmInitializationMode;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    FmiInstance *inst = enter(c, "fmi2ExitInitializationMode", MASK_ExitInitializationMode);
    fmi2Status status;
    if (inst == NULL) return fmi2Error;
    status = (fmi2Status)fmiExitInitialization(inst, "fmi2ExitInitializationMode");
    /* model exchange (s.3.2.3): the master first completes the event iteration at the start */
    inst->fsm = status <= fmi2Warning ? (inst->me ? FsmEventMode : FsmStepComplete) : FsmError;
    return status;
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    FmiInstance *inst = enter(c, "fmi2Terminate", MASK_Terminate);
    if (inst == NULL) return fmi2Error;
    inst->fsm = FsmTerminated;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c)
{
    FmiInstance *inst = enter(c, "fmi2Reset", MASK_Reset);
    if (inst == NULL) return fmi2Error;
    fmiReset(inst);
    return fmi2OK;
}

/* ------------------------------------------------------------------------------------------- */
/* Getting and setting variables                                                                */

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    const char *fn = "fmi2GetReal";
    FmiInstance *inst = enter(c, fn, MASK_Get);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value)) return fmi2Error;
    return (fmi2Status)fmiGetValues(inst, fn, VRS(vr), nvr, &REALS, value);
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    const char *fn = "fmi2GetInteger";
    FmiInstance *inst = enter(c, fn, MASK_Get);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value)) return fmi2Error;
    return (fmi2Status)fmiGetValues(inst, fn, VRS(vr), nvr, &INTEGERS, value);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    const char *fn = "fmi2GetBoolean";
    FmiInstance *inst = enter(c, fn, MASK_Get);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value)) return fmi2Error;
    return (fmi2Status)fmiGetValues(inst, fn, VRS(vr), nvr, &BOOLEANS, value);
}

/* There are no String variables: every value reference is refused. */
static fmi2Status noStrings(FmiInstance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr)
{
    if (nvr == 0) return fmi2OK;
    {
        const VarInfo *v = fmiFindVar(inst->model, vr[0]);
        const char *name = v ? v->name : NULL;
        if (name) fmiLogStatus(inst, FmiError, "%s: %s (vr %u) is not a String variable", fn, name, (unsigned)vr[0]);
        else fmiLogStatus(inst, FmiError, "%s: unknown value reference %u (this FMU has no String variables)",
                               fn, (unsigned)vr[0]);
    }
    return fmi2Error;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    const char *fn = "fmi2GetString";
    FmiInstance *inst = enter(c, fn, MASK_Get);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value)) return fmi2Error;
    return noStrings(inst, fn, vr, nvr);
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    const char *fn = "fmi2SetReal";
    FmiInstance *inst = enter(c, fn, MASK_Set);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value)) return fmi2Error;
    return (fmi2Status)fmiSetValues(inst, fn, VRS(vr), nvr, &REALS, value);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    const char *fn = "fmi2SetInteger";
    FmiInstance *inst = enter(c, fn, MASK_Set);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value)) return fmi2Error;
    return (fmi2Status)fmiSetValues(inst, fn, VRS(vr), nvr, &INTEGERS, value);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    const char *fn = "fmi2SetBoolean";
    FmiInstance *inst = enter(c, fn, MASK_Set);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value)) return fmi2Error;
    return (fmi2Status)fmiSetValues(inst, fn, VRS(vr), nvr, &BOOLEANS, value);
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    const char *fn = "fmi2SetString";
    FmiInstance *inst = enter(c, fn, MASK_Set);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value)) return fmi2Error;
    return noStrings(inst, fn, vr, nvr);
}

/* ------------------------------------------------------------------------------------------- */
/* FMU state                                                                                    */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    const char *fn = "fmi2GetFMUstate";
    FmiInstance *inst = enterState(c, fn, FMUstate != NULL, "FMUstate");
    if (inst == NULL) return fmi2Error;
    return (fmi2Status)fmiStateGet(inst, fn, FMUstate);
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate)
{
    const char *fn = "fmi2SetFMUstate";
    FmiInstance *inst = enterState(c, fn, FMUstate != NULL, "FMUstate");
    fmi2Status status;
    if (inst == NULL) return fmi2Error;
    status = (fmi2Status)fmiStateSet(inst, fn, FMUstate);
    /* a deserialized state of a running instance comes back in stepComplete: for model exchange
     * that is continuous-time mode */
    if (inst->me && inst->fsm == FsmStepComplete) inst->fsm = FsmContinuousTimeMode;
    return status;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate)
{
    const char *fn = "fmi2FreeFMUstate";
    FmiInstance *inst = enterState(c, fn, FMUstate != NULL, "FMUstate");
    if (inst == NULL) return fmi2Error;
    return (fmi2Status)fmiStateFree(inst, fn, FMUstate);
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size)
{
    const char *fn = "fmi2SerializedFMUstateSize";
    FmiInstance *inst = enterState(c, fn, FMUstate != NULL && size != NULL, "FMUstate or size");
    if (inst == NULL) return fmi2Error;
    return (fmi2Status)fmiStateSize(inst, fn, FMUstate, size);
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[], size_t size)
{
    const char *fn = "fmi2SerializeFMUstate";
    FmiInstance *inst = enterState(c, fn, FMUstate != NULL && serializedState != NULL,
                                  "FMUstate or serializedState");
    if (inst == NULL) return fmi2Error;
    return (fmi2Status)fmiStateSerialize(inst, fn, FMUstate, (unsigned char *)serializedState, size);
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate)
{
    const char *fn = "fmi2DeSerializeFMUstate";
    FmiInstance *inst = enterState(c, fn, serializedState != NULL && FMUstate != NULL,
                                  "serializedState or FMUstate");
    if (inst == NULL) return fmi2Error;
    return (fmi2Status)fmiStateDeserialize(inst, fn, (const unsigned char *)serializedState, size, FMUstate);
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[], size_t nUnknown,
                                        const fmi2ValueReference vKnown_ref[], size_t nKnown,
                                        const fmi2Real dvKnown[], fmi2Real dvUnknown[])
{
    const char *fn = "fmi2GetDirectionalDerivative";
    FmiInstance *inst = enter(c, fn, MASK_GetDirectionalDerivative);
    (void)vUnknown_ref; (void)nUnknown; (void)vKnown_ref; (void)nKnown; (void)dvKnown; (void)dvUnknown;
    if (inst == NULL) return fmi2Error;
    fmiLogStatus(inst, FmiError, "%s: not supported (providesDirectionalDerivative = false)", fn);
    return fmi2Error;
}

/* ------------------------------------------------------------------------------------------- */
/* Co-simulation                                                                                */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    const char *fn = "fmi2SetRealInputDerivatives";
    FmiInstance *inst = enterCS(c, fn, MASK_SetRealInputDerivatives);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value) || nullArgs(inst, fn, nvr, order, order)) return fmi2Error;
    return (fmi2Status)fmiSetInputDerivatives(inst, fn, VRS(vr), nvr, (const int32_t *)order, value);
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    const char *fn = "fmi2GetRealOutputDerivatives";
    FmiInstance *inst = enterCS(c, fn, MASK_GetRealOutputDerivatives);
    if (inst == NULL || nullArgs(inst, fn, nvr, vr, value) || nullArgs(inst, fn, nvr, order, order)) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    fmiLogStatus(inst, FmiError, "%s: output derivatives are not provided (maxOutputDerivativeOrder = 0)", fn);
    return fmi2Error;
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    FmiInstance *inst = enterCS(c, "fmi2DoStep", MASK_DoStep);
    fmi2Status status;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (inst == NULL) return fmi2Error;
    status = (fmi2Status)fmiDoStep(inst, "fmi2DoStep", currentCommunicationPoint, communicationStepSize);
    /* fmi2Discard: state restored, the master may set an earlier FMU state and retry;
     * fmi2Error: terminal until fmi2Reset or fmi2SetFMUstate */
    inst->fsm = status <= fmi2Warning ? FsmStepComplete : (status == fmi2Discard ? FsmStepFailed : FsmError);
    return status;
}

fmi2Status fmi2CancelStep(fmi2Component c)
{
    FmiInstance *inst = enterCS(c, "fmi2CancelStep", MASK_CancelStep);
    if (inst == NULL) return fmi2Error;
    return fmi2Error; /* unreachable: steps are never asynchronous */
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    const char *fn = "fmi2GetStatus";
    FmiInstance *inst = enterStatus(c, fn, value != NULL);
    if (inst == NULL) return fmi2Error;
    if (s != fmi2DoStepStatus) {
        fmiLogStatus(inst, FmiDiscard, "%s: status kind %d is not available here (only fmi2DoStepStatus)", fn, (int)s);
        return fmi2Discard;
    }
    *value = (fmi2Status)inst->run.lastDoStepStatus;
    return fmi2OK;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    const char *fn = "fmi2GetRealStatus";
    FmiInstance *inst = enterStatus(c, fn, value != NULL);
    if (inst == NULL) return fmi2Error;
    if (s != fmi2LastSuccessfulTime) {
        fmiLogStatus(inst, FmiDiscard, "%s: status kind %d is not available here (only fmi2LastSuccessfulTime)",
                          fn, (int)s);
        return fmi2Discard;
    }
    *value = inst->run.time; /* a discarded step leaves the time at its start */
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    const char *fn = "fmi2GetIntegerStatus";
    FmiInstance *inst = enterStatus(c, fn, value != NULL);
    if (inst == NULL) return fmi2Error;
    fmiLogStatus(inst, FmiDiscard, "%s: status kind %d is not available (FMI 2.0 defines no Integer status)", fn,
                      (int)s);
    return fmi2Discard;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    const char *fn = "fmi2GetBooleanStatus";
    FmiInstance *inst = enterStatus(c, fn, value != NULL);
    if (inst == NULL) return fmi2Error;
    if (s != fmi2Terminated) {
        fmiLogStatus(inst, FmiDiscard, "%s: status kind %d is not available here (only fmi2Terminated)", fn, (int)s);
        return fmi2Discard;
    }
    /* the slave never asks to end the simulation by itself, except in the error state */
    *value = inst->fsm == FsmError ? fmi2True : fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    const char *fn = "fmi2GetStringStatus";
    FmiInstance *inst = enterStatus(c, fn, value != NULL);
    if (inst == NULL) return fmi2Error;
    *value = "";
    fmiLogStatus(inst, FmiDiscard, "%s: status kind %d is not available (steps are never asynchronous)", fn,
                      (int)s);
    return fmi2Discard;
}
