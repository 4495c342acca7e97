/* The BladeExternalContact model for the generic FMI layer: the blade of ShroudedBlade (Galerkin
 * reduction, docs/model.md s.2) without a built-in contact; the contact force at the contact
 * coordinate is an input (docs/model.md s.8):
 *   M q'' + C0 q' + K0(Omega) q = G f_w(t) + F(t),   E' = C0 q'^2,   W' = F q',
 * f_w = aeroLoad + Fw0 sin(psi + 2 pi engineOrder bladeIndex / bladeCount) (the built-in load, psi
 * the integrated excitation phase, as ShroudedBlade).
 * F (contactForce) is the force ON the blade, positive along q. The physics, the integrator and the
 * step are ShroudedBlade's (physics/dynamics with FrictionNone, solver/rk4_events, solver/blade_step),
 * so with F = 0 the
 * trajectory is bit-identical to ShroudedBlade with the contact open and no amplitude events
 * (amplitudeMode 1, d > max |q|), given the same communication points and inputs. */
#include <math.h>
#include <stddef.h>

#include "fmi/log.h"
#include "fmi/model.h"
#include "models/BladeExternalContact/variables.h"
#include "physics/dynamics_step.h"
#include "solver/blade_modes.h"
#include "solver/blade_step.h"

#define NUM_FORCES 2 /* contactForce, contactForce2: summed (a master that cannot add signals
                        connects one contact to each) */
#define NUM_INPUTS (SOLVER_INPUT_FORCE + NUM_FORCES) /* aeroLoad, rotorSpeed, the forces */

typedef struct {
    double par[PAR_NUM];                                  /* [units of the XML]; slots: variables.h */
    int32_t ipar[IPAR_NUM];                               /* formulation, the built-in load's travelling
                                                             wave, m bending modes (docs/model.md s.2a) */
    double in[NUM_INPUTS][SOLVER_MAX_ORDER + 1];          /* input values and derivatives [unit/s^j] */
    DynState state;                                       /* q, q', E, W (psi, w unused) */
    /* derived (rebuilt, not serialized) */
    BladeReduction blade;
    DynModel model;
    double curvature[MODES_MAX];                          /* phi_i''(0), phi_i(l) = 1 [1/m^2] */
} BxData;

typedef struct {
    DynOutputs out;
    SolverCounters counters;
    BladeModesCache modesCache;
    double frequencies[MODES_MAX];                        /* modeFrequency [Hz] */
    /* the last reduction: a reset and re-initialised instance (the ring's period map does that every
     * period) reuses it */
    BladeReductionCache reductionCache;
} BxMemory;

enum { OutQ = 0, OutV, OutEnergy, OutW, OutFrequency, OutModalQ1, OutModalV1 = OutModalQ1 + MODES_MAX,
       OutModeFrequency1 = OutModalV1 + MODES_MAX, OutRootMoment = OutModeFrequency1 + MODES_MAX };

#define AT(member) (long)offsetof(BxData, member)
#define PAR(k) AT(par[k])
#define IPAR(k) AT(ipar[k])
#define INPUT(k) AT(in[k][0])
#define DATA(inst) ((BxData *)(inst)->data)

/* Sorted by value reference: generated from model.toml (the blade's variables from ../blade.toml,
 * with ShroudedBlade's value references). */
static const VarInfo VARS[] = {
#include "models/BladeExternalContact/variables.inc"
};
/* the spec's bounds and array sizes agree with the C constants (a negative array size otherwise) */
typedef char SpecAgreesWithC[(max_modes == MODES_MAX && PAR_NUM == ParVm0 + MODES_MAX) ? 1 : -1];

#define COUNT(member) (int)(sizeof(((BxData *)0)->member) / sizeof(((BxData *)0)->member[0]))
#define F64(member) {AT(member), FieldF64, 1}

static const StateField FIELDS[] = {
    {AT(par), FieldF64, COUNT(par)},
    {AT(in), FieldF64, COUNT(in) * COUNT(in[0])},
    F64(state.q), F64(state.v), F64(state.psi), F64(state.E), F64(state.W),
    {AT(ipar), FieldI32, COUNT(ipar)},
    {AT(state.qx), FieldF64, MODES_MAX - 1}, {AT(state.vx), FieldF64, MODES_MAX - 1},
};
/* 4: the integer parameters in one block (ipar, slots generated from model.toml); 3: the modes; 2: the
 * built-in load's parameters joined */
#define STATE_VERSION 4

/* Reduction, dynamics constants (FrictionNone: no contact), and at the end of initialization the
 * start state. */
