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
#include "models/ShroudedBlade/config.h"
#include "physics/dynamics_step.h"
#include "solver/blade_step.h"

/* ------------------------------------------------------------------------------------------- */
/* Variable table (bounds as harness/params.py: open where the quantity must be strictly
 * positive)                                                                                    */

typedef enum {
    OutQ = 0, OutV, OutNormalForce, OutFrictionForce, OutKeq, OutCeq, OutAmplitude, OutEnergy,
    OutFrequency, OutJenkinsForce, OutRegime, OutContactState, OutRunningMaximum,
    OutPsi, OutW, OutDer0, /* OutDer0 + i: dx_i/dt */
    OutSens0 = OutDer0 + DYN_NX /* OutSens0 + SENS_NP row + col: the sensitivities (vr_sens0) */
} OutputId;

/* The rows of the sensitivity outputs (config.h) */
enum { SensRowQ = 0, SensRowV, SensRowJenkinsForce, SensRowRunningMaximum, SensRowAmplitude, SENS_ROWS };

#define INF HUGE_VAL
#define HALF_PI 1.5707963267948966
#define PAR(k) (long)offsetof(BladeData, par[k])
#define IPAR(k) (long)offsetof(BladeData, ipar[k])
#define INPUT(k) (long)offsetof(BladeData, in[k][0])
#define NONE VAR_NO_OFFSET

