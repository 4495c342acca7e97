/* The ring's Jacobi communication loop in C (harness/system/ring_c.py): the data flow of the fmpy
 * master harness/system/ring.py (docs/model.md s.8) without Python between the FMI calls.
 *
 * The instances are made, parameterised and initialised by the harness through fmpy; this loop
 * gets their fmi2Component handles and the binaries' function pointers, and per communication
 * point t_k = (baseNs + (k - baseK) stepNs) / 1e9 (libcosim's integer-nanosecond grid; a sweep
 * changes the step with the speed and starts a new base there), or t_k = baseTime + (k - baseK) exactStep
 * when exactStep > 0 (the ring's period map: K steps make exactly one load period T, from t = 0; a
 * speed sweep: from a point where the load phase is a multiple of 2 pi / K at each speed):
 *   1. reads every blade's q, v, E, W (the blades make their own load; the speed is the setup's rpm);
 *   2. sets each contact j's inputs (blade j side A, blade j+1 side B) with the velocities'
 *      extrapolated derivatives, reads forceA, forceB, dissipatedEnergy (and contactState: readState);
 *   3. sets blade i's rotorSpeed, contactForce = forceB(i-1) + forceA(i) with the derivatives of
 *      contactForce;
 *   4. steps every FMU from t_k to t_{k+1}.
 * One call does the points first..last-1 with their steps, and point `last` without a step when
 * `finish` is set: a run may be cut into calls (a speed sweep changes rpm between them); the
 * histories live in `work` and `filled`, which the caller keeps between calls.
 * Derivatives: order 1..p of the polynomial through the last q + 1 <= p + 1 values (weights from the
 * harness, the same numbers ring.py uses). afterStep (libcosim's data flow, ring.py coupling
 * "libcosim"): from t_1 on, the blades get the forces the contacts reported at the end of their
 * own step, read before their inputs are set again. timeDoSteps: the time inside every fmi2DoStep
 * is added to *inside [s] (the FMUs' own compute, for harness/bench.py). A blade |q| above qLimit
 * (or not finite) stops the loop (RING_DIVERGED: a blowing-up Jacobi coupling, stopped before the
 * FMU's state overflows). A status above fmi2Warning stops the loop: the return value says which
 * call, *failStep and *failFmu where. */
#define _POSIX_C_SOURCE 199309L /* clock_gettime */
#include <math.h>
#include <stddef.h>
#include <string.h>
#include <time.h>

#include "fmi2Functions.h"

#define RING_MAX_ORDER 4

typedef struct {
    fmi2GetRealTYPE *getReal;
    fmi2SetRealTYPE *setReal;
    fmi2GetIntegerTYPE *getInteger;
    fmi2SetRealInputDerivativesTYPE *setRealInputDerivatives;
    fmi2DoStepTYPE *doStep;
} RingApi; /* one binary's functions (pointers handed over by ctypes) */

typedef struct {
    int n, first, last, finish;   /* N blades; points first..last (last stepped to only) */
    int order;                    /* extrapolation order p */
    int afterStep, timeDoSteps;   /* libcosim's data flow; time the doSteps */
    int recordEvery;              /* record t_k for (k - first) a multiple of it: row (k - first) / recordEvery */
    long long stepNs, baseNs;     /* communication step [ns]; t_baseK [ns] */
    int baseK;
    double rpm;                   /* rotor speed [rpm] of every blade and contact */
    double qLimit;                /* divergence: |q| above it [m] */
    const double *weights;        /* W[(q (p+1) + m) (p+1) + j]: derivative m at t_k of the order-q fit, value j steps back */
    RingApi blade, contact;
    void **blades, **contacts;    /* fmi2Component of each instance */
    unsigned int bladeOut[4];     /* tipDisplacement, tipVelocity, dissipatedEnergy, contactWork */
    unsigned int contactIn[5];    /* displacementA, velocityA, displacementB, velocityB, rotorSpeed */
    unsigned int contactOut[3];   /* forceA, forceB, dissipatedEnergy */
    unsigned int contactState;
    unsigned int bladeIn[2];      /* rotorSpeed, contactForce */
    double exactStep;             /* > 0: t_k = baseTime + (k - baseK) exactStep [s] (an exact period T = K exactStep), not the ns grid */
    double baseTime;              /* t_baseK [s] on the exact grid */
    int readState;                /* record contactState (an fmi2GetInteger per contact and point; 0: left 0) */
} RingSetup;

