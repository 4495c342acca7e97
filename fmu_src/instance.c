/* ShroudedBlade FMU instance: parameters and their validation, initialization, the communication
 * step, FMU state copies and their serialization (see instance.h). No global mutable state:
 * the tables below are const. */
#include "instance.h"

#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"

/* ------------------------------------------------------------------------------------------- */
/* Names                                                                                        */

const char *fsmStateName(int32_t state)
{
    switch (state) {
    case FsmStartEnd: return "startAndEnd";
    case FsmInstantiated: return "instantiated";
    case FsmInitializationMode: return "initializationMode";
    case FsmStepComplete: return "stepComplete";
    case FsmStepInProgress: return "stepInProgress";
    case FsmStepFailed: return "stepFailed";
    case FsmStepCanceled: return "stepCanceled";
    case FsmTerminated: return "terminated";
    case FsmError: return "error";
    case FsmFatal: return "fatal";
    default: return "unknown";
    }
}

static const char *const CATEGORY_NAMES[LOG_NUM_CATEGORIES] = {
    "logEvents", "logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
    "logAll", "logCalls"};

const char *logCategoryName(int category)
{
    return (category >= 0 && category < LOG_NUM_CATEGORIES) ? CATEGORY_NAMES[category] : "logAll";
}

/* ------------------------------------------------------------------------------------------- */
/* Variable table (modelDescription.xml; bounds as harness/params.py: open where the quantity must
 * be strictly positive)                                                                        */

typedef enum { TypeReal, TypeInteger, TypeBoolean } VarType;
typedef enum { CausParameter, CausInput, CausOutput } Causality;
typedef enum {
    OutQ = 0, OutV, OutNormalForce, OutFrictionForce, OutKeq, OutCeq, OutAmplitude, OutEnergy,
    OutFrequency, OutRegime, OutContactState
} OutputId;

typedef struct {
    fmi2ValueReference vr;
    const char *name;
    VarType type;
    Causality causality;
    const char *unit;   /* "" if dimensionless */
    double start;
    double lo, hi;      /* allowed range */
    int loOpen, hiOpen; /* 1: the bound itself is excluded */
    int slot;           /* RealParam, IntParam, input index or OutputId */
    int startSlot;      /* RealParam holding the start value of an initial="exact" output, or -1 */
} VarInfo;

#define INF HUGE_VAL
#define HALF_PI 1.5707963267948966

static const VarInfo VARS[] = {
    {vr_EI, "EI", TypeReal, CausParameter, "N.m2", 343.0, 0.0, INF, 1, 0, ParEI, -1},
    {vr_rho, "rho", TypeReal, CausParameter, "kg/m3", 7800.0, 0.0, INF, 1, 0, ParRho, -1},
    {vr_A, "A", TypeReal, CausParameter, "m2", 4.2e-4, 0.0, INF, 1, 0, ParA, -1},
    {vr_l, "l", TypeReal, CausParameter, "m", 0.15, 0.0, INF, 1, 0, ParL, -1},
    {vr_c, "c", TypeReal, CausParameter, "N.s/m2", 29.8, 0.0, INF, 0, 0, ParC, -1},
    {vr_m0, "m0", TypeReal, CausParameter, "kg", 0.025, 0.0, INF, 0, 0, ParM0, -1},
    {vr_kn, "kn", TypeReal, CausParameter, "N/m", 1e7, 0.0, INF, 1, 0, ParKn, -1},
    {vr_kdRatio, "kdRatio", TypeReal, CausParameter, "", 0.608695652173913, 0.0, INF, 1, 0, ParKdRatio, -1},
    {vr_mu, "mu", TypeReal, CausParameter, "", 0.33, 0.0, INF, 0, 0, ParMu, -1},
    {vr_gamma, "gamma", TypeReal, CausParameter, "rad", 1.0471975511965976, 0.0, HALF_PI, 1, 1, ParGamma, -1},
    {vr_d, "d", TypeReal, CausParameter, "m", 3e-5, 0.0, INF, 0, 0, ParD, -1},
    {vr_B, "B", TypeReal, CausParameter, "m", 6e-5, 0.0, INF, 1, 0, ParB, -1},
    {vr_maxStep, "maxStep", TypeReal, CausParameter, "s", 1e-5, 1e-8, 1e-3, 0, 0, ParMaxStep, -1},
    {vr_frictionModel, "frictionModel", TypeInteger, CausParameter, "", 1, 1, 3, 0, 0, IparFrictionModel, -1},
    {vr_formulation, "formulation", TypeInteger, CausParameter, "", 1, 1, 2, 0, 0, IparFormulation, -1},
    {vr_projection, "projection", TypeInteger, CausParameter, "", 1, 1, 2, 0, 0, IparProjection, -1},
    {vr_amplitudeMode, "amplitudeMode", TypeInteger, CausParameter, "", 2, 1, 2, 0, 0, IparAmplitudeMode, -1},
    {vr_engineOrder, "engineOrder", TypeInteger, CausParameter, "", 3, 1, 100, 0, 0, IparEngineOrder, -1},
    {vr_gating, "gating", TypeBoolean, CausParameter, "", 1, 0, 1, 0, 0, IparGating, -1},
    {vr_aeroLoad, "aeroLoad", TypeReal, CausInput, "N/m", 0.0, -INF, INF, 0, 0, SOLVER_INPUT_AERO, -1},
    {vr_rotorSpeed, "rotorSpeed", TypeReal, CausInput, "rpm", 5000.0, 0.0, 30000.0, 0, 0, SOLVER_INPUT_SPEED, -1},
    {vr_tipDisplacement, "tipDisplacement", TypeReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, OutQ, ParQ0},
    {vr_tipVelocity, "tipVelocity", TypeReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, OutV, ParV0},
    {vr_normalForce, "normalForce", TypeReal, CausOutput, "N", 0.0, -INF, INF, 0, 0, OutNormalForce, -1},
    {vr_frictionForce, "frictionForce", TypeReal, CausOutput, "N", 0.0, -INF, INF, 0, 0, OutFrictionForce, -1},
    {vr_Keq, "Keq", TypeReal, CausOutput, "N/m", 0.0, -INF, INF, 0, 0, OutKeq, -1},
    {vr_Ceq, "Ceq", TypeReal, CausOutput, "N.s/m", 0.0, -INF, INF, 0, 0, OutCeq, -1},
    {vr_amplitude, "amplitude", TypeReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, OutAmplitude, -1},
    {vr_dissipatedEnergy, "dissipatedEnergy", TypeReal, CausOutput, "J", 0.0, -INF, INF, 0, 0, OutEnergy, ParE0},
    {vr_naturalFrequency, "naturalFrequency", TypeReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, OutFrequency, -1},
    {vr_regime, "regime", TypeInteger, CausOutput, "", 0, -INF, INF, 0, 0, OutRegime, -1},
    {vr_contactState, "contactState", TypeInteger, CausOutput, "", 0, -INF, INF, 0, 0, OutContactState, -1},
};
#define NUM_VARS ((int)(sizeof VARS / sizeof VARS[0]))

