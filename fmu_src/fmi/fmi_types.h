/* Neutral types of the generic FMI layer. Below the faces (fmi2_cs.c, fmi3_cs.c) nothing uses
 * fmiN types: the numeric values of FmiStatus equal those of fmi2Status and fmi3Status
 * (OK..Fatal), so a face converts by a cast. */
#ifndef FMI_TYPES_H
#define FMI_TYPES_H

#include <stddef.h>
#include <stdint.h>

/* Escalating: a worse status has a larger value. */
typedef enum { FmiOK = 0, FmiWarning = 1, FmiDiscard = 2, FmiError = 3, FmiFatal = 4 } FmiStatus;

typedef uint32_t FmiValueRef;

typedef enum { VarReal, VarInteger, VarBoolean } VarType;
/* CausLocal: a calculated variable that is not an output (model exchange: states and derivatives) */
typedef enum { CausParameter, CausInput, CausOutput, CausLocal } Causality;

/* One row of a model's variable table (generated from the model's spec, fmu_src/gen). Values live in the model's data (the FMU state) at
 * `offset`: a double for Real, an int32_t for Integer and Boolean. An input's value is the first
 * of (1 + maxInputOrder) doubles: the value and its time derivatives. A calculated output has no
 * storage: `output` is its number for the model's output function; an output with a settable
 * start value (initial="exact") also has one (offset >= 0). */
typedef struct {
    FmiValueRef vr;
    const char *name;
    VarType type;
    Causality causality;
    const char *unit;   /* "" if dimensionless */
    double start;       /* start value [unit] */
    double lo, hi;      /* allowed range [unit] */
    int loOpen, hiOpen; /* 1: the bound itself is excluded */
    long offset;        /* byte offset in the model's data, or -1 */
    int output;         /* output number (outputs only), else -1 */
    int meOnly;         /* 1: a model-exchange local (state, derivative): unknown to a face that
                           declares none (FMI 3.0 co-simulation) */
} VarInfo;

#define VAR_NO_OFFSET (-1L)

/* One entry of the serialized field list of a model's data: `count` consecutive values of one
 * kind at `offset`. The blob's counts and size are summed from this list. */
typedef enum { FieldF64, FieldI32 } FieldKind;

typedef struct {
    long offset;
    FieldKind kind;
    int count;
} StateField;

#endif
