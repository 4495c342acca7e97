/* The ShroudedBlade model for the generic FMI layer: the variable table (modelDescription.xml),
 * the serialized field list, start values, the build step (Galerkin reduction, contact and
 * dynamics constants, initial state), the outputs and the communication step (the blades' step
 * driver, solver/blade_step.c). Co-simulation only: model exchange is model_me.c. */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "fmi/log.h"
#include "models/ShroudedBlade/blade_data.h"
#include "physics/dynamics_step.h"
#include "solver/blade_step.h"

/* ------------------------------------------------------------------------------------------- */
/* Variable table (model.toml: bounds open where the quantity must be strictly positive)         */

typedef enum {
    OutQ = 0, OutV, OutNormalForce, OutFrictionForce, OutKeq, OutCeq, OutAmplitude, OutEnergy,
    OutFrequency, OutJenkinsForce, OutRegime, OutContactState, OutRunningMaximum,
    OutPsi, OutW, OutDer0, /* OutDer0 + i: dx_i/dt */
    OutSens0 = OutDer0 + DYN_NX_MAX, /* OutSens0 + SENS_NP row + col: the sensitivities (vr_sens) */
    OutModalQ1 = OutSens0 + 20,  /* OutModalQ1 + i - 1: modalDisplacement[i] */
    OutModalV1 = OutModalQ1 + MODES_MAX,
    OutModeFrequency1 = OutModalV1 + MODES_MAX,
    OutRootMoment = OutModeFrequency1 + MODES_MAX,
    OutSensitivity11 /* + SENS_MODAL_COLS (r - 1) + (c - 1): sensitivity[r,c] */
} OutputId;

/* The rows of the sensitivity outputs (model.toml: sens_out) */
enum { SensRowQ = 0, SensRowV, SensRowJenkinsForce, SensRowRunningMaximum, SensRowAmplitude, SENS_ROWS };

#define PAR(k) (long)offsetof(BladeData, par[k])
#define IPAR(k) (long)offsetof(BladeData, ipar[k])
#define INPUT(k) (long)offsetof(BladeData, in[k][0])

/* Sorted by value reference (the layer bisects): generated from model.toml. */
static const VarInfo VARS[] = {
#include "models/ShroudedBlade/variables.inc"
};
/* the spec's bounds and array sizes agree with the C constants (a negative array size otherwise) */
typedef char SpecAgreesWithC[(max_modes == MODES_MAX && PAR_NUM == ParVm0 + MODES_MAX) ? 1 : -1];

/* ------------------------------------------------------------------------------------------- */
/* Serialized fields (the layer frames them; counts follow from this list)                      */

#define COUNT(member) (int)(sizeof(((BladeData *)0)->member) / sizeof(((BladeData *)0)->member[0]))
#define F64(member) {(long)offsetof(BladeData, member), FieldF64, 1}
#define I32(member) {(long)offsetof(BladeData, member), FieldI32, 1}

static const StateField FIELDS[] = {
    {(long)offsetof(BladeData, par), FieldF64, COUNT(par)},
    {(long)offsetof(BladeData, in), FieldF64, COUNT(in) * COUNT(in[0])},
    F64(state.q), F64(state.v), F64(state.psi), F64(state.E), F64(state.w), F64(state.B),
    F64(state.windowMax), F64(state.periods),
    {(long)offsetof(BladeData, state.qx), FieldF64, MODES_MAX - 1},
    {(long)offsetof(BladeData, state.vx), FieldF64, MODES_MAX - 1},
    {(long)offsetof(BladeData, ipar), FieldI32, COUNT(ipar)},
    I32(warnedFullStick), I32(state.mode), I32(state.side), I32(state.slipDir), I32(state.vdir),
    {(long)offsetof(BladeData, sens.S), FieldF64, SENS_NY_MAX * SENS_NP_MAX},
    {(long)offsetof(BladeData, sens.dB), FieldF64, SENS_NP_MAX},
    {(long)offsetof(BladeData, sens.peak), FieldF64, SENS_PEAKS},
    {(long)offsetof(BladeData, sens.gPeak), FieldF64, SENS_PEAKS * SENS_NP_MAX},
    F64(sens.dKeq), F64(sens.dCeqOmega), I32(sens.grazing),
};

