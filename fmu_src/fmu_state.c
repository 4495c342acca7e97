/* FMU states of ShroudedBlade: copies of the instance data owned by the instance (fmi2Get/Set/
 * FreeFMUstate) and their serialization, a versioned, pointer-free, little-endian byte format that
 * is checked (magic, version, size, GUID hash, checksum, every value) before it is used. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "config.h"
#include "instance_internal.h"

/* ------------------------------------------------------------------------------------------- */
/* FMU state objects                                                                           */

#define BLOB_MAGIC 0x53426c6164655331ULL /* "SBladeS1" */

struct StateBlob {
    uint64_t magic;
    Instance *owner; /* the instance whose list holds this blob */
    StateBlob *prev, *next;
    InstanceData d;
};

static void unlinkBlob(StateBlob *b)
{
    if (b->owner) {
        if (b->prev) b->prev->next = b->next;
        else b->owner->states = b->next;
        if (b->next) b->next->prev = b->prev;
    }
    b->owner = NULL;
    b->prev = b->next = NULL;
}

static StateBlob *newBlob(Instance *inst)
{
    StateBlob *b = (StateBlob *)calloc(1, sizeof *b);
    if (b == NULL) return NULL;
    b->magic = BLOB_MAGIC;
    b->owner = inst;
    b->next = inst->states;
    if (inst->states) inst->states->prev = b;
    inst->states = b;
    return b;
}

static void destroyBlob(StateBlob *b)
{
    unlinkBlob(b);
    b->magic = 0;
    free(b);
}

void fmuStateFreeAll(Instance *inst)
{
    while (inst->states) destroyBlob(inst->states);
}

static StateBlob *checkBlob(Instance *inst, const char *fn, fmi2FMUstate state)
{
    StateBlob *b = (StateBlob *)state;
    if (b == NULL || b->magic != BLOB_MAGIC) {
        instanceLogStatus(inst, fmi2Error, "%s: the FMU state %p was not created by this FMU (or was freed)", fn,
                          state);
        return NULL;
    }
    return b;
}

/* The blob to fill: the caller's state (checked) to overwrite, or a new one if it passes NULL. */
static StateBlob *blobToFill(Instance *inst, const char *fn, fmi2FMUstate state)
{
    StateBlob *b;
    if (state != NULL) return checkBlob(inst, fn, state);
    b = newBlob(inst);
    if (b == NULL) instanceLogStatus(inst, fmi2Error, "%s: out of memory", fn);
    return b;
}

fmi2Status instanceGetState(Instance *inst, fmi2FMUstate *state)
{
    StateBlob *b = blobToFill(inst, "fmi2GetFMUstate", *state);
    if (b == NULL) return fmi2Error;
    b->d = inst->d;
    *state = (fmi2FMUstate)b;
    return fmi2OK;
}

fmi2Status instanceSetState(Instance *inst, fmi2FMUstate state)
{
    const StateBlob *b = checkBlob(inst, "fmi2SetFMUstate", state);
    if (b == NULL) return fmi2Error;
    inst->d = b->d;
    return fmi2OK;
}

fmi2Status instanceFreeState(Instance *inst, fmi2FMUstate *state)
{
    StateBlob *b;
    if (*state == NULL) return fmi2OK;
    b = checkBlob(inst, "fmi2FreeFMUstate", *state);
    if (b == NULL) return fmi2Error;
    destroyBlob(b);
    *state = NULL;
    return fmi2OK;
}

/* Serialization: versioned, pointer-free, little-endian.
 *   offset 0   8 bytes  magic "SBLDSTAT"
 *          8   int32    format version (2: the start values of jenkinsForce and runningMaximum
 *                       joined the parameters; version 1 blobs are refused)
 *         12   int32    total size in bytes
 *         16   uint64   FNV-1a 64 hash of the GUID
 *         24   int32    number of doubles (SER_NDOUBLE), int32 number of int32 (SER_NINT)
 *         32   doubles  IEEE 754 binary64, little-endian (list in walkFields)
 *              int32    two's complement, little-endian
 *   size - 8   uint64   FNV-1a 64 checksum of all preceding bytes                             */

#define SER_VERSION 2 /* bump whenever walkFields changes */
#define SER_HEADER 32
#define SER_NDOUBLE (PAR_NUM + SOLVER_NUM_INPUTS * (SOLVER_MAX_ORDER + 1) + 3 + 8)
#define SER_NINT (1 + IPAR_NUM + 3 + 4)
#define SER_SIZE (SER_HEADER + 8 * SER_NDOUBLE + 4 * SER_NINT + 8)
static const unsigned char SER_MAGIC[8] = {'S', 'B', 'L', 'D', 'S', 'T', 'A', 'T'};

