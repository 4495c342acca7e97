/* The FMI 2.0 model-exchange face: the fmi2* functions of section 3.2 over the model's
 * FmiModelExchange (inst->me: the same right-hand side, switching functions and event updates
 * the co-simulation integrator uses); linked only into a binary whose model has one. Call
 * sequence from the model-exchange state table (s.3.2.3): initialization ends in event mode
 * (fmi2ExitInitializationMode, fmi2_cs.c); event mode and continuous-time mode alternate. A
 * co-simulation instance refuses every function here. */
#include <math.h>

#include "fmi2Functions.h"
#include "fmi/build.h"
#include "fmi/instance.h"
#include "fmi/log.h"
#include "fmi/variables.h"

#define MASK_SetTime (FsmEventMode | FsmContinuousTimeMode)
#define MASK_SetContinuousStates FsmContinuousTimeMode
/* the getters also in initialization mode, as fmi2GetReal (FMI 2.0 s.3.2.3: the initial states,
 * derivatives and event indicators are initial unknowns) */
#define MASK_GetStates (FsmInitializationMode | FsmEventMode | FsmContinuousTimeMode | FsmTerminated | FsmError)
#define MASK_GetNominals (FsmInstantiated | MASK_GetStates)
#define MASK_EnterEventMode (FsmEventMode | FsmContinuousTimeMode)
#define MASK_NewDiscreteStates FsmEventMode
#define MASK_EnterContinuousTimeMode FsmEventMode
#define MASK_CompletedIntegratorStep FsmContinuousTimeMode

/* The instance behind c for a model-exchange call allowed in its state; else NULL (logged). */
static FmiInstance *enterME(fmi2Component c, const char *fn, int mask)
{
    FmiInstance *inst = (FmiInstance *)c;
    if (inst != NULL && inst->magic == FMI_INSTANCE_MAGIC && !inst->me) {
        fmiLog(inst, FmiOK, LogCalls, "%s (state: %s)", fn, fsmStateName(inst->fsm));
        fmiLogStatus(inst, FmiError, "%s: not available: the instance was instantiated for co-simulation "
                     "(fmuType = fmi2CoSimulation)", fn);
        return NULL;
    }
    return fmiEnter(c, fn, mask, 1);
}

/* enterME() for a function with an array of n elements: the array must not be NULL and n must be
 * the model's count of states (nz = 0) or of event indicators (nz = 1). */
