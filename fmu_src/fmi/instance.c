/* Generic FMU instance: lifecycle, start values from the model's table, experiment setup, the end
 * of initialization and the checks every communication step shares. No global mutable state. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fmi/build.h"
#include "fmi/instance.h"
#include "fmi/log.h"
#include "fmi/state_blob.h"

static char *copyString(const char *s)
{
    size_t n;
    char *p;
    if (s == NULL) return NULL;
    n = strlen(s);
    p = (char *)malloc(n + 1);
    if (p) memcpy(p, s, n + 1);
    return p;
}

/* n bytes zeroed (at least one: calloc(0) may return NULL) */
static void *zeroed(size_t n) { return calloc(1, n > 0 ? n : 1); }

/* memory is zeroed once here (a cache, not state: a reset keeps it) */
FmiInstance *fmiNew(const FmiModel *model, const FmiModelExchange *me, const FmiFace *face,
                    const char *instanceName, const char *resourceLocation, FmiLogSink sink, void *sinkCtx,
                    int loggingOn)
{
    FmiInstance *inst = (FmiInstance *)calloc(1, sizeof *inst);
    if (inst == NULL) {
        free(sinkCtx);
        return NULL;
    }
    inst->model = model;
    inst->me = me;
    inst->face = face;
    inst->sinkCtx = sinkCtx;
    inst->instanceName = copyString(instanceName);
    inst->resourceLocation = copyString(resourceLocation);
    inst->data = zeroed(model->dataSize);
    inst->memory = zeroed(model->memorySize);
    if (me) {
        inst->meData = zeroed(me->dataSize);
        inst->meMemory = zeroed(me->memorySize);
    }
    if (inst->instanceName == NULL || (resourceLocation != NULL && inst->resourceLocation == NULL) ||
        inst->data == NULL || inst->memory == NULL || (me && (inst->meData == NULL || inst->meMemory == NULL))) {
        fmiFree(inst);
        return NULL;
    }
    inst->magic = FMI_INSTANCE_MAGIC;
    inst->sink = sink;
    for (int k = 0; k < LOG_NUM_CATEGORIES; ++k) inst->logOn[k] = loggingOn ? 1 : 0;
    fmiReset(inst);
    return inst;
}

void fmiFree(FmiInstance *inst)
{
    if (inst == NULL) return;
    fmiStateFreeAll(inst);
    free(inst->instanceName);
    free(inst->resourceLocation);
    free(inst->data);
    free(inst->memory);
    free(inst->meData);
    free(inst->meMemory);
    free(inst->sinkCtx);
    inst->magic = 0;
    free(inst);
}

FmiInstance *fmiEnter(void *handle, const char *fn, int mask, int logCall)
{
    FmiInstance *inst = (FmiInstance *)handle;
    if (inst == NULL || inst->magic != FMI_INSTANCE_MAGIC) return NULL;
    /* (the state's name only when the call is logged: every get, set and step comes through here) */
    if (logCall && fmiLogEnabled(inst, LogCalls))
        fmiLog(inst, FmiOK, LogCalls, "%s (state: %s)", fn, inst->face->stateName(inst->fsm));
    if ((inst->fsm & mask) == 0) {
        fmiLogStatus(inst, FmiError, "%s: Illegal call sequence (state: %s)", fn, inst->face->stateName(inst->fsm));
        return NULL;
    }
    return inst;
}

/* The table's start values into the model's data (a calculated output has no storage). */
static void startValues(const FmiModel *model, void *data)
{
    for (int i = 0; i < model->nVars; ++i) {
        const VarInfo *v = &model->vars[i];
        if (v->offset < 0) continue;
        if (v->type == VarReal) *(double *)(void *)((char *)data + v->offset) = v->start;
        else *(int32_t *)(void *)((char *)data + v->offset) = (int32_t)v->start;
    }
}

