/* The BladeExternalContact model for the generic FMI layer: the blade of ShroudedBlade (Galerkin
 * reduction, docs/model.md s.2) without a built-in contact; the contact force at the contact
 * coordinate is an input (docs/model.md s.8):
 *   M q'' + C0 q' + K0(Omega) q = G f_w(t) + F(t),   E' = C0 q'^2,   W' = F q'.
 * F (contactForce) is the force ON the blade, positive along q. The physics and the integrator are
 * ShroudedBlade's (physics/dynamics with FrictionNone, solver/rk4_events), so with F = 0 the
 * trajectory is bit-identical to ShroudedBlade with the contact open and no amplitude events
 * (amplitudeMode 1, d > max |q|), given the same communication points and inputs. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "fmi/log.h"
#include "fmi/model.h"
#include "physics/dynamics_step.h"
#include "solver/rk4_events.h"

/* Must equal the guid attribute of descriptions/BladeExternalContact.xml (checked by CMake). */
#define BLADE_EXTERNAL_GUID "{3f6b2a14-8c0e-4d57-b1a9-7e20c5d4f861}"
#define ROTOR_SPEED_MAX 30000.0 /* [rpm], as ShroudedBlade (model-notes s.1) */
#define MAX_INTERNAL_STEPS 1e7
#define NUM_INPUTS 4 /* aeroLoad, rotorSpeed, contactForce (= SOLVER_INPUT_AERO, _SPEED, _FORCE), contactForce2 */
#define INPUT_FORCE2 3

typedef enum {
    ParEI = 0, ParRho, ParA, ParL, ParC, ParM0, ParMaxStep,
    ParQ0, ParV0, ParE0, ParW0, /* start values of q [m], q' [m/s], E [J], W [J] */
    PAR_NUM
} RealParam;

typedef struct {
    double par[PAR_NUM];                                  /* [units of the XML] */
    int32_t formulation;                                  /* 1 printed, 2 consistent */
    double in[NUM_INPUTS][SOLVER_MAX_ORDER + 1];          /* input values and derivatives [unit/s^j] */
    DynState state;                                       /* q, q', E, W (psi, w unused) */
    /* derived (rebuilt, not serialized) */
    BladeReduction blade;
    DynModel model;
} BxData;

typedef struct {
    DynOutputs out;
    SolverCounters counters;
} BxMemory;

enum { OutQ = 0, OutV, OutE, OutW, OutFrequency };

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
    {21, "formulation", VarInteger, CausParameter, "", 1, 1, 2, 0, 0, AT(formulation), -1},
    {40, "aeroLoad", VarReal, CausInput, "N/m", 0.0, -INF, INF, 0, 0, INPUT(SOLVER_INPUT_AERO), -1},
    {41, "rotorSpeed", VarReal, CausInput, "rpm", 5000.0, 0.0, ROTOR_SPEED_MAX, 0, 0, INPUT(SOLVER_INPUT_SPEED), -1},
    {42, "contactForce", VarReal, CausInput, "N", 0.0, -INF, INF, 0, 0, INPUT(SOLVER_INPUT_FORCE), -1},
    {43, "contactForce2", VarReal, CausInput, "N", 0.0, -INF, INF, 0, 0, INPUT(INPUT_FORCE2), -1},
    {50, "tipDisplacement", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQ0), OutQ},
    {51, "tipVelocity", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParV0), OutV},
    {57, "dissipatedEnergy", VarReal, CausOutput, "J", 0.0, -INF, INF, 0, 0, PAR(ParE0), OutE},
    {58, "naturalFrequency", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutFrequency},
    {63, "contactWork", VarReal, CausOutput, "J", 0.0, -INF, INF, 0, 0, PAR(ParW0), OutW},
};

#define COUNT(member) (int)(sizeof(((BxData *)0)->member) / sizeof(((BxData *)0)->member[0]))
#define F64(member) {AT(member), FieldF64, 1}

static const StateField FIELDS[] = {
    {AT(par), FieldF64, COUNT(par)},
    {AT(in), FieldF64, COUNT(in) * COUNT(in[0])},
    F64(state.q), F64(state.v), F64(state.psi), F64(state.E), F64(state.W),
    {AT(formulation), FieldI32, 1},
};
#define STATE_VERSION 1

/* Reduction, dynamics constants (FrictionNone: no contact), and at the end of initialization the
 * start state. */
static FmiStatus build(FmiInstance *inst, const char *fn, int initState)
{
    BxData *d = DATA(inst);
    const double *p = d->par;
    BladeParams bp;
    bp = bladeParamsOf(&p[ParEI]); /* ParEI..ParM0 in that order */
    if (bladeReduce(&bp, (Formulation)d->formulation, &d->blade) != 0 || !(d->blade.K0static > 0.0) ||
        dynBuildModel(&d->model, &d->blade, NULL, FrictionNone, ProjectionPaper, 0, 0, 1) != 0) {
        fmiLogStatus(inst, FmiError,
                     "%s: the Galerkin reduction (eq. 19-26) failed for EI = %g N.m2, rho = %g kg/m3, "
                     "A = %g m2, l = %g m, c = %g N.s/m2, m0 = %g kg, formulation = %d: the blade "
                     "parameters are not usable together", fn, bp.EI, bp.rho, bp.A, bp.l, bp.c, bp.m0,
                     (int)d->formulation);
        return FmiError;
    }
    if (initState) {
        (void)dynInitState(&d->model, &d->state, p[ParQ0], p[ParV0], p[ParE0], 0.0, 0.0, 0.0);
        d->state.W = p[ParW0];
    }
    return FmiOK;
}