static uint64_t fnv1a(const unsigned char *p, size_t n)
{
    uint64_t h = 14695981039346656037ULL;
    for (size_t i = 0; i < n; ++i) {
        h ^= p[i];
        h *= 1099511628211ULL;
    }
    return h;
}

static uint64_t guidHash(void) { return fnv1a((const unsigned char *)MODEL_GUID, strlen(MODEL_GUID)); }

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
    for (int i = 0; i < 4; ++i) u |= (uint32_t)p[i] << (8 * i);
    int32_t x;
    memcpy(&x, &u, sizeof x); /* int32_t is two's complement */
    return x;
}
static void putF64(unsigned char *p, double x)
{
    uint64_t u;
    memcpy(&u, &x, sizeof u);
    putU64(p, u);
}
static double getF64(const unsigned char *p)
{
    const uint64_t u = getU64(p);
    double x;
    memcpy(&x, &u, sizeof x);
    return x;
}

/* The field lists: one function walks the fields in a fixed order for both directions. */
typedef struct {
    unsigned char *wp;       /* writing, or NULL */
    const unsigned char *rp; /* reading, or NULL */
} Cursor;

static void fieldF64(Cursor *c, double *x)
{
    if (c->wp) { putF64(c->wp, *x); c->wp += 8; }
    else { *x = getF64(c->rp); c->rp += 8; }
}

static void fieldI32(Cursor *c, int32_t *x)
{
    if (c->wp) { putI32(c->wp, *x); c->wp += 4; }
    else { *x = getI32(c->rp); c->rp += 4; }
}

static void walkFields(Cursor *c, InstanceData *d)
{
    int i, j;
    /* doubles */
    for (i = 0; i < PAR_NUM; ++i) fieldF64(c, &d->par[i]);
    for (i = 0; i < SOLVER_NUM_INPUTS; ++i)
        for (j = 0; j <= SOLVER_MAX_ORDER; ++j) fieldF64(c, &d->in[i][j]);
    fieldF64(c, &d->time);
    fieldF64(c, &d->startTime);
    fieldF64(c, &d->stopTime);
    fieldF64(c, &d->solver.q);
    fieldF64(c, &d->solver.v);
    fieldF64(c, &d->solver.psi);
    fieldF64(c, &d->solver.E);
    fieldF64(c, &d->solver.w);
    fieldF64(c, &d->solver.B);
    fieldF64(c, &d->solver.windowMax);
    fieldF64(c, &d->solver.periods);
    /* int32 */
    fieldI32(c, &d->fsm);
    for (i = 0; i < IPAR_NUM; ++i) fieldI32(c, &d->ipar[i]);
    fieldI32(c, &d->stopTimeDefined);
    fieldI32(c, &d->lastDoStepStatus);
    fieldI32(c, &d->warnedFullStick);
    fieldI32(c, &d->solver.mode);
    fieldI32(c, &d->solver.side);
    fieldI32(c, &d->solver.slipDir);
    fieldI32(c, &d->solver.vdir);
}

fmi2Status instanceSerializedSize(Instance *inst, fmi2FMUstate state, size_t *size)
{
    if (checkBlob(inst, "fmi2SerializedFMUstateSize", state) == NULL) return fmi2Error;
    *size = SER_SIZE;
    return fmi2OK;
}

fmi2Status instanceSerialize(Instance *inst, fmi2FMUstate state, fmi2Byte buffer[], size_t size)
{
    StateBlob *b = checkBlob(inst, "fmi2SerializeFMUstate", state);
    unsigned char *p = (unsigned char *)buffer;
    InstanceData copy;
    Cursor c;
    if (b == NULL) return fmi2Error;
    if (size < SER_SIZE) {
        instanceLogStatus(inst, fmi2Error, "fmi2SerializeFMUstate: the buffer of %lu bytes is too small: %d bytes "
                          "are needed (fmi2SerializedFMUstateSize)", (unsigned long)size, SER_SIZE);
        return fmi2Error;
    }
    memcpy(p, SER_MAGIC, 8);
    putI32(p + 8, SER_VERSION);
    putI32(p + 12, SER_SIZE);
    putU64(p + 16, guidHash());
    putI32(p + 24, SER_NDOUBLE);
    putI32(p + 28, SER_NINT);
    copy = b->d;
    c.wp = p + SER_HEADER;
    c.rp = NULL;
    walkFields(&c, &copy);
    putU64(p + SER_SIZE - 8, fnv1a(p, SER_SIZE - 8));
    return fmi2OK;
}