static const VarInfo *findVar(fmi2ValueReference vr)
{
    for (int i = 0; i < NUM_VARS; ++i)
        if (VARS[i].vr == vr) return &VARS[i];
    return NULL;
}

const char *instanceVariableName(fmi2ValueReference vr)
{
    const VarInfo *v = findVar(vr);
    return v ? v->name : NULL;
}

static const char *typeName(VarType t)
{
    return t == TypeReal ? "Real" : (t == TypeInteger ? "Integer" : "Boolean");
}

static int inRange(const VarInfo *v, double x)
{
    if (!isfinite(x)) return 0;
    if (x < v->lo || (v->loOpen && x == v->lo)) return 0;
    if (x > v->hi || (v->hiOpen && x == v->hi)) return 0;
    return 1;
}

static void rangeText(const VarInfo *v, char *buf, size_t n)
{
    char lo[40], hi[40];
    if (v->type == TypeBoolean) {
        snprintf(buf, n, "{false, true}");
        return;
    }
    if (isinf(v->lo)) snprintf(lo, sizeof lo, "(-inf");
    else snprintf(lo, sizeof lo, "%c%g", v->loOpen ? '(' : '[', v->lo);
    if (isinf(v->hi)) snprintf(hi, sizeof hi, "inf)");
    else snprintf(hi, sizeof hi, "%g%c", v->hi, v->hiOpen ? ')' : ']');
    snprintf(buf, n, "%s, %s", lo, hi);
}

/* ------------------------------------------------------------------------------------------- */
/* Logging                                                                                      */

int instanceLogEnabled(const Instance *inst, int category)
{
    if (inst == NULL || inst->logger == NULL) return 0;
    if (category < 0 || category >= LOG_NUM_CATEGORIES) return 0;
    return inst->logOn[category] || inst->logOn[LogAll];
}

static void emit(Instance *inst, fmi2Status status, int category, const char *fmt, va_list ap)
{
    size_t j = 0;
    vsnprintf(inst->message, sizeof inst->message, fmt, ap);
    /* the logger's message is a printf format: escape '%' */
    for (size_t i = 0; inst->message[i] != '\0' && j + 2 < sizeof inst->escaped; ++i) {
        if (inst->message[i] == '%') inst->escaped[j++] = '%';
        inst->escaped[j++] = inst->message[i];
    }
    inst->escaped[j] = '\0';
    inst->logger(inst->componentEnvironment, inst->instanceName, status, logCategoryName(category),
                 inst->escaped);
}

void instanceLog(Instance *inst, fmi2Status status, int category, const char *fmt, ...)
{
    va_list ap;
    if (!instanceLogEnabled(inst, category)) return;
    va_start(ap, fmt);
    emit(inst, status, category, fmt, ap);
    va_end(ap);
}

static int statusCategory(fmi2Status status)
{
    switch (status) {
    case fmi2Warning: return LogStatusWarning;
    case fmi2Discard: return LogStatusDiscard;
    case fmi2Error: return LogStatusError;
    case fmi2Fatal: return LogStatusFatal;
    default: return LogEvents;
    }
}

void instanceLogStatus(Instance *inst, fmi2Status status, const char *fmt, ...)
{
    va_list ap;
    const int category = statusCategory(status);
    if (!instanceLogEnabled(inst, category)) return;
    va_start(ap, fmt);
    emit(inst, status, category, fmt, ap);
    va_end(ap);
}

/* ------------------------------------------------------------------------------------------- */
/* Start values, lifecycle                                                                      */

static void refreshInputs(Instance *inst) { solverSetInputs(&inst->inputs, (const double(*)[SOLVER_MAX_ORDER + 1])inst->d.in); }

static void setStartValues(Instance *inst)
{
    InstanceData *d = &inst->d;
    memset(d, 0, sizeof *d);
    d->fsm = FsmInstantiated;
    for (int i = 0; i < NUM_VARS; ++i) {
        const VarInfo *v = &VARS[i];
        if (v->causality == CausParameter && v->type == TypeReal) d->par[v->slot] = v->start;
        else if (v->causality == CausParameter) d->ipar[v->slot] = (int32_t)v->start;
        else if (v->causality == CausInput) d->in[v->slot][0] = v->start;
        else if (v->startSlot >= 0) d->par[v->startSlot] = v->start;
    }
    d->time = 0.0;
    d->startTime = 0.0;
    d->stopTime = 0.0;
    d->stopTimeDefined = 0;
    d->lastDoStepStatus = fmi2OK;
    d->warnedFullStick = 0;
    d->modelValid = 0;
    d->solver.B = d->par[ParB]; /* rebuilt by fmi2ExitInitializationMode; consistent until then */
    d->solver.side = d->solver.slipDir = d->solver.vdir = 1;
    refreshInputs(inst);
}

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

Instance *instanceNew(const char *instanceName, const char *resourceLocation,
                      fmi2CallbackLogger logger, fmi2ComponentEnvironment env, int loggingOn)
{
    Instance *inst = (Instance *)calloc(1, sizeof *inst);
    if (inst == NULL) return NULL;
    inst->magic = INSTANCE_MAGIC;
    inst->instanceName = copyString(instanceName);
    inst->resourceLocation = copyString(resourceLocation);
    if (inst->instanceName == NULL || (resourceLocation != NULL && inst->resourceLocation == NULL)) {
        free(inst->instanceName);
        free(inst->resourceLocation);
        free(inst);
        return NULL;
    }
    inst->logger = logger;
    inst->componentEnvironment = env;
    for (int k = 0; k < LOG_NUM_CATEGORIES; ++k) inst->logOn[k] = loggingOn ? 1 : 0;
    setStartValues(inst);
    return inst;
}