/* Sorted by value reference (the layer bisects). */
static const VarInfo VARS[] = {
    {vr_EI, "EI", VarReal, CausParameter, "N.m2", 343.0, 0.0, INF, 1, 0, PAR(ParEI), -1},
    {vr_rho, "rho", VarReal, CausParameter, "kg/m3", 7800.0, 0.0, INF, 1, 0, PAR(ParRho), -1},
    {vr_A, "A", VarReal, CausParameter, "m2", 4.2e-4, 0.0, INF, 1, 0, PAR(ParA), -1},
    {vr_l, "l", VarReal, CausParameter, "m", 0.15, 0.0, INF, 1, 0, PAR(ParL), -1},
    {vr_c, "c", VarReal, CausParameter, "N.s/m2", 29.8, 0.0, INF, 0, 0, PAR(ParC), -1},
    {vr_m0, "m0", VarReal, CausParameter, "kg", 0.025, 0.0, INF, 0, 0, PAR(ParM0), -1},
    {vr_kn, "kn", VarReal, CausParameter, "N/m", 1e7, 0.0, INF, 1, 0, PAR(ParKn), -1},
    {vr_kdRatio, "kdRatio", VarReal, CausParameter, "", 0.608695652173913, 0.0, INF, 1, 0, PAR(ParKdRatio), -1},
    {vr_mu, "mu", VarReal, CausParameter, "", 0.33, 0.0, INF, 0, 0, PAR(ParMu), -1},
    {vr_gamma, "gamma", VarReal, CausParameter, "rad", 1.0471975511965976, 0.0, HALF_PI, 1, 1, PAR(ParGamma), -1},
    {vr_d, "d", VarReal, CausParameter, "m", 3e-5, 0.0, INF, 0, 0, PAR(ParD), -1},
    {vr_B, "B", VarReal, CausParameter, "m", 6e-5, 0.0, INF, 1, 0, PAR(ParB), -1},
    {vr_maxStep, "maxStep", VarReal, CausParameter, "s", 1e-5, 1e-8, 1e-3, 0, 0, PAR(ParMaxStep), -1},
    {vr_Fw0, "Fw0", VarReal, CausParameter, "N/m", 100.0, 0.0, INF, 0, 0, PAR(ParFw0), -1},
    {vr_frictionModel, "frictionModel", VarInteger, CausParameter, "", 1, 1, 3, 0, 0, IPAR(IparFrictionModel), -1},
    {vr_formulation, "formulation", VarInteger, CausParameter, "", 1, 1, 2, 0, 0, IPAR(IparFormulation), -1},
    {vr_projection, "projection", VarInteger, CausParameter, "", 1, 1, 2, 0, 0, IPAR(IparProjection), -1},
    {vr_amplitudeMode, "amplitudeMode", VarInteger, CausParameter, "", 2, 1, 2, 0, 0, IPAR(IparAmplitudeMode), -1},
    {vr_engineOrder, "engineOrder", VarInteger, CausParameter, "", 3, 1, 100, 0, 0, IPAR(IparEngineOrder), -1},
    {vr_bladeIndex, "bladeIndex", VarInteger, CausParameter, "", 0, 0, 9999, 0, 0, IPAR(IparBladeIndex), -1},
    {vr_bladeCount, "bladeCount", VarInteger, CausParameter, "", 1, 1, 10000, 0, 0, IPAR(IparBladeCount), -1},
    {vr_gating, "gating", VarBoolean, CausParameter, "", 1, 0, 1, 0, 0, IPAR(IparGating), -1},
    {vr_sensitivities, "sensitivities", VarBoolean, CausParameter, "", 0, 0, 1, 0, 0, IPAR(IparSensitivities), -1},
    {vr_aeroLoad, "aeroLoad", VarReal, CausInput, "N/m", 0.0, -INF, INF, 0, 0, INPUT(SOLVER_INPUT_AERO), -1},
    {vr_rotorSpeed, "rotorSpeed", VarReal, CausInput, "rpm", 5000.0, 0.0, ROTOR_SPEED_MAX, 0, 0,
     INPUT(SOLVER_INPUT_SPEED), -1},
    {vr_tipDisplacement, "tipDisplacement", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQ0), OutQ},
    {vr_tipVelocity, "tipVelocity", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParV0), OutV},
    {vr_normalForce, "normalForce", VarReal, CausOutput, "N", 0.0, -INF, INF, 0, 0, NONE, OutNormalForce},
    {vr_frictionForce, "frictionForce", VarReal, CausOutput, "N", 0.0, -INF, INF, 0, 0, NONE, OutFrictionForce},
    {vr_Keq, "Keq", VarReal, CausOutput, "N/m", 0.0, -INF, INF, 0, 0, NONE, OutKeq},
    {vr_Ceq, "Ceq", VarReal, CausOutput, "N.s/m", 0.0, -INF, INF, 0, 0, NONE, OutCeq},
    {vr_amplitude, "amplitude", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, NONE, OutAmplitude},
    {vr_dissipatedEnergy, "dissipatedEnergy", VarReal, CausOutput, "J", 0.0, -INF, INF, 0, 0, PAR(ParE0), OutEnergy},
    {vr_naturalFrequency, "naturalFrequency", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutFrequency},
    /* its start value is checked against the friction cone at initialization (checkStartForce) */
    {vr_jenkinsForce, "jenkinsForce", VarReal, CausOutput, "N", 0.0, -INF, INF, 0, 0, PAR(ParF0), OutJenkinsForce},
    {vr_regime, "regime", VarInteger, CausOutput, "", 0, -INF, INF, 0, 0, NONE, OutRegime},
    {vr_contactState, "contactState", VarInteger, CausOutput, "", 0, -INF, INF, 0, 0, NONE, OutContactState},
    {vr_runningMaximum, "runningMaximum", VarReal, CausOutput, "m", 0.0, 0.0, INF, 0, 0, PAR(ParWindowMax0),
     OutRunningMaximum},
    /* model exchange (also readable in co-simulation): the states psi and w, the derivatives */
    {vr_excitationPhase, "excitationPhase", VarReal, CausLocal, "rad", 0.0, -INF, INF, 0, 0, NONE, OutPsi},
    {vr_sliderPosition, "sliderPosition", VarReal, CausLocal, "m", 0.0, -INF, INF, 0, 0, NONE, OutW},
    {vr_der_tipDisplacement, "der(tipDisplacement)", VarReal, CausLocal, "m/s", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + 0},
    {vr_der_tipVelocity, "der(tipVelocity)", VarReal, CausLocal, "m/s2", 0.0, -INF, INF, 0, 0, NONE, OutDer0 + 1},
    {vr_der_excitationPhase, "der(excitationPhase)", VarReal, CausLocal, "rad/s", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + 2},
    {vr_der_dissipatedEnergy, "der(dissipatedEnergy)", VarReal, CausLocal, "W", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + 3},
    {vr_der_sliderPosition, "der(sliderPosition)", VarReal, CausLocal, "m/s", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + 4},
    /* sensitivities (docs/model-notes.md s.8) */
    {vr_sens0 + 0, "dTipDisplacement_dQ0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 0},
    {vr_sens0 + 1, "dTipDisplacement_dV0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 1},
    {vr_sens0 + 2, "dTipDisplacement_dF0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 2},
    {vr_sens0 + 3, "dTipDisplacement_dB", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 3},
    {vr_sens0 + 4, "dTipVelocity_dQ0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 4},
    {vr_sens0 + 5, "dTipVelocity_dV0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 5},
    {vr_sens0 + 6, "dTipVelocity_dF0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 6},
    {vr_sens0 + 7, "dTipVelocity_dB", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 7},
    {vr_sens0 + 8, "dJenkinsForce_dQ0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 8},
    {vr_sens0 + 9, "dJenkinsForce_dV0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 9},
    {vr_sens0 + 10, "dJenkinsForce_dF0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 10},
    {vr_sens0 + 11, "dJenkinsForce_dB", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 11},
    {vr_sens0 + 12, "dRunningMaximum_dQ0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 12},
    {vr_sens0 + 13, "dRunningMaximum_dV0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 13},
    {vr_sens0 + 14, "dRunningMaximum_dF0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 14},
    {vr_sens0 + 15, "dRunningMaximum_dB", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 15},
    {vr_sens0 + 16, "dAmplitude_dQ0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 16},
    {vr_sens0 + 17, "dAmplitude_dV0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 17},
    {vr_sens0 + 18, "dAmplitude_dF0", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 18},
    {vr_sens0 + 19, "dAmplitude_dB", VarReal, CausOutput, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 19},
};

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
    {(long)offsetof(BladeData, ipar), FieldI32, COUNT(ipar)},
    I32(warnedFullStick), I32(state.mode), I32(state.side), I32(state.slipDir), I32(state.vdir),
    {(long)offsetof(BladeData, sens.S), FieldF64, SENS_NY * SENS_NP},
    {(long)offsetof(BladeData, sens.dB), FieldF64, SENS_NP},
    {(long)offsetof(BladeData, sens.peak), FieldF64, SENS_PEAKS},
    {(long)offsetof(BladeData, sens.gPeak), FieldF64, SENS_PEAKS * SENS_NP},
    F64(sens.dKeq), F64(sens.dCeqOmega), I32(sens.grazing),
};

/* Versions: 5 the built-in load's parameters joined; 4 the sensitivities; 3 the state-machine
 * value left the blob and the layer's run fields moved ahead; 2 the start values of jenkinsForce
 * and runningMaximum joined the parameters. Older versions are refused. */
#define STATE_VERSION 5

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
static FmiStatus checkStartForce(FmiInstance *inst, const char *fn)
{
    const BladeData *d = BLADE_DATA(inst);
    const double F0 = d->par[ParF0], q0 = d->par[ParQ0];
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
    BladeMemory *mem = BLADE_MEMORY(inst);
    const int32_t formulation = d->ipar[IparFormulation];
    int rc;
    if (mem->bladeCacheValid && mem->bladeCacheFormulation == formulation &&
        memcmp(&mem->bladeCacheParams, bp, sizeof *bp) == 0) {
        d->blade = mem->bladeCache;
        return 0;
    }
    mem->bladeCacheValid = 0;
    rc = bladeReduce(bp, (Formulation)formulation, &d->blade);
    if (rc == 0) {
        mem->bladeCacheParams = *bp;
        mem->bladeCacheFormulation = formulation;
        mem->bladeCache = d->blade;
        mem->bladeCacheValid = 1;
    }
    return rc;
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
    if (initState) {
        if (checkStartForce(inst, fn) != FmiOK) return FmiError;
        st = dynInitState(&d->model, &d->state, p[ParQ0], p[ParV0], p[ParE0], p[ParF0], p[ParB],
                          p[ParWindowMax0]);
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
    dynOutputs(&d->model, &d->state, d->in[SOLVER_INPUT_SPEED][0], &BLADE_MEMORY(inst)->out);
}

/* dx_i/dt, the der(...) variables, evaluated only when asked for (at omega = 0 with a
 * describing-function contact, C_eq is taken as 0) */
static double derivative(const FmiInstance *inst, int i)
{
    const BladeData *d = BLADE_DATA(inst);
    const DynState *s = &d->state;
    const double x[DYN_NX] = {s->q, s->v, s->psi, s->E, s->w};
    double f[DYN_NX];
    (void)dynRhs(&d->model, s, d->in[SOLVER_INPUT_AERO][0], d->in[SOLVER_INPUT_SPEED][0], x, f);
    return f[i];
}

/* Sensitivity output OutSens0 + k (0 unless sensitivities = true) */
static double sensitivity(const FmiInstance *inst, int k)
{
    const BladeData *d = BLADE_DATA(inst);
    const int row = k / SENS_NP, col = k % SENS_NP;
    double g[SENS_NP];
    switch (row) {
    case SensRowQ: return d->sens.S[0][col];
    case SensRowV: return d->sens.S[1][col];
    case SensRowJenkinsForce: sensJenkinsForceGradient(&d->model, &d->state, &d->sens, g); return g[col];
    case SensRowRunningMaximum: sensPeakGradient(&d->sens, g); return d->ipar[IparSensitivities] ? g[col] : 0.0;
    default: return d->sens.dB[col];
    }
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
    if (id >= OutDer0 && id < OutDer0 + DYN_NX) return derivative(inst, id - OutDer0);
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
    b.speedMax = ROTOR_SPEED_MAX;
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
    MODEL_NAME, MODEL_GUID, VARS, (int)(sizeof VARS / sizeof VARS[0]), SOLVER_MAX_ORDER,
    sizeof(BladeData), sizeof(BladeMemory), 1, STATE_VERSION, FIELDS, (int)(sizeof FIELDS / sizeof FIELDS[0]),
    startValues, build, bladeWarnFullStickOnce, outputs, output, nonFiniteHint, doStep, validData,
};