/* Versions: 6 the modes (their parameter, start values and modal states); 5 the built-in load's parameters joined; 4 the sensitivities; 3 the state-machine
 * value left the blob and the layer's run fields moved ahead; 2 the start values of jenkinsForce
 * and runningMaximum joined the parameters. Older versions are refused. */
#define STATE_VERSION 6

/* ------------------------------------------------------------------------------------------- */
/* Start values, build                                                                          */

static void startValues(FmiInstance *inst)
{
    BladeData *d = BLADE_DATA(inst);
    /* by the zeroed data: no warning given yet; the state is built at initialization and kept
     * consistent until then */
    d->state.B = d->par[ParB];
    d->state.side = d->state.slipDir = d->state.vdir = 1;
}

/* The start value of jenkinsForce must fit the start state (model-notes s.7): 0 for the
 * describing-function models and for an open contact, inside the friction cone [-L, L] (relative
 * tolerance DYN_CONE_RTOL) otherwise. Cross-field, so checked here, not at the set. */
static FmiStatus checkStartForce(FmiInstance *inst, const char *fn, double q0)
{
    const BladeData *d = BLADE_DATA(inst);
    const double F0 = d->par[ParF0];
    double L;
    if (F0 == 0.0) return FmiOK;
    if (d->model.friction != FrictionMacroslipTD) {
        fmiLogStatus(inst, FmiError,
                     "%s: jenkinsForce = %.15g N: its start value applies only to frictionModel 3 (the "
                     "time-domain Jenkins element), here frictionModel = %d: accepted range [0, 0] N",
                     fn, F0, (int)d->ipar[IparFrictionModel]);
        return FmiError;
    }
    L = dynStartForceLimit(&d->model, q0);
    if (L < 0.0) {
        fmiLogStatus(inst, FmiError,
                     "%s: jenkinsForce = %.15g N, but the contact is open at the start value "
                     "tipDisplacement = %.15g m (|q0| <= d = %g m), where the spring is unloaded: "
                     "accepted range [0, 0] N", fn, F0, q0, d->model.contact.d);
        return FmiError;
    }
    if (!(fabs(F0) <= L * (1.0 + DYN_CONE_RTOL))) {
        fmiLogStatus(inst, FmiError,
                     "%s: jenkinsForce = %.15g N is outside the friction cone: accepted range "
                     "[-%.15g, %.15g] N, from tipDisplacement = %.15g m (L = mu kn cos(gamma) "
                     "(|q0| - d), mu = %g, kn = %g N/m, gamma = %g rad, d = %g m)", fn, F0, L, L, q0,
                     d->par[ParMu], d->par[ParKn], d->par[ParGamma], d->par[ParD]);
        return FmiError;
    }
    return FmiOK;
}

/* bladeReduce into d->blade, reusing the instance's last reduction when the blade parameters and
 * the formulation are bit-identical (a reduction costs ~90 us, a period of the blade ~30 us). */
static int bladeReduceCached(FmiInstance *inst, const BladeParams *bp)
{
    BladeData *d = BLADE_DATA(inst);
    return bladeReduceReusing(&BLADE_MEMORY(inst)->reductionCache, bp, (Formulation)d->ipar[IparFormulation],
                              &d->blade);
}

/* Blade reduction and dynamics constants from the parameters; if initState, also the initial
 * state (q0, v0, E0, F0, B, windowMax0). Logs and returns FmiError on failure. */