/* ------------------------------------------------------------------------------------------- */
/* FMU state objects                                                                            */

#define BLOB_MAGIC 0x53426c6164655331ULL /* "SBladeS1" */

struct StateBlob {
    uint64_t magic;
    Instance *owner; /* the instance whose list holds this blob */
    StateBlob *prev, *next;
    InstanceData d;
};

static void unlinkBlob(StateBlob *b)
{
    if (b->owner) {
        if (b->prev) b->prev->next = b->next;
        else b->owner->states = b->next;
        if (b->next) b->next->prev = b->prev;
    }
    b->owner = NULL;
    b->prev = b->next = NULL;
}

static StateBlob *newBlob(Instance *inst)
{
    StateBlob *b = (StateBlob *)calloc(1, sizeof *b);
    if (b == NULL) return NULL;
    b->magic = BLOB_MAGIC;
    b->owner = inst;
    b->next = inst->states;
    if (inst->states) inst->states->prev = b;
    inst->states = b;
    return b;
}

void instanceFree(Instance *inst)
{
    if (inst == NULL) return;
    while (inst->states) {
        StateBlob *b = inst->states;
        unlinkBlob(b);
        b->magic = 0;
        free(b);
    }
    free(inst->instanceName);
    free(inst->resourceLocation);
    inst->magic = 0;
    free(inst);
}

void instanceReset(Instance *inst) { setStartValues(inst); }

/* ------------------------------------------------------------------------------------------- */
/* Model construction                                                                           */

/* Builds blade reduction and solver model from the parameters; if initState, also the initial
 * solver state (q0, v0, E0, B). Logs and returns fmi2Error on failure. */
static fmi2Status buildModel(Instance *inst, const char *fn, int initState)
{
    InstanceData *d = &inst->d;
    const double *p = d->par;
    BladeParams bp;
    ContactParams cp;
    SolverStatus st;
    d->modelValid = 0;
    bp.EI = p[ParEI];
    bp.rho = p[ParRho];
    bp.A = p[ParA];
    bp.l = p[ParL];
    bp.c = p[ParC];
    bp.m0 = p[ParM0];
    if (bladeReduce(&bp, (Formulation)d->ipar[IparFormulation], &d->blade) != 0 ||
        !(d->blade.M > 0.0) || !isfinite(d->blade.M) || !isfinite(d->blade.C0) ||
        !(d->blade.K0static > 0.0) || !isfinite(d->blade.K0static) || !isfinite(d->blade.K0omega2) ||
        !isfinite(d->blade.loadGain)) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: the Galerkin reduction (eq. 19-26) failed for EI = %g N.m2, rho = %g kg/m3, "
                          "A = %g m2, l = %g m, c = %g N.s/m2, m0 = %g kg, formulation = %d "
                          "(M = %g kg, K0 = %g N/m): the blade parameters are not usable together",
                          fn, bp.EI, bp.rho, bp.A, bp.l, bp.c, bp.m0, (int)d->ipar[IparFormulation],
                          d->blade.M, d->blade.K0static);
        return fmi2Error;
    }
    cp.kn = p[ParKn];
    cp.kdRatio = p[ParKdRatio];
    cp.mu = p[ParMu];
    cp.gamma = p[ParGamma];
    cp.d = p[ParD];
    if (!contactParamsValid(&cp) ||
        solverBuildModel(&d->model, &d->blade, &cp, (FrictionModel)d->ipar[IparFrictionModel],
                         (Projection)d->ipar[IparProjection], d->ipar[IparGating] != 0,
                         d->ipar[IparAmplitudeMode] == 2, d->ipar[IparEngineOrder]) != 0) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: the contact parameters kn = %g N/m, kdRatio = %g, mu = %g, gamma = %g rad, "
                          "d = %g m are not usable together", fn, cp.kn, cp.kdRatio, cp.mu, cp.gamma, cp.d);
        return fmi2Error;
    }
    if (initState) {
        st = solverInitState(&d->model, &d->solver, p[ParQ0], p[ParV0], p[ParE0], p[ParB]);
    } else {
        st = solverUpdateDescribe(&d->model, &d->solver);
    }
    if (st != SolverOk) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: the describing function (eq. 7-13) failed for B = %g m (d = %g m, kn = %g N/m, "
                          "kdRatio = %g, mu = %g, gamma = %g rad)", fn, d->solver.B, cp.d, cp.kn,
                          cp.kdRatio, cp.mu, cp.gamma);
        return fmi2Error;
    }
    d->modelValid = 1;
    return fmi2OK;
}

static int preInit(const InstanceData *d)
{
    return d->fsm == FsmInstantiated || d->fsm == FsmInitializationMode;
}

/* The model is needed to evaluate outputs; before initialization it follows the parameters. */
static fmi2Status ensureModel(Instance *inst, const char *fn)
{
    if (inst->d.modelValid) return fmi2OK;
    return buildModel(inst, fn, preInit(&inst->d));
}

static fmi2Status warnFullStickOnce(Instance *inst, const char *fn)
{
    InstanceData *d = &inst->d;
    if (d->warnedFullStick || d->solver.df.regime != RegimeFullStick) return fmi2OK;
    d->warnedFullStick = 1;
    instanceLogStatus(inst, fmi2Warning,
                      "%s: full-stick regime (MODEL.md s.3): kd tan(gamma) = %g N/m < mu kn = %g N/m, the "
                      "macroslip loop never slips; f_c = 0 and f_k = (kd tan(gamma)/kn) p_k are used "
                      "(B = %g m)", fn, d->model.kd * tan(d->par[ParGamma]),
                      d->par[ParMu] * d->par[ParKn], d->solver.B);
    return fmi2Warning;
}

/* ------------------------------------------------------------------------------------------- */
/* Get / Set                                                                                    */

static double outputValue(const Instance *inst, const VarInfo *v, const SolverOutputs *o)
{
    const SolverState *s = &inst->d.solver;
    switch ((OutputId)v->slot) {
    case OutQ: return s->q;
    case OutV: return s->v;
    case OutNormalForce: return o->normalForce;
    case OutFrictionForce: return o->frictionForce;
    case OutKeq: return o->Keq;
    case OutCeq: return o->Ceq;
    case OutAmplitude: return s->B;
    case OutEnergy: return s->E;
    case OutFrequency: return o->naturalFrequency;
    case OutRegime: return (double)o->regime;
    case OutContactState: return (double)o->contactState;
    }
    return 0.0;
}