static FmiInstance *enterArray(fmi2Component c, const char *fn, int mask, const void *a, size_t n, int nz)
{
    FmiInstance *inst = enterME(c, fn, mask);
    const char *what = nz ? "ni" : "nx";
    int expected;
    if (inst == NULL) return NULL;
    expected = nz ? inst->me->nz : inst->me->nx;
    if (n != (size_t)expected) {
        fmiLogStatus(inst, FmiError, "%s: %s = %lu, but this FMU has %d", fn, what, (unsigned long)n, expected);
        return NULL;
    }
    if (a == NULL && n > 0) {
        fmiLogStatus(inst, FmiError, "%s: NULL array argument with %s = %lu", fn, what, (unsigned long)n);
        return NULL;
    }
    /* the model's data follow the parameters (in initialization mode: the state follows the start
     * values, as for fmi2GetReal; after a deserialized FMU state: the derived data) */
    if (mask != MASK_GetNominals && fmiEnsureBuilt(inst, fn) != FmiOK) return NULL;
    return inst;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    const char *fn = "fmi2SetTime";
    FmiInstance *inst = enterME(c, fn, MASK_SetTime);
    if (inst == NULL) return fmi2Error;
    if (!isfinite(time)) {
        fmiLogStatus(inst, FmiError, "%s: time = %g s is not a finite number", fn, time);
        return fmi2Error;
    }
    inst->run.time = time;
    return fmi2OK;
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{
    const char *fn = "fmi2SetContinuousStates";
    FmiInstance *inst = enterArray(c, fn, MASK_SetContinuousStates, x, nx, 0);
    if (inst == NULL) return fmi2Error;
    for (size_t i = 0; i < nx; ++i) {
        if (!isfinite(x[i])) {
            fmiLogStatus(inst, FmiDiscard, "%s: x[%lu] = %g is not finite at t = %.17g s; the states are "
                         "unchanged", fn, (unsigned long)i, x[i], inst->run.time);
            return fmi2Discard;
        }
    }
    inst->me->setStates(inst, x);
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{
    const char *fn = "fmi2GetDerivatives";
    FmiInstance *inst = enterArray(c, fn, MASK_GetStates, derivatives, nx, 0);
    if (inst == NULL) return fmi2Error;
    return (fmi2Status)inst->me->derivatives(inst, fn, derivatives);
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni)
{
    const char *fn = "fmi2GetEventIndicators";
    FmiInstance *inst = enterArray(c, fn, MASK_GetStates, eventIndicators, ni, 1);
    if (inst == NULL) return fmi2Error;
    return (fmi2Status)inst->me->eventIndicators(inst, fn, eventIndicators);
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    const char *fn = "fmi2GetContinuousStates";
    FmiInstance *inst = enterArray(c, fn, MASK_GetStates, x, nx, 0);
    if (inst == NULL) return fmi2Error;
    inst->me->getStates(inst, x);
    return fmi2OK;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    const char *fn = "fmi2GetNominalsOfContinuousStates";
    FmiInstance *inst = enterArray(c, fn, MASK_GetNominals, x_nominal, nx, 0);
    if (inst == NULL) return fmi2Error;
    inst->me->nominals(inst, x_nominal);
    return fmi2OK;
}

fmi2Status fmi2EnterEventMode(fmi2Component c)
{
    FmiInstance *inst = enterME(c, "fmi2EnterEventMode", MASK_EnterEventMode);
    if (inst == NULL) return fmi2Error;
    inst->fsm = FsmEventMode;
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *eventInfo)
{
    const char *fn = "fmi2NewDiscreteStates";
    FmiInstance *inst = enterME(c, fn, MASK_NewDiscreteStates);
    int changed = 0;
    FmiStatus status;
    if (inst == NULL) return fmi2Error;
    if (eventInfo == NULL) {
        fmiLogStatus(inst, FmiError, "%s: fmi2eventInfo is NULL", fn);
        return fmi2Error;
    }
    if (fmiEnsureBuilt(inst, fn) != FmiOK) return fmi2Error;
    /* the model iterates to the end in one call; no time events (the period ends are state
     * events of the excitation phase, which follows the rotorSpeed input) */
    status = inst->me->eventUpdate(inst, fn, &changed);
    eventInfo->newDiscreteStatesNeeded = fmi2False;
    eventInfo->terminateSimulation = fmi2False;
    eventInfo->nominalsOfContinuousStatesChanged = fmi2False;
    eventInfo->valuesOfContinuousStatesChanged = changed ? fmi2True : fmi2False;
    eventInfo->nextEventTimeDefined = fmi2False;
    eventInfo->nextEventTime = 0.0;
    if (status > FmiWarning) inst->fsm = FsmError;
    return (fmi2Status)status;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    FmiInstance *inst = enterME(c, "fmi2EnterContinuousTimeMode", MASK_EnterContinuousTimeMode);
    if (inst == NULL) return fmi2Error;
    inst->fsm = FsmContinuousTimeMode;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation)
{
    const char *fn = "fmi2CompletedIntegratorStep";
    FmiInstance *inst = enterME(c, fn, MASK_CompletedIntegratorStep);
    (void)noSetFMUStatePriorToCurrentPoint;
    if (inst == NULL) return fmi2Error;
    if (enterEventMode == NULL || terminateSimulation == NULL) {
        fmiLogStatus(inst, FmiError, "%s: enterEventMode or terminateSimulation is NULL", fn);
        return fmi2Error;
    }
    /* every switch has an event indicator: no step events */
    *enterEventMode = fmi2False;
    *terminateSimulation = fmi2False;
    return fmi2OK;
}