static FmiStatus build(FmiInstance *inst, const char *fn, int initState)
{
    BladeData *d = BLADE_DATA(inst);
    const double *p = d->par;
    BladeParams bp;
    ContactParams cp;
    DynStatus st;
    bp = bladeParamsOf(&p[ParEI]); /* ParEI..ParM0 in that order */
    /* bladeReduce succeeds only with finite results and M > 0; the blade must also be stiff */
    if (bladeReduceCached(inst, &bp) != 0 || !(d->blade.K0static > 0.0)) {
        fmiLogStatus(inst, FmiError,
                     "%s: the Galerkin reduction (eq. 19-26) failed for EI = %g N.m2, rho = %g kg/m3, "
                     "A = %g m2, l = %g m, c = %g N.s/m2, m0 = %g kg, formulation = %d "
                     "(M = %g kg, K0 = %g N/m): the blade parameters are not usable together",
                     fn, bp.EI, bp.rho, bp.A, bp.l, bp.c, bp.m0, (int)d->ipar[IparFormulation],
                     d->blade.M, d->blade.K0static);
        return FmiError;
    }
    cp.kn = p[ParKn];
    cp.kdRatio = p[ParKdRatio];
    cp.mu = p[ParMu];
    cp.gamma = p[ParGamma];
    cp.d = p[ParD];
    if (!contactParamsValid(&cp) ||
        dynBuildModel(&d->model, &d->blade, &cp, (FrictionModel)d->ipar[IparFrictionModel],
                      (Projection)d->ipar[IparProjection], d->ipar[IparGating] != 0,
                      d->ipar[IparAmplitudeMode] == 2, d->ipar[IparEngineOrder]) != 0) {
        fmiLogStatus(inst, FmiError,
                     "%s: the contact parameters kn = %g N/m, kdRatio = %g, mu = %g, gamma = %g rad, "
                     "d = %g m are not usable together", fn, cp.kn, cp.kdRatio, cp.mu, cp.gamma, cp.d);
        return FmiError;
    }
    if (d->ipar[IparBladeIndex] >= d->ipar[IparBladeCount]) {
        fmiLogStatus(inst, FmiError, "%s: bladeIndex = %d must be in [0, bladeCount - 1] = [0, %d]", fn,
                     (int)d->ipar[IparBladeIndex], (int)d->ipar[IparBladeCount] - 1);
        return FmiError;
    }
    dynSetLoad(&d->model, p[ParFw0], d->ipar[IparEngineOrder], d->ipar[IparBladeIndex], d->ipar[IparBladeCount]);
    {
        const BladeModesSetup setup = {d->ipar[IparModes], d->ipar[IparFormulation], p[ParMaxStep],
                                       d->in[SOLVER_INPUT_SPEED][0]};
        BLADE_MEMORY(inst)->frequencyValid = 0;
        if (bladeModesBuild(inst, fn, &setup, &bp, &d->blade, &BLADE_MEMORY(inst)->modesCache, &d->model,
                            d->curvature) != FmiOK)
            return FmiError;
    }
    if (initState) {
        double u0, du0;
        if (bladeModesStart(inst, fn, d->ipar[IparModes], p[ParQ0], p[ParV0], &p[ParQm0], &p[ParVm0], &u0, &du0) !=
                FmiOK ||
            checkStartForce(inst, fn, u0) != FmiOK)
            return FmiError;
        st = dynInitState(&d->model, &d->state, u0, du0, p[ParE0], p[ParF0], p[ParB], p[ParWindowMax0]);
        bladeModesInitState(&d->model, &d->state, &p[ParQm0], &p[ParVm0]);
        memset(&d->sens, 0, sizeof d->sens);
        if (st == DynOk && d->ipar[IparSensitivities]) st = sensInit(&d->model, &d->state, p[ParWindowMax0], &d->sens);
    } else {
        st = dynUpdateDescribe(&d->model, &d->state);
    }
    if (st != DynOk) {
        fmiLogStatus(inst, FmiError,
                     "%s: the describing function (eq. 7-13) failed for B = %g m (d = %g m, kn = %g N/m, "
                     "kdRatio = %g, mu = %g, gamma = %g rad)", fn, d->state.B, cp.d, cp.kn, cp.kdRatio,
                     cp.mu, cp.gamma);
        return FmiError;
    }
    return FmiOK;
}

/* ------------------------------------------------------------------------------------------- */
/* Outputs                                                                                      */

/* (model exchange holds contactState between events: model_me.c) */
static void outputs(FmiInstance *inst)
{
    BladeData *d = BLADE_DATA(inst);
    BladeMemory *mem = BLADE_MEMORY(inst);
    const double n = d->in[SOLVER_INPUT_SPEED][0];
    dynOutputs(&d->model, &d->state, n, &mem->out);
    if (!mem->frequencyValid || mem->frequencySpeed != n) { /* an eigenproblem per speed, not per get */
        dynModeFrequencies(&d->model, n, mem->frequencies);
        mem->frequencySpeed = n;
        mem->frequencyValid = 1;
    }
    if (d->model.modes > 1) mem->out.naturalFrequency = mem->frequencies[0];
    mem->jacobianValid = 0; /* computed at the first sensitivity[r,c] read of this get call */
}

