/* What the two files of the FMI 2.0 face share (fmi2_cs.c: common and co-simulation functions,
 * fmi2_me.c: model exchange). */
#ifndef FMI2_FACE_H
#define FMI2_FACE_H

#include "fmi2Functions.h"
#include "fmi/instance.h"

/* The instance behind c, if c is one and the call is allowed in its state (a mask of FsmState
 * bits); else NULL (logged when possible). logCall: log the call (category logCalls). */
FmiInstance *fmi2FaceEnter(fmi2Component c, const char *fn, int mask, int logCall);

#endif
