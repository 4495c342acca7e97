/* The Excitation model (the ShroudedBlade system example's load source) for the generic FMI layer.
 *
 * Outputs at the communication point t (no states, no inputs):
 *   rotorSpeed n(t) [rpm]: n0 before t0, linear to n1 at t1, n1 after (a run-up when n1 > n0);
 *   aeroLoad f_w(t) [N/m] = Fw0 sin(psi_e(t) + 2 pi engineOrder bladeIndex / bladeCount),
 *   psi_e = engineOrder * (2 pi / 60) * int_0^t n ds (paper eq. 17 with Omega = 2 pi n / 60,
 *   phase-continuous over the ramp; closed-form integral). The second term is the travelling wave
 *   on a disk of bladeCount blades: blade i sits 2 pi i / bladeCount ahead of blade 0 and meets the
 *   engine-fixed pattern of engineOrder lobes that much earlier (blade 0 of 1: the paper's load).
 * The time is the layer's: the master's last communication point plus the step size. */
#include <math.h>
#include <stddef.h>

#include "fmi/log.h"
#include "fmi/model.h"
#include "models/Excitation/config.h"

typedef struct {
    double fw0;          /* load amplitude [N/m] */
    double n0;           /* speed before the ramp [rpm] */
    double n1;           /* speed after the ramp [rpm] */
    double t0;           /* ramp start [s] */
    double t1;           /* ramp end [s] */
    int32_t engineOrder; /* excitation order [-] */
    int32_t bladeIndex;  /* this blade's place on the disk, 0..bladeCount-1 [-] */
    int32_t bladeCount;  /* blades on the disk [-] */
} ExcitationData;

typedef struct {
    double aeroLoad, rotorSpeed; /* outputs of the current get call */
} ExcitationMemory;

enum { OutAeroLoad = 0, OutRotorSpeed };

#define INF HUGE_VAL
#define AT(member) (long)offsetof(ExcitationData, member)

/* Sorted by value reference. */
static const VarInfo VARS[] = {
    {1, "Fw0", VarReal, CausParameter, "N/m", 100.0, -INF, INF, 0, 0, AT(fw0), -1},
    {2, "n0", VarReal, CausParameter, "rpm", 5000.0, 0.0, INF, 0, 0, AT(n0), -1},
    {3, "n1", VarReal, CausParameter, "rpm", 5000.0, 0.0, INF, 0, 0, AT(n1), -1},
    {4, "t0", VarReal, CausParameter, "s", 0.0, -INF, INF, 0, 0, AT(t0), -1},
    {5, "t1", VarReal, CausParameter, "s", 1.0, -INF, INF, 0, 0, AT(t1), -1},
    {6, "engineOrder", VarInteger, CausParameter, "", 3, 1, 100, 0, 0, AT(engineOrder), -1},
    {7, "bladeIndex", VarInteger, CausParameter, "", 0, 0, 9999, 0, 0, AT(bladeIndex), -1},
    {8, "bladeCount", VarInteger, CausParameter, "", 1, 1, 10000, 0, 0, AT(bladeCount), -1},
    {10, "aeroLoad", VarReal, CausOutput, "N/m", 0.0, -INF, INF, 0, 0, VAR_NO_OFFSET, OutAeroLoad},
    {11, "rotorSpeed", VarReal, CausOutput, "rpm", 0.0, -INF, INF, 0, 0, VAR_NO_OFFSET, OutRotorSpeed},
};

/* n(t) [rpm] */
static double speedAt(const ExcitationData *e, double t)
{
    if (t <= e->t0) return e->n0;
    if (t >= e->t1) return e->n1;
    return e->n0 + (e->n1 - e->n0) * (t - e->t0) / (e->t1 - e->t0);
}

/* int_0^t n(s) ds [rpm s], exact for the piecewise-linear profile */
static double speedIntegral(const ExcitationData *e, double t)
{
    const double slope = (e->n1 - e->n0) / (e->t1 - e->t0); /* [rpm/s] */
    if (t <= e->t0) return e->n0 * t;
    if (t <= e->t1) {
        const double s = t - e->t0;
        return e->n0 * t + 0.5 * slope * s * s;
    }
    {
        const double w = e->t1 - e->t0;
        return e->n0 * e->t1 + 0.5 * slope * w * w + e->n1 * (t - e->t1);
    }
}

/* f_w(t) [N/m], eq. 17 */
static double aeroLoadAt(const ExcitationData *e, double t)
{
    const double twoPi = 2.0 * 3.14159265358979323846;
    const double psi = (double)e->engineOrder * (twoPi / 60.0) * speedIntegral(e, t);
    const double lead = twoPi * (double)e->engineOrder * (double)e->bladeIndex / (double)e->bladeCount;
    return e->fw0 * sin(psi + lead); /* lead = 0 for blade 0: exactly the single-blade load */
}

/* The ramp needs t1 > t0 and the blade must be on the disk (the table checks the single values). */
static FmiStatus build(FmiInstance *inst, const char *fn, int initState)
{
    const ExcitationData *e = (const ExcitationData *)inst->data;
    (void)initState;
    if (!(e->t1 > e->t0)) {
        fmiLogStatus(inst, FmiError, "%s: the ramp needs t1 > t0, here t0 = %g s, t1 = %g s", fn, e->t0, e->t1);
        return FmiError;
    }
    if (e->bladeIndex >= e->bladeCount) {
        fmiLogStatus(inst, FmiError, "%s: bladeIndex = %d must be in [0, bladeCount - 1] = [0, %d]", fn,
                     (int)e->bladeIndex, (int)e->bladeCount - 1);
        return FmiError;
    }
    return FmiOK;
}

static void outputs(FmiInstance *inst)
{
    const ExcitationData *e = (const ExcitationData *)inst->data;
    ExcitationMemory *o = (ExcitationMemory *)inst->memory;
    o->aeroLoad = aeroLoadAt(e, inst->run.time);
    o->rotorSpeed = speedAt(e, inst->run.time);
}

static double output(const FmiInstance *inst, int id)
{
    const ExcitationMemory *o = (const ExcitationMemory *)inst->memory;
    return id == OutAeroLoad ? o->aeroLoad : o->rotorSpeed;
}

/* No state: the outputs are functions of the time. */
static FmiStatus doStep(FmiInstance *inst, const char *fn, double tc, double h)
{
    (void)inst; (void)fn; (void)tc; (void)h;
    return FmiOK;
}

const FmiModel fmiModel = {
    MODEL_NAME, MODEL_GUID, VARS, (int)(sizeof VARS / sizeof VARS[0]), 0,
    sizeof(ExcitationData), sizeof(ExcitationMemory), 0, 1, NULL, 0,
    NULL, build, NULL, outputs, output, NULL, doStep, NULL, NULL,
};

/* co-simulation only */
const FmiModelExchange *const fmiModelExchange = NULL;