/* dx_i/dt, the der(...) variables, evaluated only when asked for (at omega = 0 with a
 * describing-function contact, C_eq is taken as 0) */
static double derivative(const FmiInstance *inst, int i)
{
    const BladeData *d = BLADE_DATA(inst);
    const DynState *s = &d->state;
    double x[DYN_NX_MAX] = {s->q, s->v, s->psi, s->E, s->w}, f[DYN_NX_MAX] = {0.0}; /* m = 1: f[5..] stay 0 */
    for (int k = 0; k < MODES_MAX - 1; ++k) { /* the extra modal coordinates (dynamics.h) */
        x[DYN_NX + k] = s->qx[k];
        x[DYN_X_RATES + k] = s->vx[k];
    }
    (void)dynRhs(&d->model, s, d->in[SOLVER_INPUT_AERO][0], d->in[SOLVER_INPUT_SPEED][0], x, f);
    return f[i];
}

/* Sensitivity output OutSens0 + k (0 unless sensitivities = true) */
static double sensitivity(const FmiInstance *inst, int k)
{
    const BladeData *d = BLADE_DATA(inst);
    const int row = k / SENS_NP, col = k % SENS_NP;
    double g[SENS_NP_MAX];
    switch (row) {
    case SensRowQ: return d->sens.S[0][col];
    case SensRowV: return d->sens.S[1][col];
    case SensRowJenkinsForce: sensJenkinsForceGradient(&d->model, &d->state, &d->sens, g); return g[col];
    case SensRowRunningMaximum: sensPeakGradient(&d->sens, g); return d->ipar[IparSensitivities] ? g[col] : 0.0;
    default: return d->sens.dB[col];
    }
}

/* sensitivity[r,c], entry k row-major (0 unless sensitivities) */
static double modalJacobian(const FmiInstance *inst, int k)
{
    const BladeData *d = BLADE_DATA(inst);
    BladeMemory *mem = BLADE_MEMORY(inst);
    if (!mem->jacobianValid) {
        if (d->ipar[IparSensitivities]) sensModalJacobian(&d->model, &d->state, &d->sens, mem->jacobian);
        else memset(mem->jacobian, 0, sizeof mem->jacobian);
        mem->jacobianValid = 1;
    }
    return (&mem->jacobian[0][0])[k];
}

/* modalDisplacement[i], modalVelocity[i], modeFrequency[i] (0 above m) */
static double modeOutput(const FmiInstance *inst, int id)
{
    const BladeData *d = BLADE_DATA(inst);
    double q[MODES_MAX], v[MODES_MAX];
    if (id >= OutModeFrequency1) return BLADE_MEMORY(inst)->frequencies[id - OutModeFrequency1];
    dynModalState(&d->model, &d->state, q, v);
    return id >= OutModalV1 ? v[id - OutModalV1] : q[id - OutModalQ1];
}

static double output(const FmiInstance *inst, int id)
{
    const DynState *s = &BLADE_DATA(inst)->state;
    const DynOutputs *o = &BLADE_MEMORY(inst)->out;
    switch ((OutputId)id) {
    case OutQ: return s->q;
    case OutV: return s->v;
    case OutNormalForce: return o->normalForce;
    case OutFrictionForce: return o->frictionForce;
    case OutKeq: return o->Keq;
    case OutCeq: return o->Ceq;
    case OutAmplitude: return s->B;
    case OutEnergy: return s->E;
    case OutFrequency: return o->naturalFrequency;
    case OutJenkinsForce: return o->jenkinsForce;
    case OutRunningMaximum: return s->windowMax;
    case OutRegime: return (double)o->regime;
    case OutContactState: return (double)o->contactState;
    case OutPsi: return s->psi;
    case OutW: return s->w;
    default: break;
    }
    if (id >= OutSensitivity11 && id < OutSensitivity11 + SENS_MODAL_ROWS * SENS_MODAL_COLS)
        return modalJacobian(inst, id - OutSensitivity11);
    if (id >= OutModalQ1 && id < OutRootMoment) return modeOutput(inst, id);
    if (id == OutRootMoment)
        return bladeRootMoment(&BLADE_DATA(inst)->model, s, BLADE_DATA(inst)->par[ParEI], BLADE_DATA(inst)->curvature);
    if (id >= OutDer0 && id < OutDer0 + DYN_NX_MAX) return derivative(inst, id - OutDer0);
    if (id >= OutSens0 && id < OutSens0 + SENS_ROWS * SENS_NP) return sensitivity(inst, id - OutSens0);
    return 0.0;
}

