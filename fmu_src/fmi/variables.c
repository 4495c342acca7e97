/* The get/set/validate engine over a model's variable table (see variables.h). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "fmi/build.h"
#include "fmi/log.h"
#include "fmi/variables.h"

/* A value in the model's data at a table offset (the table gives each variable's type). */
static double *realAt(void *data, long offset) { return (double *)(void *)((char *)data + offset); }
static int32_t *intAt(void *data, long offset) { return (int32_t *)(void *)((char *)data + offset); }
static double realIn(const void *data, long offset)
{
    return *(const double *)(const void *)((const char *)data + offset);
}
static int32_t intIn(const void *data, long offset)
{
    return *(const int32_t *)(const void *)((const char *)data + offset);
}

/* Bisection: the table is sorted by value reference (every Get/Set looks up each vr). */
const VarInfo *fmiFindVar(const FmiModel *model, FmiValueRef vr)
{
    int lo = 0, hi = model->nVars - 1;
    while (lo <= hi) {
        const int mid = (lo + hi) / 2;
        if (model->vars[mid].vr == vr) return &model->vars[mid];
        if (model->vars[mid].vr < vr) lo = mid + 1;
        else hi = mid - 1;
    }
    return NULL;
}

const VarInfo *fmiFaceVar(const FmiInstance *inst, FmiValueRef vr)
{
    const VarInfo *v = fmiFindVar(inst->model, vr);
    if (v != NULL && v->meOnly && !inst->face->declaresLocals) return NULL;
    return v;
}

const char *fmiVarTypeName(VarType t)
{
    return t == VarReal ? "Real" : (t == VarInteger ? "Integer" : "Boolean");
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
    if (v->type == VarBoolean) {
        snprintf(buf, n, "{false, true}");
        return;
    }
    if (isinf(v->lo)) snprintf(lo, sizeof lo, "(-inf");
    else snprintf(lo, sizeof lo, "%c%g", v->loOpen ? '(' : '[', v->lo);
    if (isinf(v->hi)) snprintf(hi, sizeof hi, "inf)");
    else snprintf(hi, sizeof hi, "%g%c", v->hi, v->hiOpen ? ')' : ']');
    snprintf(buf, n, "%s, %s", lo, hi);
}

/* The stored value of a parameter, an input, or an output's start value. */
static double storedValue(const VarInfo *v, const void *data)
{
    return v->type == VarReal ? realIn(data, v->offset) : (double)intIn(data, v->offset);
}

/* Looks up vr, checks its type; logs and returns NULL if unknown or of another type. */
static const VarInfo *lookup(FmiInstance *inst, const char *fn, FmiValueRef vr, VarType type)
{
    const VarInfo *v = fmiFaceVar(inst, vr);
    if (v == NULL) {
        fmiLogStatus(inst, FmiError, "%s: unknown value reference %u", fn, (unsigned)vr);
        return NULL;
    }
    if (v->type != type) {
        fmiLogStatus(inst, FmiError, "%s: %s (vr %u) is of type %s, not %s", fn, v->name, (unsigned)vr,
                     inst->face->typeNames[v->type], inst->face->typeNames[type]);
        return NULL;
    }
    return v;
}

