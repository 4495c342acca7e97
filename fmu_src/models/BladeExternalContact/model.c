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
#include "models/BladeExternalContact/config.h"
#include "physics/dynamics_step.h"
#include "solver/blade_modes.h"
#include "solver/blade_step.h"

#define NUM_FORCES 2 /* contactForce, contactForce2: summed (a master that cannot add signals
                        connects one contact to each) */
#define NUM_INPUTS (SOLVER_INPUT_FORCE + NUM_FORCES) /* aeroLoad, rotorSpeed, the forces */
#define INPUT_FORCE2 (SOLVER_INPUT_FORCE + 1)

typedef enum {
    ParEI = 0, ParRho, ParA, ParL, ParC, ParM0, ParMaxStep,
    ParQ0, ParV0, ParE0, ParW0, /* start values of q [m], q' [m/s], E [J], W [J] */
    ParFw0,                     /* amplitude of the built-in aerodynamic load [N/m] */
    ParQm0,                     /* start values of modalDisplacement[1..6] [m] */
    ParVm0 = ParQm0 + MODES_MAX, /* start values of modalVelocity[1..6] [m/s] */
    PAR_NUM = ParVm0 + MODES_MAX
} RealParam;

typedef struct {
    double par[PAR_NUM];                                  /* [units of the XML] */
    int32_t formulation;                                  /* 1 printed, 2 consistent */
    int32_t engineOrder, bladeIndex, bladeCount;          /* the built-in load's travelling wave */
    int32_t modes;                                        /* m bending modes (docs/model.md s.2a) */
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
} BxMemory;

enum { OutQ = 0, OutV, OutE, OutW, OutFrequency, OutModalQ1, OutModalV1 = OutModalQ1 + MODES_MAX,
       OutModeFrequency1 = OutModalV1 + MODES_MAX, OutRootMoment = OutModeFrequency1 + MODES_MAX };

#define INF HUGE_VAL
#define AT(member) (long)offsetof(BxData, member)
#define PAR(k) AT(par[k])
#define INPUT(k) AT(in[k][0])
#define NONE VAR_NO_OFFSET
#define DATA(inst) ((BxData *)(inst)->data)

