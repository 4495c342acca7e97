/* FMU states: copies owned by the instance (get/set/free) and their serialization, a versioned,
 * pointer-free, little-endian byte format whose counts and size follow from the model's field
 * list. The state-machine value is not serialized: a deserialized state derives it. */
#ifndef FMI_STATE_BLOB_H
#define FMI_STATE_BLOB_H

#include "fmi/instance.h"

/* *state NULL: a new copy; else the caller's copy (checked) is overwritten. */
FmiStatus fmiStateGet(FmiInstance *inst, const char *fn, void **state);
FmiStatus fmiStateSet(FmiInstance *inst, const char *fn, void *state);
FmiStatus fmiStateFree(FmiInstance *inst, const char *fn, void **state);
FmiStatus fmiStateSize(FmiInstance *inst, const char *fn, void *state, size_t *size);
FmiStatus fmiStateSerialize(FmiInstance *inst, const char *fn, void *state, unsigned char buffer[], size_t size);
FmiStatus fmiStateDeserialize(FmiInstance *inst, const char *fn, const unsigned char buffer[], size_t size,
                              void **state);
/* Frees every FMU state the instance still holds. */
void fmiStateFreeAll(FmiInstance *inst);

#endif
