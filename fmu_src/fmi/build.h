/* The model's derived data from its parameters: the one place the layer calls the model's build
 * (instance.c at the end of initialization, variables.c and fmi2_me.c before outputs). Calls only
 * the model's function pointers, so no file it is called from is called back. */
#ifndef FMI_BUILD_H
#define FMI_BUILD_H

#include "fmi/instance.h"

/* The model's build (FmiModel.build), then for a model-exchange instance its FmiModelExchange.built;
 * sets inst->built. initState: also the initial state (end of initialization). */
FmiStatus fmiBuild(FmiInstance *inst, const char *fn, int initState);
/* fmiBuild if the parameters changed since the last build (before the end of initialization also
 * the state from the start values: outputs follow the parameters). Logs and returns FmiError on
 * failure. */
FmiStatus fmiEnsureBuilt(FmiInstance *inst, const char *fn);

#endif
