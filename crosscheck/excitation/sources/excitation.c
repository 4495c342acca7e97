/*
 * Excitation: FMI 2.0 co-simulation source of the ShroudedBlade system example.
 *
 * Outputs at the communication point t (no states, no inputs):
 *   rotorSpeed n(t) [rpm]: n0 before t0, linear to n1 at t1, n1 after (a run-up when n1 > n0);
 *   aeroLoad f_w(t) [N/m] = Fw0 sin(psi_e(t)), psi_e = engineOrder * (2 pi / 60) * int_0^t n ds
 *   (paper eq. 17 with Omega = 2 pi n / 60, phase-continuous over the ramp; closed-form integral).
 * The time is the last communication point the master gave plus the step size, never accumulated
 * internally. No global mutable state; messages only through the FMI logger; C99.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#define MODEL_GUID "{6a0c7e52-3f1d-4b8e-9c27-5d4e1f0a9b13}"

enum { vrFw0 = 1, vrN0 = 2, vrN1 = 3, vrT0 = 4, vrT1 = 5, vrEngineOrder = 6, vrAeroLoad = 10, vrRotorSpeed = 11 };

typedef enum { PhaseInstantiated, PhaseInitialization, PhaseStep, PhaseTerminated } Phase;

typedef struct {
    fmi2CallbackFunctions cb; /* copied from fmi2Instantiate */
    char *name;               /* instance name (owned copy) */
    Phase phase;
    double fw0;               /* [N/m] load amplitude */
    double n0;                /* [rpm] speed before the ramp */
    double n1;                /* [rpm] speed after the ramp */
    double t0;                /* [s] ramp start */
    double t1;                /* [s] ramp end */
    int engineOrder;          /* [1] excitation order */
    double time;              /* [s] current communication point */
} Excitation;

static void logError(const Excitation *e, const char *fmt, ...)
{
    char msg[256];
    va_list ap;
    if (e == NULL || e->cb.logger == NULL) {
        return;
    }
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    e->cb.logger(e->cb.componentEnvironment, e->name, fmi2Error, "logStatusError", "%s", msg);
}

static void setDefaults(Excitation *e)
{
    e->fw0 = 100.0;
    e->n0 = 5000.0;
    e->n1 = 5000.0;
    e->t0 = 0.0;
    e->t1 = 1.0;
    e->engineOrder = 3;
    e->time = 0.0;
    e->phase = PhaseInstantiated;
}

/* n(t) [rpm] */
static double speedAt(const Excitation *e, double t)
{
    if (t <= e->t0) {
        return e->n0;
    }
    if (t >= e->t1) {
        return e->n1;
    }
    return e->n0 + (e->n1 - e->n0) * (t - e->t0) / (e->t1 - e->t0);
}

/* int_0^t n(s) ds [rpm s], exact for the piecewise-linear profile */
static double speedIntegral(const Excitation *e, double t)
{
    const double slope = (e->n1 - e->n0) / (e->t1 - e->t0); /* [rpm/s] */
    if (t <= e->t0) {
        return e->n0 * t;
    }
    if (t <= e->t1) {
        const double s = t - e->t0;
        return e->n0 * t + 0.5 * slope * s * s;
    }
    {
        const double w = e->t1 - e->t0;
        return e->n0 * e->t1 + 0.5 * slope * w * w + e->n1 * (t - e->t1);
    }
}

/* f_w(t) [N/m], eq. 17 */
static double aeroLoadAt(const Excitation *e, double t)
{
    const double psi = (double)e->engineOrder * (2.0 * 3.14159265358979323846 / 60.0) * speedIntegral(e, t);
    return e->fw0 * sin(psi);
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String guid,
                              fmi2String resourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    Excitation *e;
    (void)resourceLocation;
    (void)visible;
    (void)loggingOn;
    if (functions == NULL || functions->logger == NULL || instanceName == NULL || instanceName[0] == '\0') {
        return NULL;
    }
    if (fmuType != fmi2CoSimulation || guid == NULL || strcmp(guid, MODEL_GUID) != 0) {
        functions->logger(functions->componentEnvironment, instanceName, fmi2Error, "logStatusError",
                          "fmi2Instantiate: expected a co-simulation instance with GUID %s", MODEL_GUID);
        return NULL;
    }
    e = (Excitation *)calloc(1, sizeof(Excitation));
    if (e == NULL) {
        return NULL;
    }
    e->name = (char *)malloc(strlen(instanceName) + 1);
    if (e->name == NULL) {
        free(e);
        return NULL;
    }
    strcpy(e->name, instanceName);
    e->cb = *functions;
    setDefaults(e);
    return e;
}

