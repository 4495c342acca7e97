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
#include "models/Excitation/variables.h"

/* par: Fw0 [N/m], n0, n1 (speed before and after the ramp) [rpm], t0, t1 (ramp start, end) [s];
 * ipar: engineOrder, bladeIndex (0..bladeCount-1), bladeCount. Slots: variables.h (model.toml). */
typedef struct {
    double par[PAR_NUM];
    int32_t ipar[IPAR_NUM];
} ExcitationData;

typedef struct {
    double aeroLoad, rotorSpeed; /* outputs of the current get call */
} ExcitationMemory;

enum { OutAeroLoad = 0, OutRotorSpeed };

#define AT(member) (long)offsetof(ExcitationData, member)

#define PAR(k) AT(par[k])
#define IPAR(k) AT(ipar[k])

/* Sorted by value reference: generated from model.toml. */
static const VarInfo VARS[] = {
#include "models/Excitation/variables.inc"
};

/* n(t) [rpm] */
static double speedAt(const ExcitationData *e, double t)
{
    if (t <= e->par[ParT0]) return e->par[ParN0];
    if (t >= e->par[ParT1]) return e->par[ParN1];
    return e->par[ParN0] + (e->par[ParN1] - e->par[ParN0]) * (t - e->par[ParT0]) / (e->par[ParT1] - e->par[ParT0]);
}

/* int_0^t n(s) ds [rpm s], exact for the piecewise-linear profile */
static double speedIntegral(const ExcitationData *e, double t)
{
    const double slope = (e->par[ParN1] - e->par[ParN0]) / (e->par[ParT1] - e->par[ParT0]); /* [rpm/s] */
    if (t <= e->par[ParT0]) return e->par[ParN0] * t;
    if (t <= e->par[ParT1]) {
        const double s = t - e->par[ParT0];
        return e->par[ParN0] * t + 0.5 * slope * s * s;
    }
    {
        const double w = e->par[ParT1] - e->par[ParT0];
        return e->par[ParN0] * e->par[ParT1] + 0.5 * slope * w * w + e->par[ParN1] * (t - e->par[ParT1]);
    }
}

/* f_w(t) [N/m], eq. 17 */
static double aeroLoadAt(const ExcitationData *e, double t)
{
    const double twoPi = 2.0 * 3.14159265358979323846;
    const double psi = (double)e->ipar[IparEngineOrder] * (twoPi / 60.0) * speedIntegral(e, t);
    const double lead = twoPi * (double)e->ipar[IparEngineOrder] * (double)e->ipar[IparBladeIndex] / (double)e->ipar[IparBladeCount];
    return e->par[ParFw0] * sin(psi + lead); /* lead = 0 for blade 0: exactly the single-blade load */
}

/* The ramp needs t1 > t0 and the blade must be on the disk (the table checks the single values). */
static FmiStatus build(FmiInstance *inst, const char *fn, int initState)
{
    const ExcitationData *e = (const ExcitationData *)inst->data;
    (void)initState;
    if (!(e->par[ParT1] > e->par[ParT0])) {
        fmiLogStatus(inst, FmiError, "%s: the ramp needs t1 > t0, here t0 = %g s, t1 = %g s", fn, e->par[ParT0], e->par[ParT1]);
        return FmiError;
    }
    if (e->ipar[IparBladeIndex] >= e->ipar[IparBladeCount]) {
        fmiLogStatus(inst, FmiError, "%s: bladeIndex = %d must be in [0, bladeCount - 1] = [0, %d]", fn,
                     (int)e->ipar[IparBladeIndex], (int)e->ipar[IparBladeCount] - 1);
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
    .name = MODEL_NAME,
    .guid = MODEL_GUID,
    .vars = VARS,
    .nVars = (int)(sizeof VARS / sizeof VARS[0]),
    .dataSize = sizeof(ExcitationData),
    .memorySize = sizeof(ExcitationMemory),
    .canGetAndSetState = 0,
    .stateVersion = 1,
    .build = build,
    .outputs = outputs,
    .output = output,
    .doStep = doStep,
};

/* co-simulation only */
const FmiModelExchange *const fmiModelExchange = NULL;