static void nonFiniteHint(const FmiInstance *inst, char *buf, size_t n)
{
    snprintf(buf, n, " at rotorSpeed = %g rpm (a describing-function coefficient ~ 1/omega overflows)",
             BLADE_DATA(inst)->in[SOLVER_INPUT_SPEED][0]);
}

/* ------------------------------------------------------------------------------------------- */
/* The step                                                                                     */

FmiStatus bladeWarnFullStickOnce(FmiInstance *inst, const char *fn)
{
    BladeData *d = BLADE_DATA(inst);
    if (d->warnedFullStick || d->state.df.regime != RegimeFullStick) return FmiOK;
    d->warnedFullStick = 1;
    fmiLogStatus(inst, FmiWarning,
                 "%s: full-stick regime (docs/model.md s.3): kd tan(gamma) = %g N/m < mu kn = %g N/m, the "
                 "macroslip loop never slips; f_c = 0 and f_k = (kd tan(gamma)/kn) p_k are used "
                 "(B = %g m)", fn, d->model.kd * tan(d->par[ParGamma]), d->par[ParMu] * d->par[ParKn],
                 d->state.B);
    return FmiWarning;
}

/* model-notes s.1, s.6: the blades' step, then the full-stick warning */
static FmiStatus doStep(FmiInstance *inst, const char *fn, double tc, double h)
{
    BladeData *d = BLADE_DATA(inst);
    BladeStep b;
    FmiStatus status;
    b.model = &d->model;
    b.state = &d->state;
    b.sens = d->ipar[IparSensitivities] ? &d->sens : NULL;
    b.in = d->in;
    b.nForces = 0;
    b.maxStep = d->par[ParMaxStep];
    b.speedMax = max_rotorSpeed;
    b.instabilityHint = NULL;
    b.counters = &BLADE_MEMORY(inst)->counters;
    status = bladeStep(inst, fn, &b, tc, h);
    return status == FmiOK ? bladeWarnFullStickOnce(inst, fn) : status;
}

/* ------------------------------------------------------------------------------------------- */
/* Deserialized data                                                                            */

static int validData(FmiInstance *inst, const char *fn, const void *data, int initialized)
{
    const BladeData *d = (const BladeData *)data;
    const DynState *s = &d->state;
    const int td = d->ipar[IparFrictionModel] == FrictionMacroslipTD;
    if (d->warnedFullStick != 0 && d->warnedFullStick != 1) {
        fmiLogStatus(inst, FmiError, "%s: invalid time or status fields in the data", fn);
        return 0;
    }
    if (!initialized) return 1; /* the state is built at the end of initialization */
    for (int k = 0; k < MODES_MAX - 1; ++k)
        if (!isfinite(s->qx[k]) || !isfinite(s->vx[k])) {
            fmiLogStatus(inst, FmiError, "%s: invalid solver state in the data", fn);
            return 0;
        }
    if (!isfinite(s->q) || !isfinite(s->v) || !isfinite(s->psi) || !isfinite(s->E) || !isfinite(s->w) ||
        !(s->B >= 0.0) || !isfinite(s->B) || !(s->windowMax >= 0.0) || !isfinite(s->windowMax) ||
        !(s->periods >= 0.0) || s->periods > 9e15 || s->periods != floor(s->periods) ||
        s->mode < 0 || s->mode > (td ? ContactSlip : GateOn) || (s->side != 1 && s->side != -1) ||
        (s->slipDir != 1 && s->slipDir != -1) || (s->vdir != 1 && s->vdir != -1) || !sensFinite(&d->sens) ||
        d->sens.grazing < 0) {
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
    .dataSize = sizeof(BladeData),
    .memorySize = sizeof(BladeMemory),
    .canGetAndSetState = 1,
    .stateVersion = STATE_VERSION,
    .fields = FIELDS,
    .nFields = (int)(sizeof FIELDS / sizeof FIELDS[0]),
    .startValues = startValues,
    .build = build,
    .initialized = bladeWarnFullStickOnce,
    .outputs = outputs,
    .output = output,
    .nonFiniteHint = nonFiniteHint,
    .doStep = doStep,
    .validData = validData,
};