typedef struct {
    double *q, *v, *E, *W, *contactForce, *forceA, *forceB, *Ec, *state; /* rows x N, row-major */
} RingRecord;

enum { RING_OK = 0, RING_BAD_SETUP, RING_GET, RING_SET, RING_DERIVATIVES, RING_STEP, RING_DIVERGED };

/* A signal's last p + 1 values, newest first (ring.py's _History). */
typedef struct {
    double *buf; /* (p + 1) x N */
    int *filled;
} History;

/* Pushes y (N values) and writes derivatives 1..p at t_k into d (p x N; zero beyond the history). */
static void historyPush(History *h, const RingSetup *s, const double *y, double *d) {
    const int n = s->n, p = s->order, P = p + 1;
    memmove(h->buf + n, h->buf, sizeof(double) * (size_t)(p * n));
    memcpy(h->buf, y, sizeof(double) * (size_t)n);
    if (*h->filled < P) (*h->filled)++;
    const int q = *h->filled - 1;
    for (int m = 1; m <= p; m++)
        for (int i = 0; i < n; i++) {
            double acc = 0.0;
            if (m <= q)
                for (int j = 0; j <= q; j++) acc += s->weights[(q * P + m) * P + j] * h->buf[j * n + i];
            d[(m - 1) * n + i] = acc;
        }
}

/* Sets derivatives 1..p of the inputs vrs[0..count-1] from columns col of the arrays d[0..count-1]. */
static int setDerivatives(const RingApi *api, void *c, const RingSetup *s, int count, const unsigned int *vrs,
                          const double *const *d, const int *col) {
    fmi2ValueReference vr[2 * RING_MAX_ORDER];
    fmi2Integer ord[2 * RING_MAX_ORDER];
    fmi2Real val[2 * RING_MAX_ORDER];
    const int p = s->order;
    for (int a = 0; a < count; a++)
        for (int m = 0; m < p; m++)
            vr[a * p + m] = vrs[a], ord[a * p + m] = m + 1, val[a * p + m] = d[a][m * s->n + col[a]];
    return api->setRealInputDerivatives(c, vr, (size_t)(count * p), ord, val) > fmi2Warning;
}

#define FAIL(code, fmu) do { *failFmu = (fmu); return (code); } while (0)

static double now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* fmi2DoStep, timed into *inside when asked */
static int doStep(fmi2DoStepTYPE *f, void *c, double t, double h, int timed, double *inside) {
    if (!timed) return f(c, t, h, fmi2True) > fmi2Warning;
    const double t0 = now();
    const fmi2Status st = f(c, t, h, fmi2True);
    *inside += now() - t0;
    return st > fmi2Warning;
}

/* Reads contact j's forces, energy and state into fA, fB and the record row. */
static int readContact(const RingSetup *s, int j, double *fA, double *fB, RingRecord *r, size_t row) {
    double out[3];
    fmi2Integer state;
    if (s->contact.getReal(s->contacts[j], s->contactOut, 3, out) > fmi2Warning) return 1;
    fA[j] = out[0], fB[j] = out[1];
    r->forceA[row + j] = out[0], r->forceB[row + j] = out[1], r->Ec[row + j] = out[2];
    if (!s->readState) return 0;
    if (s->contact.getInteger(s->contacts[j], &s->contactState, 1, &state) > fmi2Warning) return 1;
    r->state[row + j] = (double)state;
    return 0;
}

/* Runs the loop; work holds 2 (p + 1) N + 2 p N + 18 N doubles (the histories of v and of the
 * contact force first), filled 2 ints (zero at the start of a run; both kept between the calls of
 * one run). */