/* Value of any variable as a double; o holds the outputs (read only for outputs). */
static double variableValue(const Instance *inst, const VarInfo *v, const SolverOutputs *o)
{
    const InstanceData *d = &inst->d;
    switch (v->causality) {
    case CausParameter: return v->type == TypeReal ? d->par[v->slot] : (double)d->ipar[v->slot];
    case CausInput: return d->in[v->slot][0];
    default: return outputValue(inst, v, o);
    }
}

/* Looks up vr, checks its type; logs and returns NULL if unknown or of another type. */
static const VarInfo *lookup(Instance *inst, const char *fn, fmi2ValueReference vr, VarType type)
{
    const VarInfo *v = findVar(vr);
    if (v == NULL) {
        instanceLogStatus(inst, fmi2Error, "%s: unknown value reference %u", fn, (unsigned)vr);
        return NULL;
    }
    if (v->type != type) {
        instanceLogStatus(inst, fmi2Error, "%s: %s (vr %u) is of type %s, not %s", fn, v->name,
                          (unsigned)vr, typeName(v->type), typeName(type));
        return NULL;
    }
    return v;
}

/* Element i of a caller's fmi2Real/fmi2Integer/fmi2Boolean array, read or written as a double. */
static double readValue(VarType type, const void *values, size_t i)
{
    switch (type) {
    case TypeReal: return ((const fmi2Real *)values)[i];
    case TypeInteger: return (double)((const fmi2Integer *)values)[i];
    default: return ((const fmi2Boolean *)values)[i] ? 1.0 : 0.0; /* any nonzero is true */
    }
}

static void writeValue(VarType type, void *values, size_t i, double x)
{
    switch (type) {
    case TypeReal: ((fmi2Real *)values)[i] = x; break;
    case TypeInteger: ((fmi2Integer *)values)[i] = (fmi2Integer)x; break;
    default: ((fmi2Boolean *)values)[i] = x != 0.0 ? fmi2True : fmi2False; break;
    }
}

/* Unknown or mistyped references give 0 and fmi2Error, the others are still read. */
static fmi2Status getValues(Instance *inst, const char *fn, const fmi2ValueReference vr[],
                            size_t nvr, VarType type, void *out)
{
    fmi2Status status = fmi2OK;
    SolverOutputs o;
    int haveOutputs = 0;
    memset(&o, 0, sizeof o);
    for (size_t i = 0; i < nvr; ++i) {
        const VarInfo *v = lookup(inst, fn, vr[i], type);
        if (v == NULL) {
            status = fmi2Error;
            writeValue(type, out, i, 0.0);
            continue;
        }
        if (v->causality == CausOutput && !haveOutputs) {
            if (ensureModel(inst, fn) != fmi2OK) return fmi2Error;
            solverOutputs(&inst->d.model, &inst->d.solver, inst->d.in[SOLVER_INPUT_SPEED][0], &o);
            haveOutputs = 1;
        }
        writeValue(type, out, i, variableValue(inst, v, &o));
    }
    return status;
}

fmi2Status instanceGetReal(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    return getValues(inst, fn, vr, nvr, TypeReal, value);
}

fmi2Status instanceGetInteger(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    return getValues(inst, fn, vr, nvr, TypeInteger, value);
}

fmi2Status instanceGetBoolean(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    return getValues(inst, fn, vr, nvr, TypeBoolean, value);
}

/* May v be set now? Logs and returns 0 if not. */
static int settable(Instance *inst, const char *fn, const VarInfo *v)
{
    const int32_t fsm = inst->d.fsm;
    const int before = preInit(&inst->d);
    if (v->causality == CausInput) return 1; /* the call-sequence mask already restricts states */
    if (v->causality == CausParameter) {
        if (before) return 1;
        instanceLogStatus(inst, fmi2Error,
                          "%s: parameter %s (vr %u) has variability fixed: it can be set only before "
                          "fmi2ExitInitializationMode (state: %s)", fn, v->name, (unsigned)v->vr,
                          fsmStateName(fsm));
        return 0;
    }
    if (v->startSlot >= 0 && before) return 1; /* initial="exact" output: its start value */
    if (v->startSlot >= 0) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: output %s (vr %u) can be set (its start value) only before "
                          "fmi2ExitInitializationMode (state: %s)", fn, v->name, (unsigned)v->vr,
                          fsmStateName(fsm));
    } else {
        instanceLogStatus(inst, fmi2Error, "%s: %s (vr %u) is a calculated output and cannot be set",
                          fn, v->name, (unsigned)v->vr);
    }
    return 0;
}

/* Validates x for v; logs (naming variable, value, allowed range) and returns 0 if invalid. */
static int validValue(Instance *inst, const char *fn, const VarInfo *v, double x)
{
    char range[96];
    const char *sp = v->unit[0] ? " " : "";
    if (inRange(v, x)) return 1;
    rangeText(v, range, sizeof range);
    if (!isfinite(x)) {
        instanceLogStatus(inst, fmi2Error, "%s: %s = %g%s%s is not a finite number; allowed range %s%s%s", fn,
                          v->name, x, sp, v->unit, range, sp, v->unit);
    } else if (v->type == TypeReal) {
        instanceLogStatus(inst, fmi2Error, "%s: %s = %g%s%s is out of range %s", fn, v->name, x, sp,
                          v->unit, range);
    } else {
        instanceLogStatus(inst, fmi2Error, "%s: %s = %.0f is out of range %s", fn, v->name, x, range);
    }
    return 0;
}

static void applyValue(Instance *inst, const VarInfo *v, double x)
{
    InstanceData *d = &inst->d;
    switch (v->causality) {
    case CausParameter:
        if (v->type == TypeReal) d->par[v->slot] = x;
        else d->ipar[v->slot] = (int32_t)x;
        d->modelValid = 0;
        break;
    case CausInput:
        /* model-notes s.1: setting a value resets the derivatives of that input */
        d->in[v->slot][0] = x;
        for (int j = 1; j <= SOLVER_MAX_ORDER; ++j) d->in[v->slot][j] = 0.0;
        break;
    default:
        d->par[v->startSlot] = x;
        d->modelValid = 0;
        break;
    }
}

