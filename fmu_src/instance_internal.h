/* Functions shared by the files behind instance.h (instance.c, variables.c, fmu_state.c,
 * logging.c). fmi2_api.c uses instance.h only. */
#ifndef INSTANCE_INTERNAL_H
#define INSTANCE_INTERNAL_H

#include "instance.h"

/* instance.c */
/* 1 before fmi2ExitInitializationMode (the model then follows the parameters). */
int instancePreInit(const InstanceData *d);
/* Builds blade reduction and solver model from the parameters; if initState, also the initial
 * solver state. Logs and returns fmi2Error on failure. */
fmi2Status instanceBuildModel(Instance *inst, const char *fn, int initState);
/* Builds the model if a parameter changed since it was last built (outputs need it). */
fmi2Status instanceEnsureModel(Instance *inst, const char *fn);

/* variables.c */
/* Writes the start values of all parameters, inputs and initial="exact" outputs into d. */
void variablesStartValues(InstanceData *d);
/* 1 if every parameter, input value and start value in d is in its range; else logs and 0. */
int variablesValid(Instance *inst, const char *fn, const InstanceData *d);

/* fmu_state.c */
/* Frees every FMU state the instance still holds (fmi2FreeInstance). */
void fmuStateFreeAll(Instance *inst);

#endif