static void outputs(FmiInstance *inst)
{
    const BxData *d = DATA(inst);
    dynOutputs(&d->model, &d->state, d->in[SOLVER_INPUT_SPEED][0], &((BxMemory *)inst->memory)->out);
}

static double output(const FmiInstance *inst, int id)
{
    const DynState *s = &DATA(inst)->state;
    switch (id) {
    case OutQ: return s->q;
    case OutV: return s->v;
    case OutE: return s->E;
    case OutW: return s->W;
    default: return ((const BxMemory *)inst->memory)->out.naturalFrequency;
    }
}

/* As ShroudedBlade's step (model-notes s.1, s.6): equal internal steps of at most maxStep, the
 * rotor speed in range at both ends, the state restored on trouble, the inputs carried on. */
static FmiStatus doStep(FmiInstance *inst, const char *fn, double tc, double h)
{
    BxData *d = DATA(inst);
    const double ratio = h / d->par[ParMaxStep];
    SolverInputs in;
    DynState backup;
    DynStatus st;
    double n0, n1, tFail = 0.0;
    long nSteps;
    if (!(ratio - 1e-9 <= MAX_INTERNAL_STEPS)) {
        fmiLogStatus(inst, FmiError, "%s: communicationStepSize = %g s needs more than %.0f internal steps of "
                     "at most maxStep = %g s: use a shorter communication step or a larger maxStep", fn, h,
                     MAX_INTERNAL_STEPS, d->par[ParMaxStep]);
        return FmiError;
    }
    nSteps = (long)ceil(ratio - 1e-9);
    if (nSteps < 1) nSteps = 1;
    solverSetInputs(&in, (const double(*)[SOLVER_MAX_ORDER + 1])d->in);
    {   /* F = contactForce + contactForce2 (a master that cannot add signals connects one contact to
         * each); a derivative of contactForce2 that is 0 leaves contactForce's bits as they are */
        double F[SOLVER_MAX_ORDER + 1];
        for (int j = 0; j <= SOLVER_MAX_ORDER; ++j)
            F[j] = d->in[INPUT_FORCE2][j] != 0.0 ? d->in[SOLVER_INPUT_FORCE][j] + d->in[INPUT_FORCE2][j]
                                                  : d->in[SOLVER_INPUT_FORCE][j];
        solverSetForce(&in, F);
    }
    n0 = solverInputAt(&in, SOLVER_INPUT_SPEED, 0.0);
    n1 = solverInputAt(&in, SOLVER_INPUT_SPEED, h);
    if (!(n0 >= 0.0 && n0 <= ROTOR_SPEED_MAX && n1 >= 0.0 && n1 <= ROTOR_SPEED_MAX)) {
        fmiLogStatus(inst, FmiDiscard, "%s: rotorSpeed = %g rpm at t = %.17g s and %g rpm at the step end "
                     "t = %.17g s: it must stay in [0, %g] rpm; the step is refused, the state is unchanged",
                     fn, n0, tc, n1, tc + h, ROTOR_SPEED_MAX);
        return FmiDiscard;
    }
    backup = d->state;
    st = solverAdvance(&d->model, &d->state, &in, tc, h, nSteps, NULL, NULL,
                       &((BxMemory *)inst->memory)->counters, &tFail, NULL);
    if (st != DynOk) {
        d->state = backup;
        fmiLogStatus(inst, FmiDiscard, "%s: the state became non-finite near t = %.17g s (numerical "
                     "instability: try a smaller maxStep = %g s or a smaller contactForce); the step from "
                     "t = %.17g s is discarded and the state restored", fn, tc + tFail, d->par[ParMaxStep], tc);
        return FmiDiscard;
    }
    /* the inputs carried to the next point (model-notes s.7); each force on its own polynomial */
    solverShiftInput(&in, SOLVER_INPUT_AERO, h, d->in[SOLVER_INPUT_AERO]);
    solverShiftInput(&in, SOLVER_INPUT_SPEED, h, d->in[SOLVER_INPUT_SPEED]);
    for (int f = SOLVER_INPUT_FORCE; f <= INPUT_FORCE2; ++f) {
        SolverInputs one;
        memset(&one, 0, sizeof one);
        solverSetForce(&one, d->in[f]);
        solverShiftInput(&one, SOLVER_INPUT_FORCE, h, d->in[f]);
    }
    return FmiOK;
}

static int validData(FmiInstance *inst, const char *fn, const void *data, int initialized)
{
    const DynState *s = &((const BxData *)data)->state;
    if (initialized && !(isfinite(s->q) && isfinite(s->v) && isfinite(s->psi) && isfinite(s->E) &&
                         isfinite(s->W))) {
        fmiLogStatus(inst, FmiError, "%s: invalid solver state in the data", fn);
        return 0;
    }
    return 1;
}

const FmiModel fmiModel = {
    "BladeExternalContact", BLADE_EXTERNAL_GUID, VARS, (int)(sizeof VARS / sizeof VARS[0]), SOLVER_MAX_ORDER,
    sizeof(BxData), sizeof(BxMemory), 1, STATE_VERSION, FIELDS, (int)(sizeof FIELDS / sizeof FIELDS[0]),
    NULL, build, NULL, outputs, output, NULL, doStep, validData, NULL,
};
