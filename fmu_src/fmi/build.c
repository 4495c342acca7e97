/* Building the model's derived data (see build.h). */
#include "fmi/build.h"

FmiStatus fmiBuild(FmiInstance *inst, const char *fn, int initState)
{
    FmiStatus status = inst->model->build(inst, fn, initState);
    if (status == FmiOK && inst->me && inst->me->built) status = inst->me->built(inst, fn, initState);
    inst->built = status == FmiOK;
    return status;
}

FmiStatus fmiEnsureBuilt(FmiInstance *inst, const char *fn)
{
    if (inst->built) return FmiOK;
    return fmiBuild(inst, fn, fsmPreInit(inst->fsm));
}