/* Atomic: every value is validated before any is applied. */
static fmi2Status setValues(Instance *inst, const char *fn, const fmi2ValueReference vr[],
                            size_t nvr, VarType type, const void *values)
{
    int anyInput = 0;
    for (size_t i = 0; i < nvr; ++i) {
        const VarInfo *v = lookup(inst, fn, vr[i], type);
        if (v == NULL || !settable(inst, fn, v) || !validValue(inst, fn, v, readValue(type, values, i)))
            return fmi2Error;
    }
    for (size_t i = 0; i < nvr; ++i) {
        const VarInfo *v = findVar(vr[i]);
        applyValue(inst, v, readValue(type, values, i));
        anyInput |= v->causality == CausInput;
    }
    if (anyInput) refreshInputs(inst);
    return fmi2OK;
}

fmi2Status instanceSetReal(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    return setValues(inst, fn, vr, nvr, TypeReal, value);
}

fmi2Status instanceSetInteger(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    return setValues(inst, fn, vr, nvr, TypeInteger, value);
}

fmi2Status instanceSetBoolean(Instance *inst, const char *fn, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    return setValues(inst, fn, vr, nvr, TypeBoolean, value);
}

fmi2Status instanceSetInputDerivatives(Instance *inst, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    const char *fn = "fmi2SetRealInputDerivatives";
    for (size_t i = 0; i < nvr; ++i) {
        const VarInfo *v = findVar(vr[i]);
        if (v == NULL) {
            instanceLogStatus(inst, fmi2Error, "%s: unknown value reference %u", fn, (unsigned)vr[i]);
            return fmi2Error;
        }
        if (v->causality != CausInput) {
            instanceLogStatus(inst, fmi2Error,
                              "%s: %s (vr %u) is not an input: derivatives can be set only for aeroLoad "
                              "(vr %d) and rotorSpeed (vr %d)", fn, v->name, (unsigned)vr[i],
                              vr_aeroLoad, vr_rotorSpeed);
            return fmi2Error;
        }
        if (order[i] < 1 || order[i] > SOLVER_MAX_ORDER) {
            instanceLogStatus(inst, fmi2Error, "%s: derivative order %d of %s is out of range [1, %d]", fn,
                              (int)order[i], v->name, SOLVER_MAX_ORDER);
            return fmi2Error;
        }
        if (!isfinite(value[i])) {
            instanceLogStatus(inst, fmi2Error, "%s: derivative of order %d of %s = %g is not a finite number",
                              fn, (int)order[i], v->name, value[i]);
            return fmi2Error;
        }
    }
    for (size_t i = 0; i < nvr; ++i) inst->d.in[findVar(vr[i])->slot][order[i]] = value[i];
    refreshInputs(inst);
    return fmi2OK;
}

/* ------------------------------------------------------------------------------------------- */
/* Experiment, initialization                                                                   */

fmi2Status instanceSetupExperiment(Instance *inst, int toleranceDefined, double tolerance,
                                   double startTime, int stopTimeDefined, double stopTime)
{
    const char *fn = "fmi2SetupExperiment";
    if (!isfinite(startTime)) {
        instanceLogStatus(inst, fmi2Error, "%s: startTime = %g s is not a finite number", fn, startTime);
        return fmi2Error;
    }
    if (stopTimeDefined && (!isfinite(stopTime) || stopTime < startTime)) {
        instanceLogStatus(inst, fmi2Error, "%s: stopTime = %g s must be finite and >= startTime = %g s", fn,
                          stopTime, startTime);
        return fmi2Error;
    }
    if (toleranceDefined && !(tolerance >= 0.0)) {
        instanceLogStatus(inst, fmi2Error, "%s: tolerance = %g must be >= 0", fn, tolerance);
        return fmi2Error;
    }
    /* the tolerance is not used: the fixed-step RK4 error is set by maxStep */
    inst->d.startTime = startTime;
    inst->d.time = startTime;
    inst->d.stopTimeDefined = stopTimeDefined ? 1 : 0;
    inst->d.stopTime = stopTimeDefined ? stopTime : 0.0;
    return fmi2OK;
}

fmi2Status instanceExitInitialization(Instance *inst)
{
    const char *fn = "fmi2ExitInitializationMode";
    fmi2Status status = buildModel(inst, fn, 1);
    if (status != fmi2OK) return status;
    inst->d.time = inst->d.startTime;
    refreshInputs(inst);
    return warnFullStickOnce(inst, fn);
}

/* ------------------------------------------------------------------------------------------- */
/* The communication step                                                                       */

static const char *contactName(int mode)
{
    return mode == ContactStick ? "stick" : (mode == ContactSlip ? "slip" : "open");
}

static const char *regimeName(int regime)
{
    return regime == RegimeStickSlip ? "stickSlip" : (regime == RegimeFullStick ? "fullStick" : "open");
}

/* logEvents: contact transitions and amplitude updates (only installed when enabled). */
static void eventHook(void *ctx, SolverEventKind kind, double t, const SolverState *s)
{
    Instance *inst = (Instance *)ctx;
    switch (kind) {
    case SolverEventGateOn:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: |q| > d, side %+d: K_eq = %g N/m and C_eq act (eq. 12-13)",
                    t, (int)s->side, s->df.Keq);
        break;
    case SolverEventGateOff:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: |q| <= d: K_eq and C_eq off (eq. 12-13)", t);
        break;
    case SolverEventContact:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: contact on side %+d: open -> %s", t, (int)s->side,
                    contactName(s->mode));
        break;
    case SolverEventSeparate:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: separation: -> open", t);
        break;
    case SolverEventStickToSlip:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: stick -> slip (s = %+d)", t, (int)s->slipDir);
        break;
    case SolverEventSlipToStick:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: slip -> stick", t);
        break;
    case SolverEventPeriodEnd:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: excitation period %.0f ended: amplitude B = %.9g m (regime %s)",
                    t, s->periods, s->B, regimeName(s->df.regime));
        break;
    default:
        break;
    }
}

/* Moves the Taylor expansion of the inputs from tau = 0 to tau = h (the next communication
 * point), so an input that is not set again continues as the same polynomial. */
static void shiftInputs(Instance *inst, double h)
{
    for (int i = 0; i < SOLVER_NUM_INPUTS; ++i) {
        double c[SOLVER_MAX_ORDER + 1];
        const int top = inst->inputs.top[i];
        double fact = 1.0;
        memcpy(c, inst->inputs.coef[i], sizeof c);
        for (int j = 0; j < top; ++j) /* repeated synthetic division: Taylor shift */
            for (int k = top - 1; k >= j; --k) c[k] += h * c[k + 1];
        for (int j = 0; j <= SOLVER_MAX_ORDER; ++j) {
            if (j > 0) fact *= (double)j;
            inst->d.in[i][j] = j <= top ? c[j] * fact : 0.0;
        }
        inst->d.in[i][0] = solverInputAt(&inst->inputs, i, h); /* exactly the value checked */
    }
    refreshInputs(inst);
}