static int validState(Instance *inst, const char *fn, InstanceData *d)
{
    const SolverState *s = &d->solver;
    const int32_t okFsm = FsmInstantiated | FsmInitializationMode | FsmStepComplete | FsmStepFailed |
                          FsmStepCanceled | FsmTerminated | FsmError;
    const int td = d->ipar[IparFrictionModel] == FrictionMacroslipTD;
    int i;
    if (d->fsm <= 0 || (d->fsm & (d->fsm - 1)) != 0 || (d->fsm & okFsm) == 0) {
        instanceLogStatus(inst, fmi2Error, "%s: invalid state machine state %d in the data", fn, (int)d->fsm);
        return 0;
    }
    if (!variablesValid(inst, fn, d)) return 0;
    for (i = 0; i < SOLVER_NUM_INPUTS; ++i)
        for (int j = 1; j <= SOLVER_MAX_ORDER; ++j)
            if (!isfinite(d->in[i][j])) {
                instanceLogStatus(inst, fmi2Error, "%s: input derivative not finite in the data", fn);
                return 0;
            }
    if (!isfinite(d->time) || !isfinite(d->startTime) || !isfinite(d->stopTime) ||
        (d->stopTimeDefined != 0 && d->stopTimeDefined != 1) || d->lastDoStepStatus < fmi2OK ||
        d->lastDoStepStatus > fmi2Fatal || (d->warnedFullStick != 0 && d->warnedFullStick != 1)) {
        instanceLogStatus(inst, fmi2Error, "%s: invalid time or status fields in the data", fn);
        return 0;
    }
    if (instancePreInit(d)) return 1; /* the solver state is rebuilt at fmi2ExitInitializationMode */
    if (!isfinite(s->q) || !isfinite(s->v) || !isfinite(s->psi) || !isfinite(s->E) || !isfinite(s->w) ||
        !(s->B >= 0.0) || !isfinite(s->B) || !(s->windowMax >= 0.0) || !isfinite(s->windowMax) ||
        !(s->periods >= 0.0) || s->periods > 9e15 || s->periods != floor(s->periods) ||
        s->mode < 0 || s->mode > (td ? 2 : 1) || (s->side != 1 && s->side != -1) ||
        (s->slipDir != 1 && s->slipDir != -1) || (s->vdir != 1 && s->vdir != -1)) {
        instanceLogStatus(inst, fmi2Error, "%s: invalid solver state in the data", fn);
        return 0;
    }
    return 1;
}

fmi2Status instanceDeserialize(Instance *inst, const fmi2Byte buffer[], size_t size, fmi2FMUstate *state)
{
    const char *fn = "fmi2DeSerializeFMUstate";
    const unsigned char *p = (const unsigned char *)buffer;
    InstanceData saved, tmp;
    Cursor c;
    StateBlob *b;
    if (size < 16 || memcmp(p, SER_MAGIC, 8) != 0) {
        instanceLogStatus(inst, fmi2Error, "%s: not a ShroudedBlade FMU state (wrong magic or only %lu bytes)", fn,
                          (unsigned long)size);
        return fmi2Error;
    }
    if (getI32(p + 8) != SER_VERSION) {
        instanceLogStatus(inst, fmi2Error, "%s: state format version %d is not supported (this FMU reads version %d)",
                          fn, (int)getI32(p + 8), SER_VERSION);
        return fmi2Error;
    }
    if (size != SER_SIZE || getI32(p + 12) != SER_SIZE) {
        instanceLogStatus(inst, fmi2Error, "%s: the state has %lu bytes (header says %d); version %d has %d bytes", fn,
                          (unsigned long)size, (int)getI32(p + 12), SER_VERSION, SER_SIZE);
        return fmi2Error;
    }
    if (getU64(p + 16) != guidHash() || getI32(p + 24) != SER_NDOUBLE || getI32(p + 28) != SER_NINT) {
        instanceLogStatus(inst, fmi2Error, "%s: the state was saved by another FMU (GUID hash or layout differs from "
                          "%s)", fn, MODEL_GUID);
        return fmi2Error;
    }
    if (getU64(p + SER_SIZE - 8) != fnv1a(p, SER_SIZE - 8)) {
        instanceLogStatus(inst, fmi2Error, "%s: checksum mismatch: the state data is corrupted", fn);
        return fmi2Error;
    }
    memset(&tmp, 0, sizeof tmp);
    c.wp = NULL;
    c.rp = p + SER_HEADER;
    walkFields(&c, &tmp);
    if (!validState(inst, fn, &tmp)) return fmi2Error;
    /* rebuild the derived part with the instance's own machinery, then restore the instance */
    saved = inst->d;
    inst->d = tmp;
    if (!instancePreInit(&tmp)) {
        if (instanceBuildModel(inst, fn, 0) != fmi2OK && tmp.fsm != FsmError) {
            inst->d = saved;
            return fmi2Error;
        }
    }
    tmp = inst->d;
    inst->d = saved;
    b = blobToFill(inst, fn, *state);
    if (b == NULL) return fmi2Error;
    b->d = tmp;
    *state = (fmi2FMUstate)b;
    return fmi2OK;
}
