/* Table-driven access to a model's variables: lookup, range validation with messages that name
 * the variable, the value and the range, get/set of Real, Integer and Boolean arrays and input
 * derivatives. Values cross this interface as doubles with an element accessor per face type. */
#ifndef FMI_VARIABLES_H
#define FMI_VARIABLES_H

#include "fmi/instance.h"

/* The caller's array of one FMI type, read or written element-wise as doubles. */
typedef struct {
    VarType type;
    double (*read)(const void *values, size_t i);
    void (*write)(void *values, size_t i, double x);
} FmiArray;

const VarInfo *fmiFindVar(const FmiModel *model, FmiValueRef vr);
const char *fmiVarTypeName(VarType type);
/* fmiFindVar as the instance's face declares the variables (NULL: unknown there). */
const VarInfo *fmiFaceVar(const FmiInstance *inst, FmiValueRef vr);

/* Unknown or mistyped references give 0 and FmiError, the others are still read. */
FmiStatus fmiGetValues(FmiInstance *inst, const char *fn, const FmiValueRef vr[], size_t nvr,
                       const FmiArray *a, void *values);
/* Atomic: every value is validated before any is applied. */
FmiStatus fmiSetValues(FmiInstance *inst, const char *fn, const FmiValueRef vr[], size_t nvr,
                       const FmiArray *a, const void *values);
/* Atomic as fmiSetValues; order[i] in [1, model->maxInputOrder]. */
FmiStatus fmiSetInputDerivatives(FmiInstance *inst, const char *fn, const FmiValueRef vr[], size_t nvr,
                                 const int32_t order[], const double value[]);

/* 1 if every parameter, input (value and derivatives) and start value in data is valid; else
 * logs and 0. */
int fmiVariablesValid(FmiInstance *inst, const char *fn, const void *data);

#endif