void fmi2FreeInstance(fmi2Component c)
{
    Excitation *e = (Excitation *)c;
    if (e != NULL) {
        free(e->name);
        free(e);
    }
}

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t n, const fmi2String categories[])
{
    (void)loggingOn;
    (void)n;
    (void)categories;
    return c == NULL ? fmi2Error : fmi2OK;
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    Excitation *e = (Excitation *)c;
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    if (e == NULL || e->phase != PhaseInstantiated) {
        logError(e, "fmi2SetupExperiment: Illegal call sequence");
        return fmi2Error;
    }
    e->time = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c)
{
    Excitation *e = (Excitation *)c;
    if (e == NULL || e->phase != PhaseInstantiated) {
        logError(e, "fmi2EnterInitializationMode: Illegal call sequence");
        return fmi2Error;
    }
    e->phase = PhaseInitialization;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c)
{
    Excitation *e = (Excitation *)c;
    if (e == NULL || e->phase != PhaseInitialization) {
        logError(e, "fmi2ExitInitializationMode: Illegal call sequence");
        return fmi2Error;
    }
    if (!(e->t1 > e->t0) || e->n0 < 0.0 || e->n1 < 0.0 || e->engineOrder < 1) {
        logError(e, "fmi2ExitInitializationMode: need t1 > t0, n0 >= 0, n1 >= 0, engineOrder >= 1");
        return fmi2Error;
    }
    e->phase = PhaseStep;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c)
{
    Excitation *e = (Excitation *)c;
    if (e == NULL) {
        return fmi2Error;
    }
    e->phase = PhaseTerminated;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c)
{
    Excitation *e = (Excitation *)c;
    if (e == NULL) {
        return fmi2Error;
    }
    setDefaults(e);
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    const Excitation *e = (const Excitation *)c;
    size_t i;
    if (e == NULL || (nvr > 0 && (vr == NULL || value == NULL))) {
        return fmi2Error;
    }
    for (i = 0; i < nvr; i++) {
        switch (vr[i]) {
        case vrFw0: value[i] = e->fw0; break;
        case vrN0: value[i] = e->n0; break;
        case vrN1: value[i] = e->n1; break;
        case vrT0: value[i] = e->t0; break;
        case vrT1: value[i] = e->t1; break;
        case vrAeroLoad: value[i] = aeroLoadAt(e, e->time); break;
        case vrRotorSpeed: value[i] = speedAt(e, e->time); break;
        default:
            logError(e, "fmi2GetReal: unknown value reference %u", (unsigned)vr[i]);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    const Excitation *e = (const Excitation *)c;
    size_t i;
    if (e == NULL || (nvr > 0 && (vr == NULL || value == NULL))) {
        return fmi2Error;
    }
    for (i = 0; i < nvr; i++) {
        if (vr[i] != vrEngineOrder) {
            logError(e, "fmi2GetInteger: unknown value reference %u", (unsigned)vr[i]);
            return fmi2Error;
        }
        value[i] = e->engineOrder;
    }
    return fmi2OK;
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    (void)vr;
    (void)value;
    return (c == NULL || nvr > 0) ? fmi2Error : fmi2OK;
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    (void)vr;
    (void)value;
    return (c == NULL || nvr > 0) ? fmi2Error : fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    Excitation *e = (Excitation *)c;
    size_t i;
    if (e == NULL || (nvr > 0 && (vr == NULL || value == NULL))) {
        return fmi2Error;
    }
    if (nvr > 0 && e->phase != PhaseInstantiated && e->phase != PhaseInitialization) {
        logError(e, "fmi2SetReal: parameters are fixed after initialization");
        return fmi2Error;
    }
    for (i = 0; i < nvr; i++) {
        if (!isfinite(value[i])) {
            logError(e, "fmi2SetReal: value of vr %u is not finite", (unsigned)vr[i]);
            return fmi2Error;
        }
        switch (vr[i]) {
        case vrFw0: e->fw0 = value[i]; break;
        case vrN0: e->n0 = value[i]; break;
        case vrN1: e->n1 = value[i]; break;
        case vrT0: e->t0 = value[i]; break;
        case vrT1: e->t1 = value[i]; break;
        default:
            logError(e, "fmi2SetReal: vr %u is not a settable Real", (unsigned)vr[i]);
            return fmi2Error;
        }
    }
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    Excitation *e = (Excitation *)c;
    size_t i;
    if (e == NULL || (nvr > 0 && (vr == NULL || value == NULL))) {
        return fmi2Error;
    }
    if (nvr > 0 && e->phase != PhaseInstantiated && e->phase != PhaseInitialization) {
        logError(e, "fmi2SetInteger: parameters are fixed after initialization");
        return fmi2Error;
    }
    for (i = 0; i < nvr; i++) {
        if (vr[i] != vrEngineOrder || value[i] < 1 || value[i] > 100) {
            logError(e, "fmi2SetInteger: vr %u = %d is not a valid engineOrder in [1, 100]", (unsigned)vr[i],
                     (int)value[i]);
            return fmi2Error;
        }
        e->engineOrder = value[i];
    }
    return fmi2OK;
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    (void)vr;
    (void)value;
    return (c == NULL || nvr > 0) ? fmi2Error : fmi2OK;
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    (void)vr;
    (void)value;
    return (c == NULL || nvr > 0) ? fmi2Error : fmi2OK;
}

static fmi2Status unsupported(fmi2Component c, const char *function)
{
    logError((const Excitation *)c, "%s: not supported by this FMU", function);
    return fmi2Error;
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    (void)s;
    return unsupported(c, "fmi2GetFMUstate");
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s)
{
    (void)s;
    return unsupported(c, "fmi2SetFMUstate");
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s)
{
    (void)s;
    return unsupported(c, "fmi2FreeFMUstate");
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size)
{
    (void)s;
    (void)size;
    return unsupported(c, "fmi2SerializedFMUstateSize");
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte bytes[], size_t size)
{
    (void)s;
    (void)bytes;
    (void)size;
    return unsupported(c, "fmi2SerializeFMUstate");
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *s)
{
    (void)bytes;
    (void)size;
    (void)s;
    return unsupported(c, "fmi2DeSerializeFMUstate");
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown[], size_t nUnknown,
                                        const fmi2ValueReference vKnown[], size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[])
{
    (void)vUnknown;
    (void)nUnknown;
    (void)vKnown;
    (void)nKnown;
    (void)dvKnown;
    (void)dvUnknown;
    return unsupported(c, "fmi2GetDirectionalDerivative");
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2SetRealInputDerivatives");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2GetRealOutputDerivatives");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    Excitation *e = (Excitation *)c;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (e == NULL || e->phase != PhaseStep) {
        logError(e, "fmi2DoStep: Illegal call sequence");
        return fmi2Error;
    }
    if (!(communicationStepSize > 0.0) ||
        fabs(currentCommunicationPoint - e->time) > 1e-9 * (fabs(e->time) > 1.0 ? fabs(e->time) : 1.0)) {
        logError(e, "fmi2DoStep: expected t = %.17g and h > 0, got t = %.17g, h = %.17g", e->time,
                 currentCommunicationPoint, communicationStepSize);
        return fmi2Error;
    }
    e->time = currentCommunicationPoint + communicationStepSize;
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep"); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetStatus");
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    const Excitation *e = (const Excitation *)c;
    if (e == NULL || value == NULL || s != fmi2LastSuccessfulTime) {
        return unsupported(c, "fmi2GetRealStatus");
    }
    *value = e->time;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetIntegerStatus");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    const Excitation *e = (const Excitation *)c;
    if (e == NULL || value == NULL || s != fmi2Terminated) {
        return unsupported(c, "fmi2GetBooleanStatus");
    }
    *value = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetStringStatus");
}