FmiStatus fmiGetValues(FmiInstance *inst, const char *fn, const FmiValueRef vr[], size_t nvr,
                       const FmiArray *a, void *values)
{
    const FmiModel *m = inst->model;
    FmiStatus status = FmiOK;
    int haveOutputs = 0;
    for (size_t i = 0; i < nvr; ++i) {
        const VarInfo *v = lookup(inst, fn, vr[i], a->type);
        double x;
        if (v == NULL) {
            status = FmiError;
            a->write(values, i, 0.0);
            continue;
        }
        if (v->causality != CausOutput && v->causality != CausLocal) {
            a->write(values, i, storedValue(v, inst->data));
            continue;
        }
        if (!haveOutputs) {
            if (fmiEnsureBuilt(inst, fn) != FmiOK) return FmiError;
            m->outputs(inst);
            if (inst->me && inst->me->outputs) inst->me->outputs(inst);
            haveOutputs = 1;
        }
        x = m->output(inst, v->output);
        a->write(values, i, x);
        if (!isfinite(x)) {
            /* a step checks its own end: this follows an input set since the step */
            char hint[160] = "";
            if (m->nonFiniteHint) m->nonFiniteHint(inst, hint, sizeof hint);
            fmiLogStatus(inst, FmiWarning, "%s: %s = %g is not finite%s", fn, v->name, x, hint);
            if (status == FmiOK) status = FmiWarning;
        }
    }
    return status;
}

/* May v be set now? Logs and returns 0 if not. */
static int settable(FmiInstance *inst, const char *fn, const VarInfo *v)
{
    const int before = fsmPreInit(inst->fsm);
    if (v->causality == CausInput) return 1; /* the call-sequence mask already restricts states */
    if (v->causality == CausParameter) {
        if (before) return 1;
        fmiLogStatus(inst, FmiError,
                     "%s: parameter %s (vr %u) has variability fixed: it can be set only before "
                     "%s (state: %s)", fn, v->name, (unsigned)v->vr, inst->face->exitInitializationMode,
                     inst->face->stateName(inst->fsm));
        return 0;
    }
    if (v->causality == CausLocal) {
        fmiLogStatus(inst, FmiError, "%s: %s (vr %u) is a calculated variable and cannot be set", fn, v->name,
                     (unsigned)v->vr);
        return 0;
    }
    if (v->offset >= 0 && before) return 1; /* initial="exact" output: its start value */
    if (v->offset >= 0) {
        fmiLogStatus(inst, FmiError,
                     "%s: output %s (vr %u) can be set (its start value) only before "
                     "%s (state: %s)", fn, v->name, (unsigned)v->vr, inst->face->exitInitializationMode,
                     inst->face->stateName(inst->fsm));
    } else {
        fmiLogStatus(inst, FmiError, "%s: %s (vr %u) is a calculated output and cannot be set", fn, v->name,
                     (unsigned)v->vr);
    }
    return 0;
}

/* Validates x for v; logs (naming variable, value, allowed range) and returns 0 if invalid. */
static int validValue(FmiInstance *inst, const char *fn, const VarInfo *v, double x)
{
    char range[96];
    const char *sp = v->unit[0] ? " " : "";
    if (inRange(v, x)) return 1;
    rangeText(v, range, sizeof range);
    if (!isfinite(x)) {
        fmiLogStatus(inst, FmiError, "%s: %s = %g%s%s is not a finite number; allowed range %s%s%s", fn, v->name,
                     x, sp, v->unit, range, sp, v->unit);
    } else if (v->type == VarReal) {
        fmiLogStatus(inst, FmiError, "%s: %s = %g%s%s is out of range %s", fn, v->name, x, sp, v->unit, range);
    } else {
        fmiLogStatus(inst, FmiError, "%s: %s = %.0f is out of range %s", fn, v->name, x, range);
    }
    return 0;
}

static void applyValue(FmiInstance *inst, const VarInfo *v, double x)
{
    if (v->type == VarReal) *realAt(inst->data, v->offset) = x;
    else *intAt(inst->data, v->offset) = (int32_t)x;
    if (v->causality == CausInput) {
        /* setting a value resets the derivatives of that input (model-notes s.1) */
        double *u = realAt(inst->data, v->offset);
        for (int j = 1; j <= inst->model->maxInputOrder; ++j) u[j] = 0.0;
    } else {
        inst->built = 0; /* a parameter or a start value: derived data follow */
    }
}

