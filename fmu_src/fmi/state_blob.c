/* FMU state copies and their serialization (see state_blob.h).
 *
 * Serialized format (this layer's framing; the fields come from FmiModel.fields):
 *   offset 0   8 bytes  magic "SBLDSTAT"
 *          8   int32    format version (FmiModel.stateVersion)
 *         12   int32    total size in bytes
 *         16   uint64   FNV-1a 64 hash of the model's GUID
 *         24   int32    number of doubles, int32 number of int32 (both summed from the field list)
 *         32   doubles  IEEE 754 binary64, little-endian: time, startTime, stopTime, then the
 *                       model's F64 fields in list order
 *              int32    two's complement, little-endian: initialized, stopTimeDefined,
 *                       lastDoStepStatus, then the model's I32 fields in list order
 *   size - 8   uint64   FNV-1a 64 checksum of all preceding bytes
 * Everything is checked (magic, version, size, GUID hash, counts, checksum, every value) before
 * a state is made from it. The state machine's state is not serialized (it belongs to the face's
 * call sequence, not to the model): an in-memory copy restores it, a deserialized state comes back
 * in stepComplete if initialization had ended, else in instantiated. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "fmi/log.h"
#include "fmi/state_blob.h"
#include "fmi/variables.h"

#define COPY_MAGIC 0x53426c6164655332ULL /* "SBladeS2" */

struct FmiStateCopy {
    uint64_t magic;
    FmiInstance *owner; /* the instance whose list holds this copy */
    FmiStateCopy *prev, *next;
    int32_t fsm;        /* FsmState at the copy; a deserialized copy derives it (see above) */
    FmiRun run;
    int32_t built;
    void *data;         /* model->dataSize bytes */
    void *meData;       /* me->dataSize bytes of a model-exchange instance's copy, else NULL */
};

/* ------------------------------------------------------------------------------------------- */
/* FMU state copies                                                                            */

static void unlinkCopy(FmiStateCopy *b)
{
    if (b->owner) {
        if (b->prev) b->prev->next = b->next;
        else b->owner->states = b->next;
        if (b->next) b->next->prev = b->prev;
    }
    b->owner = NULL;
    b->prev = b->next = NULL;
}

static FmiStateCopy *newCopy(FmiInstance *inst)
{
    FmiStateCopy *b = (FmiStateCopy *)calloc(1, sizeof *b);
    if (b == NULL) return NULL;
    b->data = calloc(1, inst->model->dataSize > 0 ? inst->model->dataSize : 1);
    if (inst->me) b->meData = calloc(1, inst->me->dataSize > 0 ? inst->me->dataSize : 1);
    if (b->data == NULL || (inst->me && b->meData == NULL)) {
        free(b->data);
        free(b->meData);
        free(b);
        return NULL;
    }
    b->magic = COPY_MAGIC;
    b->owner = inst;
    b->next = inst->states;
    if (inst->states) inst->states->prev = b;
    inst->states = b;
    return b;
}

static void destroyCopy(FmiStateCopy *b)
{
    unlinkCopy(b);
    b->magic = 0;
    free(b->data);
    free(b->meData);
    free(b);
}

void fmiStateFreeAll(FmiInstance *inst)
{
    while (inst->states) destroyCopy(inst->states);
}

static FmiStateCopy *checkCopy(FmiInstance *inst, const char *fn, void *state)
{
    FmiStateCopy *b = (FmiStateCopy *)state;
    if (b == NULL || b->magic != COPY_MAGIC) {
        fmiLogStatus(inst, FmiError, "%s: the FMU state %p was not created by this FMU (or was freed)", fn, state);
        return NULL;
    }
    return b;
}

/* The copy to fill: the caller's state (checked) to overwrite, or a new one if it passes NULL. */
static FmiStateCopy *copyToFill(FmiInstance *inst, const char *fn, void *state)
{
    FmiStateCopy *b;
    if (state != NULL) return checkCopy(inst, fn, state);
    b = newCopy(inst);
    if (b == NULL) fmiLogStatus(inst, FmiError, "%s: out of memory", fn);
    return b;
}

FmiStatus fmiStateGet(FmiInstance *inst, const char *fn, void **state)
{
    FmiStateCopy *b = copyToFill(inst, fn, *state);
    if (b == NULL) return FmiError;
    b->fsm = inst->fsm;
    b->run = inst->run;
    b->built = inst->built;
    memcpy(b->data, inst->data, inst->model->dataSize);
    if (inst->me && b->meData) memcpy(b->meData, inst->meData, inst->me->dataSize);
    *state = b;
    return FmiOK;
}