void fmiReset(FmiInstance *inst)
{
    memset(inst->data, 0, inst->model->dataSize);
    if (inst->me) memset(inst->meData, 0, inst->me->dataSize);
    memset(&inst->run, 0, sizeof inst->run); /* time = startTime = 0, no stop time, last status OK */
    inst->fsm = FsmInstantiated;
    inst->built = 0;
    startValues(inst->model, inst->data);
    if (inst->model->startValues) inst->model->startValues(inst);
}

FmiStatus fmiSetupExperiment(FmiInstance *inst, const char *fn, int toleranceDefined, double tolerance,
                             double startTime, int stopTimeDefined, double stopTime)
{
    if (!isfinite(startTime)) {
        fmiLogStatus(inst, FmiError, "%s: startTime = %g s is not a finite number", fn, startTime);
        return FmiError;
    }
    if (stopTimeDefined && (!isfinite(stopTime) || stopTime < startTime)) {
        fmiLogStatus(inst, FmiError, "%s: stopTime = %g s must be finite and >= startTime = %g s", fn, stopTime,
                     startTime);
        return FmiError;
    }
    if (toleranceDefined && !(tolerance >= 0.0)) {
        fmiLogStatus(inst, FmiError, "%s: tolerance = %g must be >= 0", fn, tolerance);
        return FmiError;
    }
    /* the tolerance is not used: the models integrate with fixed steps */
    inst->run.startTime = startTime;
    inst->run.time = startTime;
    inst->run.stopTimeDefined = stopTimeDefined ? 1 : 0;
    inst->run.stopTime = stopTimeDefined ? stopTime : 0.0;
    return FmiOK;
}

FmiStatus fmiExitInitialization(FmiInstance *inst, const char *fn)
{
    FmiStatus status = fmiBuild(inst, fn, 1);
    if (status != FmiOK) return status;
    inst->run.time = inst->run.startTime;
    inst->run.initialized = 1;
    return inst->model->initialized ? inst->model->initialized(inst, fn) : FmiOK;
}

double fmiTimeTolerance(double t) { return 1e-9 * (fabs(t) > 1.0 ? fabs(t) : 1.0); }

FmiStatus fmiDoStep(FmiInstance *inst, const char *fn, double tc, double h)
{
    const double tol = fmiTimeTolerance(inst->run.time);
    FmiStatus status;
    if (!isfinite(tc) || !isfinite(h)) {
        fmiLogStatus(inst, FmiError, "%s: currentCommunicationPoint = %g s and communicationStepSize = %g s "
                     "must be finite numbers", fn, tc, h);
        return FmiError;
    }
    if (!(h > 0.0)) {
        fmiLogStatus(inst, FmiError, "%s: communicationStepSize = %g s must be > 0", fn, h);
        return FmiError;
    }
    if (tc + h == tc) {
        fmiLogStatus(inst, FmiError, "%s: communicationStepSize = %g s is below the time resolution at "
                     "t = %.17g s (t + h == t): time would not advance", fn, h, tc);
        return FmiError;
    }
    if (fabs(tc - inst->run.time) > tol) {
        fmiLogStatus(inst, FmiError, "%s: currentCommunicationPoint = %.17g s does not match the FMU time "
                     "%.17g s (tolerance %g s)", fn, tc, inst->run.time, tol);
        return FmiError;
    }
    if (inst->run.stopTimeDefined && tc + h > inst->run.stopTime + fmiTimeTolerance(inst->run.stopTime)) {
        fmiLogStatus(inst, FmiError, "%s: the step to %.17g s goes past the stop time %.17g s", fn, tc + h,
                     inst->run.stopTime);
        return FmiError;
    }
    status = inst->model->doStep(inst, fn, tc, h);
    if (status <= FmiDiscard) inst->run.lastDoStepStatus = status;
    if (status <= FmiWarning) inst->run.time = tc + h; /* the master's point plus h, never accumulated */
    return status;
}