#define MAX_INTERNAL_STEPS 1e7

fmi2Status instanceDoStep(Instance *inst, double tc, double h)
{
    const char *fn = "fmi2DoStep";
    InstanceData *d = &inst->d;
    const double tol = 1e-9 * (fabs(d->time) > 1.0 ? fabs(d->time) : 1.0);
    double ratio, n0, n1, tFail = 0.0;
    long nSteps;
    SolverState backup;
    SolverStatus st;
    if (!isfinite(tc) || !isfinite(h)) {
        instanceLogStatus(inst, fmi2Error, "%s: currentCommunicationPoint = %g s and communicationStepSize = %g s "
                          "must be finite numbers", fn, tc, h);
        return fmi2Error;
    }
    if (!(h > 0.0)) {
        instanceLogStatus(inst, fmi2Error, "%s: communicationStepSize = %g s must be > 0", fn, h);
        return fmi2Error;
    }
    if (fabs(tc - d->time) > tol) {
        instanceLogStatus(inst, fmi2Error, "%s: currentCommunicationPoint = %.17g s does not match the FMU time "
                          "%.17g s (tolerance %g s)", fn, tc, d->time, tol);
        return fmi2Error;
    }
    if (d->stopTimeDefined && tc + h > d->stopTime + 1e-9 * (fabs(d->stopTime) > 1.0 ? fabs(d->stopTime) : 1.0)) {
        instanceLogStatus(inst, fmi2Error, "%s: the step to %.17g s goes past the stop time %.17g s", fn, tc + h,
                          d->stopTime);
        return fmi2Error;
    }
    /* model-notes s.6: equal internal steps h / ceil(h / maxStep) (1e-9: h an exact multiple of
     * maxStep up to rounding takes h / maxStep steps) */
    ratio = h / d->par[ParMaxStep];
    if (!(ratio - 1e-9 <= MAX_INTERNAL_STEPS)) {
        instanceLogStatus(inst, fmi2Error, "%s: communicationStepSize = %g s needs %.3g internal steps of at most "
                          "maxStep = %g s; more than %.0f are refused: use a shorter communication step "
                          "or a larger maxStep", fn, h, ceil(ratio - 1e-9), d->par[ParMaxStep], MAX_INTERNAL_STEPS);
        return fmi2Error;
    }
    nSteps = (long)ceil(ratio - 1e-9);
    if (nSteps < 1) nSteps = 1;
    /* model-notes s.1: rotorSpeed in [0, 30000] rpm at both ends of the step */
    n0 = solverInputAt(&inst->inputs, SOLVER_INPUT_SPEED, 0.0);
    n1 = solverInputAt(&inst->inputs, SOLVER_INPUT_SPEED, h);
    if (!(n0 >= 0.0 && n0 <= 30000.0 && n1 >= 0.0 && n1 <= 30000.0)) {
        instanceLogStatus(inst, fmi2Discard, "%s: rotorSpeed = %g rpm at t = %.17g s and %g rpm at the step end "
                          "t = %.17g s: it must stay in [0, 30000] rpm (its derivatives extrapolate it out "
                          "of range); the step is refused, the state is unchanged", fn, n0, tc, n1, tc + h);
        d->lastDoStepStatus = fmi2Discard;
        return fmi2Discard;
    }
    backup = d->solver;
    st = solverAdvance(&d->model, &d->solver, &inst->inputs, tc, h, nSteps,
                       instanceLogEnabled(inst, LogEvents) ? eventHook : NULL, inst, &inst->counters, &tFail);
    if (st != SolverOk) {
        const double tf = tc + tFail;
        d->solver = backup;
        switch (st) {
        case SolverNonFinite:
            instanceLogStatus(inst, fmi2Discard, "%s: the state became non-finite near t = %.17g s (numerical "
                              "instability: try a smaller maxStep = %g s; a describing-function contact at low "
                              "rotorSpeed = %g rpm is stiff since C_eq grows like 1/omega); the step from "
                              "t = %.17g s is discarded and the state restored", fn, tf, d->par[ParMaxStep],
                              n0, tc);
            break;
        case SolverChattering:
            instanceLogStatus(inst, fmi2Discard, "%s: more than %d switching events in one internal step near "
                              "t = %.17g s (chattering); the step from t = %.17g s is discarded and the state "
                              "restored", fn, SOLVER_MAX_EVENTS_PER_STEP, tf, tc);
            break;
        case SolverOmegaZero:
            instanceLogStatus(inst, fmi2Discard, "%s: rotorSpeed = 0 (omega = 0) near t = %.17g s while the "
                              "describing-function contact acts (B = %g m > d = %g m): f_c needs omega > 0; "
                              "the step from t = %.17g s is discarded and the state restored", fn, tf,
                              d->solver.B, d->par[ParD], tc);
            break;
        default:
            instanceLogStatus(inst, fmi2Discard, "%s: the describing function failed near t = %.17g s; the step "
                              "from t = %.17g s is discarded and the state restored", fn, tf, tc);
            break;
        }
        d->lastDoStepStatus = fmi2Discard;
        return fmi2Discard;
    }
    d->time = tc + h; /* model-notes s.6: the master's communication point plus h */
    shiftInputs(inst, h);
    d->lastDoStepStatus = warnFullStickOnce(inst, fn);
    return (fmi2Status)d->lastDoStepStatus;
}

/* ------------------------------------------------------------------------------------------- */
/* FMU state get / set                                                                          */

static StateBlob *checkBlob(Instance *inst, const char *fn, fmi2FMUstate state)
{
    StateBlob *b = (StateBlob *)state;
    if (b == NULL || b->magic != BLOB_MAGIC) {
        instanceLogStatus(inst, fmi2Error, "%s: the FMU state %p was not created by this FMU (or was freed)", fn,
                          state);
        return NULL;
    }
    return b;
}