FmiStatus fmiStateSet(FmiInstance *inst, const char *fn, void *state)
{
    const FmiStateCopy *b = checkCopy(inst, fn, state);
    if (b == NULL) return FmiError;
    inst->run = b->run;
    inst->built = b->built;
    memcpy(inst->data, b->data, inst->model->dataSize);
    /* a copy without model-exchange data (taken by a co-simulation instance) leaves them zero */
    if (inst->me && b->meData) memcpy(inst->meData, b->meData, inst->me->dataSize);
    else if (inst->me) memset(inst->meData, 0, inst->me->dataSize);
    inst->fsm = b->fsm;
    return FmiOK;
}

FmiStatus fmiStateFree(FmiInstance *inst, const char *fn, void **state)
{
    FmiStateCopy *b;
    if (*state == NULL) return FmiOK;
    b = checkCopy(inst, fn, *state);
    if (b == NULL) return FmiError;
    destroyCopy(b);
    *state = NULL;
    return FmiOK;
}

/* ------------------------------------------------------------------------------------------- */
/* Serialization                                                                               */

#define SER_HEADER 32
#define RUN_NDOUBLE 3 /* time, startTime, stopTime */
#define RUN_NINT 3    /* initialized, stopTimeDefined, lastDoStepStatus */
static const unsigned char SER_MAGIC[8] = {'S', 'B', 'L', 'D', 'S', 'T', 'A', 'T'};

typedef struct {
    int32_t nDouble, nInt, size;
} Layout;

static Layout layoutOf(const FmiModel *m)
{
    Layout l = {RUN_NDOUBLE, RUN_NINT, 0};
    for (int i = 0; i < m->nFields; ++i) {
        if (m->fields[i].kind == FieldF64) l.nDouble += m->fields[i].count;
        else l.nInt += m->fields[i].count;
    }
    l.size = SER_HEADER + 8 * l.nDouble + 4 * l.nInt + 8;
    return l;
}