int ringRun(const RingSetup *s, RingRecord *rec, double *work, int *filled, int *failStep, int *failFmu,
            double *inside) {
    const int n = s->n, p = s->order;
    if (n < 2 || s->first < 0 || s->last < s->first || p < 0 || p > RING_MAX_ORDER || s->recordEvery < 1 ||
        (s->last - s->first) % s->recordEvery || s->stepNs <= 0 || !(s->exactStep >= 0.0) || !isfinite(s->baseTime))
        return RING_BAD_SETUP;
    History hv = {work, filled}, hf = {work + (p + 1) * n, filled + 1};
    double *dv = work + 2 * (p + 1) * n, *df = dv + p * n;
    double *q = df + p * n, *v = q + n, *fA = v + n, *fB = fA + n;
    double *force = fB + n, *st = force + n; /* st: one blade's 4 values, then 9 scratch records */
    RingRecord scratch = {st + 4 * n, st + 5 * n, st + 6 * n, st + 7 * n, st + 8 * n, st + 9 * n, st + 10 * n,
                          st + 11 * n, st + 12 * n}; /* rows not kept are written here (row 0) */
    fmi2GetRealTYPE *bGet = s->blade.getReal;
    fmi2SetRealTYPE *cSet = s->contact.setReal, *bSet = s->blade.setReal;
    const int timed = s->timeDoSteps;
    const double *const dBlade[1] = {df};
    const double *const dContact[2] = {dv, dv};
    const unsigned int cVr[2] = {s->contactIn[1], s->contactIn[3]};
    for (int k = s->first; k <= s->last; k++) {
        if (k == s->last && !s->finish) break;
        const int kept = (k - s->first) % s->recordEvery == 0;
        RingRecord *r = kept ? rec : &scratch;
        const size_t row = kept ? (size_t)((k - s->first) / s->recordEvery) * (size_t)n : 0;
        *failStep = k;
        for (int i = 0; i < n; i++) {
            if (bGet(s->blades[i], s->bladeOut, 4, st) > fmi2Warning) FAIL(RING_GET, i);
            q[i] = st[0], v[i] = st[1];
            r->q[row + i] = st[0], r->v[row + i] = st[1], r->E[row + i] = st[2], r->W[row + i] = st[3];
            if (!(fabs(st[0]) <= s->qLimit)) FAIL(RING_DIVERGED, i);
        }
        historyPush(&hv, s, v, dv);
        const int lagged = s->afterStep && k > 0; /* libcosim: the outputs of the step just done */
        for (int j = 0; j < n; j++) {
            const int a = j, b = (j + 1) % n;
            const double in[5] = {q[a], v[a], q[b], v[b], s->rpm};
            const int cols[2] = {a, b};
            if (lagged && readContact(s, j, fA, fB, r, row)) FAIL(RING_GET, n + j);
            if (cSet(s->contacts[j], s->contactIn, 5, in) > fmi2Warning) FAIL(RING_SET, n + j);
            if (p > 0 && setDerivatives(&s->contact, s->contacts[j], s, 2, cVr, dContact, cols))
                FAIL(RING_DERIVATIVES, n + j);
            if (!lagged && readContact(s, j, fA, fB, r, row)) FAIL(RING_GET, n + j); /* feedthrough */
        }
        for (int i = 0; i < n; i++) force[i] = fB[(i + n - 1) % n] + fA[i];
        historyPush(&hf, s, force, df);
        memcpy(r->contactForce + row, force, sizeof(double) * (size_t)n);
        if (k == s->last) break;
        for (int i = 0; i < n; i++) {
            const double in[2] = {s->rpm, force[i]};
            const int cols[1] = {i};
            if (bSet(s->blades[i], s->bladeIn, 2, in) > fmi2Warning) FAIL(RING_SET, i);
            if (p > 0 && setDerivatives(&s->blade, s->blades[i], s, 1, s->bladeIn + 1, dBlade, cols))
                FAIL(RING_DERIVATIVES, i);
        }
        const double t = s->exactStep > 0.0 ? s->baseTime + (double)(k - s->baseK) * s->exactStep
                                            : (double)(s->baseNs + (long long)(k - s->baseK) * s->stepNs) / 1e9;
        const double h = s->exactStep > 0.0 ? s->baseTime + (double)(k + 1 - s->baseK) * s->exactStep - t
                                            : (double)(s->baseNs + (long long)(k + 1 - s->baseK) * s->stepNs) / 1e9 - t;
        for (int i = 0; i < n; i++)
            if (doStep(s->blade.doStep, s->blades[i], t, h, timed, inside)) FAIL(RING_STEP, i);
        for (int j = 0; j < n; j++)
            if (doStep(s->contact.doStep, s->contacts[j], t, h, timed, inside)) FAIL(RING_STEP, n + j);
    }
    return RING_OK;
}
