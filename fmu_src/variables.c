/* The variables of the ShroudedBlade FMU (modelDescription.xml): a const table of value
 * references, start values and allowed ranges; validation with messages that name the variable,
 * the value and the range; fmi2Get/Set of Real, Integer and Boolean and the input derivatives. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "config.h"
#include "instance_internal.h"

/* ------------------------------------------------------------------------------------------- */
/* Variable table (modelDescription.xml; bounds as harness/params.py: open where the quantity must
 * be strictly positive)                                                                        */

typedef enum { TypeReal, TypeInteger, TypeBoolean } VarType;
typedef enum { CausParameter, CausInput, CausOutput } Causality;
typedef enum {
    OutQ = 0, OutV, OutNormalForce, OutFrictionForce, OutKeq, OutCeq, OutAmplitude, OutEnergy,
    OutFrequency, OutJenkinsForce, OutRegime, OutContactState, OutRunningMaximum
} OutputId;

typedef struct {
    fmi2ValueReference vr;
    const char *name;
    VarType type;
    Causality causality;
    const char *unit;   /* "" if dimensionless */
    double start;       /* start value [unit] */
    double lo, hi;      /* allowed range [unit] */
    int loOpen, hiOpen; /* 1: the bound itself is excluded */
    int slot;           /* RealParam, IntParam, input index or OutputId */
    int startSlot;      /* RealParam holding the start value of an initial="exact" output, or -1 */
} VarInfo;

#define INF HUGE_VAL
#define HALF_PI 1.5707963267948966

/* Sorted by value reference (findVar bisects). */
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
    /* its start value is checked against the friction cone at initialization (instance.c) */
    {vr_jenkinsForce, "jenkinsForce", TypeReal, CausOutput, "N", 0.0, -INF, INF, 0, 0, OutJenkinsForce, ParF0},
    {vr_regime, "regime", TypeInteger, CausOutput, "", 0, -INF, INF, 0, 0, OutRegime, -1},
    {vr_contactState, "contactState", TypeInteger, CausOutput, "", 0, -INF, INF, 0, 0, OutContactState, -1},
    {vr_runningMaximum, "runningMaximum", TypeReal, CausOutput, "m", 0.0, 0.0, INF, 0, 0, OutRunningMaximum,
     ParWindowMax0},
};
#define NUM_VARS ((int)(sizeof VARS / sizeof VARS[0]))

/* Bisection: VARS is sorted by value reference (every Get/Set looks up each vr). */
static const VarInfo *findVar(fmi2ValueReference vr)
{
    int lo = 0, hi = NUM_VARS - 1;
    while (lo <= hi) {
        const int mid = (lo + hi) / 2;
        if (VARS[mid].vr == vr) return &VARS[mid];
        if (VARS[mid].vr < vr) lo = mid + 1;
        else hi = mid - 1;
    }
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
/* Get / Set                                                                                   */

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
    case OutJenkinsForce: return o->jenkinsForce;
    case OutRunningMaximum: return s->windowMax;
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
        double x;
        if (v == NULL) {
            status = fmi2Error;
            writeValue(type, out, i, 0.0);
            continue;
        }
        if (v->causality == CausOutput && !haveOutputs) {
            if (instanceEnsureModel(inst, fn) != fmi2OK) return fmi2Error;
            solverOutputs(&inst->d.model, &inst->d.solver, inst->d.in[SOLVER_INPUT_SPEED][0], &o);
            haveOutputs = 1;
        }
        x = variableValue(inst, v, &o);
        writeValue(type, out, i, x);
        if (v->causality == CausOutput && !isfinite(x)) {
            /* only after a rotorSpeed set since the step (fmi2DoStep checks its own end) */
            instanceLogStatus(inst, fmi2Warning, "%s: %s = %g is not finite at rotorSpeed = %g rpm (a "
                              "describing-function coefficient ~ 1/omega overflows)", fn, v->name, x,
                              inst->d.in[SOLVER_INPUT_SPEED][0]);
            if (status == fmi2OK) status = fmi2Warning;
        }
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
    const int before = instancePreInit(&inst->d);
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
    for (size_t i = 0; i < nvr; ++i) {
        const VarInfo *v = lookup(inst, fn, vr[i], type);
        if (v == NULL || !settable(inst, fn, v) || !validValue(inst, fn, v, readValue(type, values, i)))
            return fmi2Error;
    }
    for (size_t i = 0; i < nvr; ++i) applyValue(inst, findVar(vr[i]), readValue(type, values, i));
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
    return fmi2OK;
}

/* ------------------------------------------------------------------------------------------- */
/* Whole data sets (start values, deserialized data)                                           */
void variablesStartValues(InstanceData *d)
{
    for (int i = 0; i < NUM_VARS; ++i) {
        const VarInfo *v = &VARS[i];
        if (v->causality == CausParameter && v->type == TypeReal) d->par[v->slot] = v->start;
        else if (v->causality == CausParameter) d->ipar[v->slot] = (int32_t)v->start;
        else if (v->causality == CausInput) d->in[v->slot][0] = v->start;
        else if (v->startSlot >= 0) d->par[v->startSlot] = v->start;
    }
}

int variablesValid(Instance *inst, const char *fn, const InstanceData *d)
{
    for (int i = 0; i < NUM_VARS; ++i) {
        const VarInfo *v = &VARS[i];
        double x;
        if (v->causality == CausParameter) x = v->type == TypeReal ? d->par[v->slot] : (double)d->ipar[v->slot];
        else if (v->causality == CausInput) x = d->in[v->slot][0];
        else if (v->startSlot >= 0) x = d->par[v->startSlot];
        else continue;
        if (!validValue(inst, fn, v, x)) return 0;
    }
    return 1;
}