static uint64_t fnv1a(const unsigned char *p, size_t n)
{
    uint64_t h = 14695981039346656037ULL;
    for (size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

static uint64_t guidHash(const FmiModel *m) { return fnv1a((const unsigned char *)m->guid, strlen(m->guid)); }

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
    int32_t x;
    for (int i = 0; i < 4; ++i) u |= (uint32_t)p[i] << (8 * i);
    memcpy(&x, &u, sizeof x); /* int32_t is two's complement */
    return x;
}

/* One walk over the fields serves both directions: the doubles block is written (or read) at
 * dp, the int32 block at ip. */
typedef struct {
    unsigned char *wd, *wi;             /* writing, or NULL */
    const unsigned char *rd, *ri;       /* reading, or NULL */
} Cursor;

static void fieldF64(Cursor *c, double *x)
{
    uint64_t u;
    if (c->wd) { memcpy(&u, x, 8); putU64(c->wd, u); c->wd += 8; }
    else { u = getU64(c->rd); memcpy(x, &u, 8); c->rd += 8; }
}

static void fieldI32(Cursor *c, int32_t *x)
{
    if (c->wi) { putI32(c->wi, *x); c->wi += 4; }
    else { *x = getI32(c->ri); c->ri += 4; }
}

static void walkFields(Cursor *c, const FmiModel *m, FmiRun *run, void *data)
{
    fieldF64(c, &run->time);
    fieldF64(c, &run->startTime);
    fieldF64(c, &run->stopTime);
    fieldI32(c, &run->initialized);
    fieldI32(c, &run->stopTimeDefined);
    fieldI32(c, &run->lastDoStepStatus);
    for (int i = 0; i < m->nFields; ++i) {
        const StateField *f = &m->fields[i];
        char *base = (char *)data + f->offset;
        for (int k = 0; k < f->count; ++k) {
            if (f->kind == FieldF64) fieldF64(c, (double *)(void *)base + k);
            else fieldI32(c, (int32_t *)(void *)base + k);
        }
    }
}

FmiStatus fmiStateSize(FmiInstance *inst, const char *fn, void *state, size_t *size)
{
    if (checkCopy(inst, fn, state) == NULL) return FmiError;
    *size = (size_t)layoutOf(inst->model).size;
    return FmiOK;
}

FmiStatus fmiStateSerialize(FmiInstance *inst, const char *fn, void *state, unsigned char p[], size_t size)
{
    const FmiModel *m = inst->model;
    const Layout l = layoutOf(m);
    FmiStateCopy *b = checkCopy(inst, fn, state);
    FmiRun run;
    Cursor c;
    if (b == NULL) return FmiError;
    if (size < (size_t)l.size) {
        fmiLogStatus(inst, FmiError, "%s: the buffer of %lu bytes is too small: %d bytes are needed "
                     "(%s)", fn, (unsigned long)size, (int)l.size, inst->face->serializedStateSize);
        return FmiError;
    }
    memcpy(p, SER_MAGIC, 8);
    putI32(p + 8, m->stateVersion);
    putI32(p + 12, l.size);
    putU64(p + 16, guidHash(m));
    putI32(p + 24, l.nDouble);
    putI32(p + 28, l.nInt);
    run = b->run;
    c.wd = p + SER_HEADER;
    c.wi = p + SER_HEADER + 8 * l.nDouble;
    c.rd = c.ri = NULL;
    walkFields(&c, m, &run, b->data); /* reads b->data only */
    putU64(p + l.size - 8, fnv1a(p, (size_t)l.size - 8));
    return FmiOK;
}

static int validRun(FmiInstance *inst, const char *fn, const FmiRun *r)
{
    if (r->initialized != 0 && r->initialized != 1) {
        fmiLogStatus(inst, FmiError, "%s: invalid initialized flag %d in the data", fn, (int)r->initialized);
        return 0;
    }
    if (!isfinite(r->time) || !isfinite(r->startTime) || !isfinite(r->stopTime) ||
        (r->stopTimeDefined != 0 && r->stopTimeDefined != 1) || r->lastDoStepStatus < FmiOK ||
        r->lastDoStepStatus > FmiFatal) {
        fmiLogStatus(inst, FmiError, "%s: invalid time or status fields in the data", fn);
        return 0;
    }
    return 1;
}

FmiStatus fmiStateDeserialize(FmiInstance *inst, const char *fn, const unsigned char p[], size_t size,
                              void **state)
{
    const FmiModel *m = inst->model;
    const Layout l = layoutOf(m);
    FmiRun run, savedRun;
    void *data, *savedData;
    int32_t savedBuilt, built = 0;
    Cursor c;
    FmiStateCopy *b;
    if (size < 16 || memcmp(p, SER_MAGIC, 8) != 0) {
        fmiLogStatus(inst, FmiError, "%s: not a %s FMU state (wrong magic or only %lu bytes)", fn, m->name,
                     (unsigned long)size);
        return FmiError;
    }
    if (getI32(p + 8) != m->stateVersion) {
        fmiLogStatus(inst, FmiError, "%s: state format version %d is not supported (this FMU reads version %d)", fn,
                     (int)getI32(p + 8), (int)m->stateVersion);
        return FmiError;
    }
    if (size != (size_t)l.size || getI32(p + 12) != l.size) {
        fmiLogStatus(inst, FmiError, "%s: the state has %lu bytes (header says %d); version %d has %d bytes", fn,
                     (unsigned long)size, (int)getI32(p + 12), (int)m->stateVersion, (int)l.size);
        return FmiError;
    }
    if (getU64(p + 16) != guidHash(m) || getI32(p + 24) != l.nDouble || getI32(p + 28) != l.nInt) {
        fmiLogStatus(inst, FmiError, "%s: the state was saved by another FMU (GUID hash or layout differs from "
                     "%s)", fn, m->guid);
        return FmiError;
    }
    if (getU64(p + l.size - 8) != fnv1a(p, (size_t)l.size - 8)) {
        fmiLogStatus(inst, FmiError, "%s: checksum mismatch: the state data is corrupted", fn);
        return FmiError;
    }
    data = calloc(1, m->dataSize > 0 ? m->dataSize : 1);
    if (data == NULL) {
        fmiLogStatus(inst, FmiError, "%s: out of memory", fn);
        return FmiError;
    }
    memset(&run, 0, sizeof run);
    c.wd = c.wi = NULL;
    c.rd = p + SER_HEADER;
    c.ri = p + SER_HEADER + 8 * l.nDouble;
    walkFields(&c, m, &run, data);
    if (!validRun(inst, fn, &run) || !fmiVariablesValid(inst, fn, data) ||
        (m->validData && !m->validData(inst, fn, data, run.initialized))) {
        free(data);
        return FmiError;
    }
    /* rebuild the derived data with the model's own build in the instance, then restore it */
    savedRun = inst->run;
    savedData = inst->data;
    savedBuilt = inst->built;
    inst->run = run;
    inst->data = data;
    if (run.initialized) {
        if (m->build(inst, fn, 0) != FmiOK) {
            inst->run = savedRun;
            inst->data = savedData;
            free(data);
            return FmiError;
        }
        built = 1;
    }
    inst->run = savedRun;
    inst->data = savedData;
    inst->built = savedBuilt;
    b = copyToFill(inst, fn, *state);
    if (b == NULL) {
        free(data);
        return FmiError;
    }
    b->fsm = run.initialized ? FsmStepComplete : FsmInstantiated;
    b->run = run;
    b->built = built;
    memcpy(b->data, data, m->dataSize);
    if (inst->me && b->meData) memset(b->meData, 0, inst->me->dataSize); /* not serialized */
    free(data);
    *state = b;
    return FmiOK;
}