static FmiStatus build(FmiInstance *inst, const char *fn, int initState)
{
    BxData *d = DATA(inst);
    const double *p = d->par;
    BladeParams bp;
    bp = bladeParamsOf(&p[ParEI]); /* ParEI..ParM0 in that order */
    if (bladeReduceReusing(&((BxMemory *)inst->memory)->reductionCache, &bp, (Formulation)d->ipar[IparFormulation],
                           &d->blade) != 0 || !(d->blade.K0static > 0.0) ||
        dynBuildModel(&d->model, &d->blade, NULL, FrictionNone, ProjectionPaper, 0, 0, d->ipar[IparEngineOrder]) != 0) {
        fmiLogStatus(inst, FmiError,
                     "%s: the Galerkin reduction (eq. 19-26) failed for EI = %g N.m2, rho = %g kg/m3, "
                     "A = %g m2, l = %g m, c = %g N.s/m2, m0 = %g kg, formulation = %d: the blade "
                     "parameters are not usable together", fn, bp.EI, bp.rho, bp.A, bp.l, bp.c, bp.m0,
                     (int)d->ipar[IparFormulation]);
        return FmiError;
    }
    if (d->ipar[IparBladeIndex] >= d->ipar[IparBladeCount]) {
        fmiLogStatus(inst, FmiError, "%s: bladeIndex = %d must be in [0, bladeCount - 1] = [0, %d]", fn,
                     (int)d->ipar[IparBladeIndex], (int)d->ipar[IparBladeCount] - 1);
        return FmiError;
    }
    dynSetLoad(&d->model, p[ParFw0], d->ipar[IparEngineOrder], d->ipar[IparBladeIndex], d->ipar[IparBladeCount]);
    {
        const BladeModesSetup setup = {d->ipar[IparModes], d->ipar[IparFormulation], p[ParMaxStep], d->in[SOLVER_INPUT_SPEED][0]};
        if (bladeModesBuild(inst, fn, &setup, &bp, &d->blade, &((BxMemory *)inst->memory)->modesCache, &d->model,
                            d->curvature) != FmiOK)
            return FmiError;
    }
    if (initState) {
        double u0, du0;
        if (bladeModesStart(inst, fn, d->ipar[IparModes], p[ParQ0], p[ParV0], &p[ParQm0], &p[ParVm0], &u0, &du0) != FmiOK)
            return FmiError;
        (void)dynInitState(&d->model, &d->state, u0, du0, p[ParE0], 0.0, 0.0, 0.0);
        bladeModesInitState(&d->model, &d->state, &p[ParQm0], &p[ParVm0]);
        d->state.W = p[ParW0];
    }
    return FmiOK;
}

static void outputs(FmiInstance *inst)
{
    const BxData *d = DATA(inst);
    BxMemory *mem = (BxMemory *)inst->memory;
    dynOutputs(&d->model, &d->state, d->in[SOLVER_INPUT_SPEED][0], &mem->out);
    dynModeFrequencies(&d->model, d->in[SOLVER_INPUT_SPEED][0], mem->frequencies);
    if (d->model.modes > 1) mem->out.naturalFrequency = mem->frequencies[0];
}

static double output(const FmiInstance *inst, int id)
{
    const BxData *d = DATA(inst);
    const DynState *s = &d->state;
    double q[MODES_MAX], v[MODES_MAX];
    if (id >= OutModalQ1 && id < OutModeFrequency1) {
        dynModalState(&d->model, s, q, v);
        return id >= OutModalV1 ? v[id - OutModalV1] : q[id - OutModalQ1];
    }
    if (id >= OutModeFrequency1 && id < OutRootMoment)
        return ((const BxMemory *)inst->memory)->frequencies[id - OutModeFrequency1];
    if (id == OutRootMoment) return bladeRootMoment(&d->model, s, d->par[ParEI], d->curvature);
    switch (id) {
    case OutQ: return s->q;
    case OutV: return s->v;
    case OutEnergy: return s->E;
    case OutW: return s->W;
    default: return ((const BxMemory *)inst->memory)->out.naturalFrequency;
    }
}

/* The blades' step (model-notes s.1, s.6, s.7) with F = contactForce + contactForce2. */
static FmiStatus doStep(FmiInstance *inst, const char *fn, double tc, double h)
{
    BxData *d = DATA(inst);
    BladeStep b;
    b.model = &d->model;
    b.state = &d->state;
    b.sens = NULL;
    b.in = d->in;
    b.nForces = NUM_FORCES;
    b.maxStep = d->par[ParMaxStep];
    b.speedMax = max_rotorSpeed;
    b.instabilityHint = " or a smaller contactForce";
    b.counters = &((BxMemory *)inst->memory)->counters;
    return bladeStep(inst, fn, &b, tc, h);
}

static int validData(FmiInstance *inst, const char *fn, const void *data, int initialized)
{
    const DynState *s = &((const BxData *)data)->state;
    for (int k = 0; k < MODES_MAX - 1; ++k)
        if (initialized && !(isfinite(s->qx[k]) && isfinite(s->vx[k]))) {
            fmiLogStatus(inst, FmiError, "%s: invalid solver state in the data", fn);
            return 0;
        }
    if (initialized && !(isfinite(s->q) && isfinite(s->v) && isfinite(s->psi) && isfinite(s->E) &&
                         isfinite(s->W))) {
        fmiLogStatus(inst, FmiError, "%s: invalid solver state in the data", fn);
        return 0;
    }
    return 1;
}

const FmiModel fmiModel = {
    .name = MODEL_NAME,
    .guid = MODEL_GUID,
    .vars = VARS,
    .nVars = (int)(sizeof VARS / sizeof VARS[0]),
    .maxInputOrder = SOLVER_MAX_ORDER,
    .dataSize = sizeof(BxData),
    .memorySize = sizeof(BxMemory),
    .canGetAndSetState = 1,
    .stateVersion = STATE_VERSION,
    .fields = FIELDS,
    .nFields = (int)(sizeof FIELDS / sizeof FIELDS[0]),
    .build = build,
    .outputs = outputs,
    .output = output,
    .doStep = doStep,
    .validData = validData,
};

/* co-simulation only */
const FmiModelExchange *const fmiModelExchange = NULL;