FmiStatus fmiSetValues(FmiInstance *inst, const char *fn, const FmiValueRef vr[], size_t nvr,
                       const FmiArray *a, const void *values)
{
    for (size_t i = 0; i < nvr; ++i) {
        const VarInfo *v = lookup(inst, fn, vr[i], a->type);
        if (v == NULL || !settable(inst, fn, v) || !validValue(inst, fn, v, a->read(values, i)))
            return FmiError;
    }
    for (size_t i = 0; i < nvr; ++i) applyValue(inst, fmiFindVar(inst->model, vr[i]), a->read(values, i));
    return FmiOK;
}

/* "a (vr 1) and b (vr 2)": the inputs of the table, for messages. */
static void inputList(const FmiModel *m, char *buf, size_t n)
{
    int k = 0, total = 0;
    size_t used = 0;
    buf[0] = '\0';
    for (int i = 0; i < m->nVars; ++i) total += m->vars[i].causality == CausInput;
    for (int i = 0; i < m->nVars && used < n; ++i) {
        const VarInfo *v = &m->vars[i];
        if (v->causality != CausInput) continue;
        used += (size_t)snprintf(buf + used, n - used, "%s%s (vr %u)", k == 0 ? "" : (k + 1 == total ? " and " : ", "),
                                 v->name, (unsigned)v->vr);
        ++k;
    }
    if (total == 0) snprintf(buf, n, "inputs, and this FMU has none");
}

FmiStatus fmiSetInputDerivatives(FmiInstance *inst, const char *fn, const FmiValueRef vr[], size_t nvr,
                                 const int32_t order[], const double value[])
{
    const FmiModel *m = inst->model;
    const VarInfo *v = NULL;
    for (size_t i = 0; i < nvr; ++i) {
        if (i == 0 || vr[i] != vr[i - 1]) v = fmiFindVar(m, vr[i]); /* the orders of one input: one lookup */
        if (v == NULL) {
            fmiLogStatus(inst, FmiError, "%s: unknown value reference %u", fn, (unsigned)vr[i]);
            return FmiError;
        }
        if (v->causality != CausInput) {
            char inputs[200];
            inputList(m, inputs, sizeof inputs);
            fmiLogStatus(inst, FmiError, "%s: %s (vr %u) is not an input: derivatives can be set only for %s",
                         fn, v->name, (unsigned)vr[i], inputs);
            return FmiError;
        }
        if (order[i] < 1 || order[i] > m->maxInputOrder) {
            fmiLogStatus(inst, FmiError, "%s: derivative order %d of %s is out of range [1, %d]", fn,
                         (int)order[i], v->name, m->maxInputOrder);
            return FmiError;
        }
        if (!isfinite(value[i])) {
            fmiLogStatus(inst, FmiError, "%s: derivative of order %d of %s = %g is not a finite number", fn,
                         (int)order[i], v->name, value[i]);
            return FmiError;
        }
    }
    for (size_t i = 0; i < nvr; ++i) {
        if (i == 0 || vr[i] != vr[i - 1]) v = fmiFindVar(m, vr[i]);
        realAt(inst->data, v->offset)[order[i]] = value[i];
    }
    return FmiOK;
}

int fmiVariablesValid(FmiInstance *inst, const char *fn, const void *data)
{
    const FmiModel *m = inst->model;
    for (int i = 0; i < m->nVars; ++i) {
        const VarInfo *v = &m->vars[i];
        if (v->offset < 0) continue;
        if (!validValue(inst, fn, v, storedValue(v, data))) return 0;
    }
    for (int i = 0; i < m->nVars; ++i) {
        const VarInfo *v = &m->vars[i];
        const double *u;
        if (v->causality != CausInput) continue;
        u = (const double *)(const void *)((const char *)data + v->offset);
        for (int j = 1; j <= m->maxInputOrder; ++j)
            if (!isfinite(u[j])) {
                fmiLogStatus(inst, FmiError, "%s: input derivative not finite in the data", fn);
                return 0;
            }
    }
    return 1;
}