fmi2Status instanceGetState(Instance *inst, fmi2FMUstate *state)
{
    StateBlob *b;
    if (*state == NULL) {
        b = newBlob(inst);
        if (b == NULL) {
            instanceLogStatus(inst, fmi2Error, "fmi2GetFMUstate: out of memory");
            return fmi2Error;
        }
    } else {
        b = checkBlob(inst, "fmi2GetFMUstate", *state);
        if (b == NULL) return fmi2Error;
    }
    b->d = inst->d;
    *state = (fmi2FMUstate)b;
    return fmi2OK;
}

fmi2Status instanceSetState(Instance *inst, fmi2FMUstate state)
{
    const StateBlob *b = checkBlob(inst, "fmi2SetFMUstate", state);
    if (b == NULL) return fmi2Error;
    inst->d = b->d;
    refreshInputs(inst);
    return fmi2OK;
}

fmi2Status instanceFreeState(Instance *inst, fmi2FMUstate *state)
{
    StateBlob *b;
    if (*state == NULL) return fmi2OK;
    b = checkBlob(inst, "fmi2FreeFMUstate", *state);
    if (b == NULL) return fmi2Error;
    unlinkBlob(b);
    b->magic = 0;
    free(b);
    *state = NULL;
    return fmi2OK;
}

/* ------------------------------------------------------------------------------------------- */
/* Serialization: versioned, pointer-free, little-endian.
 *   offset 0   8 bytes  magic "SBLDSTAT"
 *          8   int32    format version (1)
 *         12   int32    total size in bytes
 *         16   uint64   FNV-1a 64 hash of the GUID
 *         24   int32    number of doubles (SER_NDOUBLE), int32 number of int32 (SER_NINT)
 *         32   doubles  IEEE 754 binary64, little-endian (list in serializeData)
 *              int32    two's complement, little-endian
 *   size - 8   uint64   FNV-1a 64 checksum of all preceding bytes                             */

#define SER_VERSION 1
#define SER_HEADER 32
#define SER_NDOUBLE (PAR_NUM + SOLVER_NUM_INPUTS * (SOLVER_MAX_ORDER + 1) + 3 + 8)
#define SER_NINT (1 + IPAR_NUM + 3 + 4)
#define SER_SIZE (SER_HEADER + 8 * SER_NDOUBLE + 4 * SER_NINT + 8)
static const unsigned char SER_MAGIC[8] = {'S', 'B', 'L', 'D', 'S', 'T', 'A', 'T'};