/* Sorted by value reference; the blade's value references where the blade has the variable. */
static const VarInfo VARS[] = {
    {1, "EI", VarReal, CausParameter, "N.m2", 343.0, 0.0, INF, 1, 0, PAR(ParEI), -1},
    {2, "rho", VarReal, CausParameter, "kg/m3", 7800.0, 0.0, INF, 1, 0, PAR(ParRho), -1},
    {3, "A", VarReal, CausParameter, "m2", 4.2e-4, 0.0, INF, 1, 0, PAR(ParA), -1},
    {4, "l", VarReal, CausParameter, "m", 0.15, 0.0, INF, 1, 0, PAR(ParL), -1},
    {5, "c", VarReal, CausParameter, "N.s/m2", 29.8, 0.0, INF, 0, 0, PAR(ParC), -1},
    {6, "m0", VarReal, CausParameter, "kg", 0.025, 0.0, INF, 0, 0, PAR(ParM0), -1},
    {13, "maxStep", VarReal, CausParameter, "s", 1e-5, 1e-8, 1e-3, 0, 0, PAR(ParMaxStep), -1},
    {14, "Fw0", VarReal, CausParameter, "N/m", 100.0, 0.0, INF, 0, 0, PAR(ParFw0), -1},
    {21, "formulation", VarInteger, CausParameter, "", 1, 1, 2, 0, 0, AT(formulation), -1},
    {24, "engineOrder", VarInteger, CausParameter, "", 3, 1, 100, 0, 0, AT(engineOrder), -1},
    {25, "bladeIndex", VarInteger, CausParameter, "", 0, 0, 9999, 0, 0, AT(bladeIndex), -1},
    {26, "bladeCount", VarInteger, CausParameter, "", 1, 1, 10000, 0, 0, AT(bladeCount), -1},
    {28, "modes", VarInteger, CausParameter, "", 1, 1, MODES_MAX, 0, 0, AT(modes), -1},
    {40, "aeroLoad", VarReal, CausInput, "N/m", 0.0, -INF, INF, 0, 0, INPUT(SOLVER_INPUT_AERO), -1},
    {41, "rotorSpeed", VarReal, CausInput, "rpm", 5000.0, 0.0, ROTOR_SPEED_MAX, 0, 0, INPUT(SOLVER_INPUT_SPEED), -1},
    {42, "contactForce", VarReal, CausInput, "N", 0.0, -INF, INF, 0, 0, INPUT(SOLVER_INPUT_FORCE), -1},
    {43, "contactForce2", VarReal, CausInput, "N", 0.0, -INF, INF, 0, 0, INPUT(INPUT_FORCE2), -1},
    {50, "tipDisplacement", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQ0), OutQ},
    {51, "tipVelocity", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParV0), OutV},
    {57, "dissipatedEnergy", VarReal, CausOutput, "J", 0.0, -INF, INF, 0, 0, PAR(ParE0), OutE},
    {58, "naturalFrequency", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutFrequency},
    {63, "contactWork", VarReal, CausOutput, "J", 0.0, -INF, INF, 0, 0, PAR(ParW0), OutW},
    /* m modes (docs/model.md s.2a); entries above m read 0 */
    {200, "modalDisplacement[1]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 0), OutModalQ1 + 0},
    {201, "modalDisplacement[2]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 1), OutModalQ1 + 1},
    {202, "modalDisplacement[3]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 2), OutModalQ1 + 2},
    {203, "modalDisplacement[4]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 3), OutModalQ1 + 3},
    {204, "modalDisplacement[5]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 4), OutModalQ1 + 4},
    {205, "modalDisplacement[6]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 5), OutModalQ1 + 5},
    {210, "modalVelocity[1]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 0), OutModalV1 + 0},
    {211, "modalVelocity[2]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 1), OutModalV1 + 1},
    {212, "modalVelocity[3]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 2), OutModalV1 + 2},
    {213, "modalVelocity[4]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 3), OutModalV1 + 3},
    {214, "modalVelocity[5]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 4), OutModalV1 + 4},
    {215, "modalVelocity[6]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 5), OutModalV1 + 5},
    {220, "modeFrequency[1]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 0},
    {221, "modeFrequency[2]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 1},
    {222, "modeFrequency[3]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 2},
    {223, "modeFrequency[4]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 3},
    {224, "modeFrequency[5]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 4},
    {225, "modeFrequency[6]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 5},
    {230, "rootMoment", VarReal, CausOutput, "N.m", 0.0, -INF, INF, 0, 0, NONE, OutRootMoment},
};

#define COUNT(member) (int)(sizeof(((BxData *)0)->member) / sizeof(((BxData *)0)->member[0]))
#define F64(member) {AT(member), FieldF64, 1}

static const StateField FIELDS[] = {
    {AT(par), FieldF64, COUNT(par)},
    {AT(in), FieldF64, COUNT(in) * COUNT(in[0])},
    F64(state.q), F64(state.v), F64(state.psi), F64(state.E), F64(state.W),
    {AT(formulation), FieldI32, 1}, {AT(engineOrder), FieldI32, 1}, {AT(bladeIndex), FieldI32, 1},
    {AT(bladeCount), FieldI32, 1},
    {AT(state.qx), FieldF64, MODES_MAX - 1}, {AT(state.vx), FieldF64, MODES_MAX - 1}, {AT(modes), FieldI32, 1},
};
#define STATE_VERSION 3 /* 3: the modes; 2: the built-in load's parameters joined */

/* Reduction, dynamics constants (FrictionNone: no contact), and at the end of initialization the
 * start state. */
static FmiStatus build(FmiInstance *inst, const char *fn, int initState)
{
    BxData *d = DATA(inst);
    const double *p = d->par;
    BladeParams bp;
    bp = bladeParamsOf(&p[ParEI]); /* ParEI..ParM0 in that order */
    if (bladeReduce(&bp, (Formulation)d->formulation, &d->blade) != 0 || !(d->blade.K0static > 0.0) ||
        dynBuildModel(&d->model, &d->blade, NULL, FrictionNone, ProjectionPaper, 0, 0, d->engineOrder) != 0) {
        fmiLogStatus(inst, FmiError,
                     "%s: the Galerkin reduction (eq. 19-26) failed for EI = %g N.m2, rho = %g kg/m3, "
                     "A = %g m2, l = %g m, c = %g N.s/m2, m0 = %g kg, formulation = %d: the blade "
                     "parameters are not usable together", fn, bp.EI, bp.rho, bp.A, bp.l, bp.c, bp.m0,
                     (int)d->formulation);
        return FmiError;
    }
    if (d->bladeIndex >= d->bladeCount) {
        fmiLogStatus(inst, FmiError, "%s: bladeIndex = %d must be in [0, bladeCount - 1] = [0, %d]", fn,
                     (int)d->bladeIndex, (int)d->bladeCount - 1);
        return FmiError;
    }
    dynSetLoad(&d->model, p[ParFw0], d->engineOrder, d->bladeIndex, d->bladeCount);
    {
        const BladeModesSetup setup = {d->modes, d->formulation, p[ParMaxStep], d->in[SOLVER_INPUT_SPEED][0]};
        if (bladeModesBuild(inst, fn, &setup, &bp, &d->blade, &((BxMemory *)inst->memory)->modesCache, &d->model,
                            d->curvature) != FmiOK)
            return FmiError;
    }
    if (initState) {
        double u0, du0;
        if (bladeModesStart(inst, fn, d->modes, p[ParQ0], p[ParV0], &p[ParQm0], &p[ParVm0], &u0, &du0) != FmiOK)
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
    case OutE: return s->E;
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
    b.speedMax = ROTOR_SPEED_MAX;
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
    MODEL_NAME, MODEL_GUID, VARS, (int)(sizeof VARS / sizeof VARS[0]), SOLVER_MAX_ORDER,
    sizeof(BxData), sizeof(BxMemory), 1, STATE_VERSION, FIELDS, (int)(sizeof FIELDS / sizeof FIELDS[0]),
    NULL, build, NULL, outputs, output, NULL, doStep, validData, NULL,
};

/* co-simulation only */
const FmiModelExchange *const fmiModelExchange = NULL;