static uint64_t fnv1a(const unsigned char *p, size_t n)
{
    uint64_t h = 14695981039346656037ULL;
    for (size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

static uint64_t guidHash(void) { return fnv1a((const unsigned char *)MODEL_GUID, strlen(MODEL_GUID)); }

static void putU64(unsigned char *p, uint64_t x)
{
    for (int i = 0; i < 8; ++i) p[i] = (unsigned char)(x >> (8 * i));
}
static uint64_t getU64(const unsigned char *p)
{
    uint64_t x = 0;
    for (int i = 0; i < 8; ++i) x |= (uint64_t)p[i] << (8 * i);
    return x;
}
static void putI32(unsigned char *p, int32_t x)
{
    const uint32_t u = (uint32_t)x;
    for (int i = 0; i < 4; ++i) p[i] = (unsigned char)(u >> (8 * i));
}
static int32_t getI32(const unsigned char *p)
{
    uint32_t u = 0;
    for (int i = 0; i < 4; ++i) u |= (uint32_t)p[i] << (8 * i);
    int32_t x;
    memcpy(&x, &u, sizeof x); /* int32_t is two's complement */
    return x;
}
static void putF64(unsigned char *p, double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    putU64(p, u);
}
static double getF64(const unsigned char *p)
{
    const uint64_t u = getU64(p);
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* The field lists: one function walks the fields in a fixed order for both directions. */
typedef struct {
    unsigned char *wp;       /* writing, or NULL */
    const unsigned char *rp; /* reading, or NULL */
} Cursor;

static void fieldF64(Cursor *c, double *x)
{
    if (c->wp) { putF64(c->wp, *x); c->wp += 8; }
    else { *x = getF64(c->rp); c->rp += 8; }
}

static void fieldI32(Cursor *c, int32_t *x)
{
    if (c->wp) { putI32(c->wp, *x); c->wp += 4; }
    else { *x = getI32(c->rp); c->rp += 4; }
}

static void walkFields(Cursor *c, InstanceData *d)
{
    int i, j;
    /* doubles */
    for (i = 0; i < PAR_NUM; ++i) fieldF64(c, &d->par[i]);
    for (i = 0; i < SOLVER_NUM_INPUTS; ++i)
        for (j = 0; j <= SOLVER_MAX_ORDER; ++j) fieldF64(c, &d->in[i][j]);
    fieldF64(c, &d->time);
    fieldF64(c, &d->startTime);
    fieldF64(c, &d->stopTime);
    fieldF64(c, &d->solver.q);
    fieldF64(c, &d->solver.v);
    fieldF64(c, &d->solver.psi);
    fieldF64(c, &d->solver.E);
    fieldF64(c, &d->solver.w);
    fieldF64(c, &d->solver.B);
    fieldF64(c, &d->solver.windowMax);
    fieldF64(c, &d->solver.periods);
    /* int32 */
    fieldI32(c, &d->fsm);
    for (i = 0; i < IPAR_NUM; ++i) fieldI32(c, &d->ipar[i]);
    fieldI32(c, &d->stopTimeDefined);
    fieldI32(c, &d->lastDoStepStatus);
    fieldI32(c, &d->warnedFullStick);
    fieldI32(c, &d->solver.mode);
    fieldI32(c, &d->solver.side);
    fieldI32(c, &d->solver.slipDir);
    fieldI32(c, &d->solver.vdir);
}

fmi2Status instanceSerializedSize(Instance *inst, fmi2FMUstate state, size_t *size)
{
    if (checkBlob(inst, "fmi2SerializedFMUstateSize", state) == NULL) return fmi2Error;
    *size = SER_SIZE;
    return fmi2OK;
}

fmi2Status instanceSerialize(Instance *inst, fmi2FMUstate state, fmi2Byte buffer[], size_t size)
{
    StateBlob *b = checkBlob(inst, "fmi2SerializeFMUstate", state);
    unsigned char *p = (unsigned char *)buffer;
    InstanceData copy;
    Cursor c;
    if (b == NULL) return fmi2Error;
    if (size < SER_SIZE) {
        instanceLogStatus(inst, fmi2Error, "fmi2SerializeFMUstate: the buffer of %lu bytes is too small: %d bytes "
                          "are needed (fmi2SerializedFMUstateSize)", (unsigned long)size, SER_SIZE);
        return fmi2Error;
    }
    memcpy(p, SER_MAGIC, 8);
    putI32(p + 8, SER_VERSION);
    putI32(p + 12, SER_SIZE);
    putU64(p + 16, guidHash());
    putI32(p + 24, SER_NDOUBLE);
    putI32(p + 28, SER_NINT);
    copy = b->d;
    c.wp = p + SER_HEADER;
    c.rp = NULL;
    walkFields(&c, &copy);
    putU64(p + SER_SIZE - 8, fnv1a(p, SER_SIZE - 8));
    return fmi2OK;
}

static int validState(Instance *inst, const char *fn, InstanceData *d)
{
    const SolverState *s = &d->solver;
    const int32_t okFsm = FsmInstantiated | FsmInitializationMode | FsmStepComplete | FsmStepFailed |
                          FsmStepCanceled | FsmTerminated | FsmError;
    const int td = d->ipar[IparFrictionModel] == FrictionMacroslipTD;
    int i;
    if (d->fsm <= 0 || (d->fsm & (d->fsm - 1)) != 0 || (d->fsm & okFsm) == 0) {
        instanceLogStatus(inst, fmi2Error, "%s: invalid state machine state %d in the data", fn, (int)d->fsm);
        return 0;
    }
    for (i = 0; i < NUM_VARS; ++i) {
        const VarInfo *v = &VARS[i];
        double x;
        if (v->causality == CausParameter) x = v->type == TypeReal ? d->par[v->slot] : (double)d->ipar[v->slot];
        else if (v->causality == CausInput) x = d->in[v->slot][0];
        else if (v->startSlot >= 0) x = d->par[v->startSlot];
        else continue;
        if (!validValue(inst, fn, v, x)) return 0;
    }
    for (i = 0; i < SOLVER_NUM_INPUTS; ++i)
        for (int j = 1; j <= SOLVER_MAX_ORDER; ++j)
            if (!isfinite(d->in[i][j])) {
                instanceLogStatus(inst, fmi2Error, "%s: input derivative not finite in the data", fn);
                return 0;
            }
    if (!isfinite(d->time) || !isfinite(d->startTime) || !isfinite(d->stopTime) ||
        (d->stopTimeDefined != 0 && d->stopTimeDefined != 1) || d->lastDoStepStatus < fmi2OK ||
        d->lastDoStepStatus > fmi2Fatal || (d->warnedFullStick != 0 && d->warnedFullStick != 1)) {
        instanceLogStatus(inst, fmi2Error, "%s: invalid time or status fields in the data", fn);
        return 0;
    }
    if (preInit(d)) return 1; /* the solver state is rebuilt at fmi2ExitInitializationMode */
    if (!isfinite(s->q) || !isfinite(s->v) || !isfinite(s->psi) || !isfinite(s->E) || !isfinite(s->w) ||
        !(s->B >= 0.0) || !isfinite(s->B) || !(s->windowMax >= 0.0) || !isfinite(s->windowMax) ||
        !(s->periods >= 0.0) || s->periods > 9e15 || s->periods != floor(s->periods) ||
        s->mode < 0 || s->mode > (td ? 2 : 1) || (s->side != 1 && s->side != -1) ||
        (s->slipDir != 1 && s->slipDir != -1) || (s->vdir != 1 && s->vdir != -1)) {
        instanceLogStatus(inst, fmi2Error, "%s: invalid solver state in the data", fn);
        return 0;
    }
    return 1;
}

fmi2Status instanceDeserialize(Instance *inst, const fmi2Byte buffer[], size_t size, fmi2FMUstate *state)
{
    const char *fn = "fmi2DeSerializeFMUstate";
    const unsigned char *p = (const unsigned char *)buffer;
    InstanceData saved, tmp;
    Cursor c;
    StateBlob *b;
    if (size < 16 || memcmp(p, SER_MAGIC, 8) != 0) {
        instanceLogStatus(inst, fmi2Error, "%s: not a ShroudedBlade FMU state (wrong magic or only %lu bytes)", fn,
                          (unsigned long)size);
        return fmi2Error;
    }
    if (getI32(p + 8) != SER_VERSION) {
        instanceLogStatus(inst, fmi2Error, "%s: state format version %d is not supported (this FMU reads version %d)",
                          fn, (int)getI32(p + 8), SER_VERSION);
        return fmi2Error;
    }
    if (size != SER_SIZE || getI32(p + 12) != SER_SIZE) {
        instanceLogStatus(inst, fmi2Error, "%s: the state has %lu bytes (header says %d); version %d has %d bytes", fn,
                          (unsigned long)size, (int)getI32(p + 12), SER_VERSION, SER_SIZE);
        return fmi2Error;
    }
    if (getU64(p + 16) != guidHash() || getI32(p + 24) != SER_NDOUBLE || getI32(p + 28) != SER_NINT) {
        instanceLogStatus(inst, fmi2Error, "%s: the state was saved by another FMU (GUID hash or layout differs from "
                          "%s)", fn, MODEL_GUID);
        return fmi2Error;
    }
    if (getU64(p + SER_SIZE - 8) != fnv1a(p, SER_SIZE - 8)) {
        instanceLogStatus(inst, fmi2Error, "%s: checksum mismatch: the state data is corrupted", fn);
        return fmi2Error;
    }
    memset(&tmp, 0, sizeof tmp);
    c.wp = NULL;
    c.rp = p + SER_HEADER;
    walkFields(&c, &tmp);
    if (!validState(inst, fn, &tmp)) return fmi2Error;
    /* rebuild the derived part with the instance's own machinery, then restore the instance */
    saved = inst->d;
    inst->d = tmp;
    if (!preInit(&tmp)) {
        if (buildModel(inst, fn, 0) != fmi2OK && tmp.fsm != FsmError) {
            inst->d = saved;
            return fmi2Error;
        }
    }
    tmp = inst->d;
    inst->d = saved;
    if (*state != NULL) {
        b = checkBlob(inst, fn, *state);
        if (b == NULL) return fmi2Error;
    } else {
        b = newBlob(inst);
        if (b == NULL) {
            instanceLogStatus(inst, fmi2Error, "%s: out of memory", fn);
            return fmi2Error;
        }
    }
    b->d = tmp;
    *state = (fmi2FMUstate)b;
    return fmi2OK;
}
