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
    OutSens0 = OutDer0 + DYN_NX_MAX, /* OutSens0 + SENS_NP row + col: the sensitivities (vr_sens0) */
    OutModalQ1 = OutSens0 + 20,  /* OutModalQ1 + i - 1: modalDisplacement[i] */
    OutModalV1 = OutModalQ1 + MODES_MAX,
    OutModeFrequency1 = OutModalV1 + MODES_MAX,
    OutRootMoment = OutModeFrequency1 + MODES_MAX,
    OutSensitivity11 /* + SENS_MODAL_COLS (r - 1) + (c - 1): sensitivity[r,c] */
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
    {vr_modes, "modes", VarInteger, CausParameter, "", 1, 1, MODES_MAX, 0, 0, IPAR(IparModes), -1},
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
    {vr_sens0 + 0, "dTipDisplacement_dQ0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 0},
    {vr_sens0 + 1, "dTipDisplacement_dV0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 1},
    {vr_sens0 + 2, "dTipDisplacement_dF0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 2},
    {vr_sens0 + 3, "dTipDisplacement_dB", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 3},
    {vr_sens0 + 4, "dTipVelocity_dQ0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 4},
    {vr_sens0 + 5, "dTipVelocity_dV0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 5},
    {vr_sens0 + 6, "dTipVelocity_dF0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 6},
    {vr_sens0 + 7, "dTipVelocity_dB", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 7},
    {vr_sens0 + 8, "dJenkinsForce_dQ0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 8},
    {vr_sens0 + 9, "dJenkinsForce_dV0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 9},
    {vr_sens0 + 10, "dJenkinsForce_dF0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 10},
    {vr_sens0 + 11, "dJenkinsForce_dB", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 11},
    {vr_sens0 + 12, "dRunningMaximum_dQ0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 12},
    {vr_sens0 + 13, "dRunningMaximum_dV0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 13},
    {vr_sens0 + 14, "dRunningMaximum_dF0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 14},
    {vr_sens0 + 15, "dRunningMaximum_dB", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 15},
    {vr_sens0 + 16, "dAmplitude_dQ0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 16},
    {vr_sens0 + 17, "dAmplitude_dV0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 17},
    {vr_sens0 + 18, "dAmplitude_dF0", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 18},
    {vr_sens0 + 19, "dAmplitude_dB", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSens0 + 19},
    /* m modes (docs/model.md s.2a); entries above m read 0 */
    {vr_modalDisplacement1 + 0, "modalDisplacement[1]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 0),
     OutModalQ1 + 0},
    {vr_modalDisplacement1 + 1, "modalDisplacement[2]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 1),
     OutModalQ1 + 1},
    {vr_modalDisplacement1 + 2, "modalDisplacement[3]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 2),
     OutModalQ1 + 2},
    {vr_modalDisplacement1 + 3, "modalDisplacement[4]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 3),
     OutModalQ1 + 3},
    {vr_modalDisplacement1 + 4, "modalDisplacement[5]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 4),
     OutModalQ1 + 4},
    {vr_modalDisplacement1 + 5, "modalDisplacement[6]", VarReal, CausOutput, "m", 0.0, -INF, INF, 0, 0, PAR(ParQm0 + 5),
     OutModalQ1 + 5},
    {vr_modalVelocity1 + 0, "modalVelocity[1]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 0),
     OutModalV1 + 0},
    {vr_modalVelocity1 + 1, "modalVelocity[2]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 1),
     OutModalV1 + 1},
    {vr_modalVelocity1 + 2, "modalVelocity[3]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 2),
     OutModalV1 + 2},
    {vr_modalVelocity1 + 3, "modalVelocity[4]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 3),
     OutModalV1 + 3},
    {vr_modalVelocity1 + 4, "modalVelocity[5]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 4),
     OutModalV1 + 4},
    {vr_modalVelocity1 + 5, "modalVelocity[6]", VarReal, CausOutput, "m/s", 0.0, -INF, INF, 0, 0, PAR(ParVm0 + 5),
     OutModalV1 + 5},
    {vr_modeFrequency1 + 0, "modeFrequency[1]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 0},
    {vr_modeFrequency1 + 1, "modeFrequency[2]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 1},
    {vr_modeFrequency1 + 2, "modeFrequency[3]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 2},
    {vr_modeFrequency1 + 3, "modeFrequency[4]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 3},
    {vr_modeFrequency1 + 4, "modeFrequency[5]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 4},
    {vr_modeFrequency1 + 5, "modeFrequency[6]", VarReal, CausOutput, "Hz", 0.0, -INF, INF, 0, 0, NONE, OutModeFrequency1 + 5},
    {vr_rootMoment, "rootMoment", VarReal, CausOutput, "N.m", 0.0, -INF, INF, 0, 0, NONE, OutRootMoment},
    /* model exchange: the derivatives of the modal states q_2..q_6, q_2'..q_6' (vr 240.., 250..) */
    {vr_modalDisplacement1 + 38 + 2, "der(modalDisplacement[2])", VarReal, CausLocal, "m/s", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_NX + 0},
    {vr_modalDisplacement1 + 38 + 3, "der(modalDisplacement[3])", VarReal, CausLocal, "m/s", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_NX + 1},
    {vr_modalDisplacement1 + 38 + 4, "der(modalDisplacement[4])", VarReal, CausLocal, "m/s", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_NX + 2},
    {vr_modalDisplacement1 + 38 + 5, "der(modalDisplacement[5])", VarReal, CausLocal, "m/s", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_NX + 3},
    {vr_modalDisplacement1 + 38 + 6, "der(modalDisplacement[6])", VarReal, CausLocal, "m/s", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_NX + 4},
    {vr_modalVelocity1 + 38 + 2, "der(modalVelocity[2])", VarReal, CausLocal, "m/s2", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_X_RATES + 0},
    {vr_modalVelocity1 + 38 + 3, "der(modalVelocity[3])", VarReal, CausLocal, "m/s2", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_X_RATES + 1},
    {vr_modalVelocity1 + 38 + 4, "der(modalVelocity[4])", VarReal, CausLocal, "m/s2", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_X_RATES + 2},
    {vr_modalVelocity1 + 38 + 5, "der(modalVelocity[5])", VarReal, CausLocal, "m/s2", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_X_RATES + 3},
    {vr_modalVelocity1 + 38 + 6, "der(modalVelocity[6])", VarReal, CausLocal, "m/s2", 0.0, -INF, INF, 0, 0, NONE,
     OutDer0 + DYN_X_RATES + 4},
    /* the modal Jacobian (docs/model.md s.2a; 0 unless sensitivities) */
    {vr_sensitivity11 + 0, "sensitivity[1,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 0},
    {vr_sensitivity11 + 1, "sensitivity[1,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 1},
    {vr_sensitivity11 + 2, "sensitivity[1,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 2},
    {vr_sensitivity11 + 3, "sensitivity[1,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 3},
    {vr_sensitivity11 + 4, "sensitivity[1,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 4},
    {vr_sensitivity11 + 5, "sensitivity[1,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 5},
    {vr_sensitivity11 + 6, "sensitivity[1,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 6},
    {vr_sensitivity11 + 7, "sensitivity[1,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 7},
    {vr_sensitivity11 + 8, "sensitivity[1,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 8},
    {vr_sensitivity11 + 9, "sensitivity[1,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 9},
    {vr_sensitivity11 + 10, "sensitivity[1,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 10},
    {vr_sensitivity11 + 11, "sensitivity[1,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 11},
    {vr_sensitivity11 + 12, "sensitivity[1,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 12},
    {vr_sensitivity11 + 13, "sensitivity[1,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 13},
    {vr_sensitivity11 + 14, "sensitivity[2,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 14},
    {vr_sensitivity11 + 15, "sensitivity[2,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 15},
    {vr_sensitivity11 + 16, "sensitivity[2,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 16},
    {vr_sensitivity11 + 17, "sensitivity[2,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 17},
    {vr_sensitivity11 + 18, "sensitivity[2,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 18},
    {vr_sensitivity11 + 19, "sensitivity[2,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 19},
    {vr_sensitivity11 + 20, "sensitivity[2,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 20},
    {vr_sensitivity11 + 21, "sensitivity[2,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 21},
    {vr_sensitivity11 + 22, "sensitivity[2,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 22},
    {vr_sensitivity11 + 23, "sensitivity[2,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 23},
    {vr_sensitivity11 + 24, "sensitivity[2,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 24},
    {vr_sensitivity11 + 25, "sensitivity[2,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 25},
    {vr_sensitivity11 + 26, "sensitivity[2,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 26},
    {vr_sensitivity11 + 27, "sensitivity[2,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 27},
    {vr_sensitivity11 + 28, "sensitivity[3,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 28},
    {vr_sensitivity11 + 29, "sensitivity[3,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 29},
    {vr_sensitivity11 + 30, "sensitivity[3,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 30},
    {vr_sensitivity11 + 31, "sensitivity[3,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 31},
    {vr_sensitivity11 + 32, "sensitivity[3,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 32},
    {vr_sensitivity11 + 33, "sensitivity[3,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 33},
    {vr_sensitivity11 + 34, "sensitivity[3,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 34},
    {vr_sensitivity11 + 35, "sensitivity[3,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 35},
    {vr_sensitivity11 + 36, "sensitivity[3,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 36},
    {vr_sensitivity11 + 37, "sensitivity[3,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 37},
    {vr_sensitivity11 + 38, "sensitivity[3,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 38},
    {vr_sensitivity11 + 39, "sensitivity[3,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 39},
    {vr_sensitivity11 + 40, "sensitivity[3,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 40},
    {vr_sensitivity11 + 41, "sensitivity[3,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 41},
    {vr_sensitivity11 + 42, "sensitivity[4,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 42},
    {vr_sensitivity11 + 43, "sensitivity[4,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 43},
    {vr_sensitivity11 + 44, "sensitivity[4,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 44},
    {vr_sensitivity11 + 45, "sensitivity[4,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 45},
    {vr_sensitivity11 + 46, "sensitivity[4,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 46},
    {vr_sensitivity11 + 47, "sensitivity[4,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 47},
    {vr_sensitivity11 + 48, "sensitivity[4,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 48},
    {vr_sensitivity11 + 49, "sensitivity[4,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 49},
    {vr_sensitivity11 + 50, "sensitivity[4,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 50},
    {vr_sensitivity11 + 51, "sensitivity[4,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 51},
    {vr_sensitivity11 + 52, "sensitivity[4,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 52},
    {vr_sensitivity11 + 53, "sensitivity[4,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 53},
    {vr_sensitivity11 + 54, "sensitivity[4,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 54},
    {vr_sensitivity11 + 55, "sensitivity[4,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 55},
    {vr_sensitivity11 + 56, "sensitivity[5,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 56},
    {vr_sensitivity11 + 57, "sensitivity[5,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 57},
    {vr_sensitivity11 + 58, "sensitivity[5,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 58},
    {vr_sensitivity11 + 59, "sensitivity[5,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 59},
    {vr_sensitivity11 + 60, "sensitivity[5,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 60},
    {vr_sensitivity11 + 61, "sensitivity[5,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 61},
    {vr_sensitivity11 + 62, "sensitivity[5,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 62},
    {vr_sensitivity11 + 63, "sensitivity[5,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 63},
    {vr_sensitivity11 + 64, "sensitivity[5,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 64},
    {vr_sensitivity11 + 65, "sensitivity[5,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 65},
    {vr_sensitivity11 + 66, "sensitivity[5,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 66},
    {vr_sensitivity11 + 67, "sensitivity[5,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 67},
    {vr_sensitivity11 + 68, "sensitivity[5,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 68},
    {vr_sensitivity11 + 69, "sensitivity[5,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 69},
    {vr_sensitivity11 + 70, "sensitivity[6,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 70},
    {vr_sensitivity11 + 71, "sensitivity[6,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 71},
    {vr_sensitivity11 + 72, "sensitivity[6,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 72},
    {vr_sensitivity11 + 73, "sensitivity[6,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 73},
    {vr_sensitivity11 + 74, "sensitivity[6,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 74},
    {vr_sensitivity11 + 75, "sensitivity[6,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 75},
    {vr_sensitivity11 + 76, "sensitivity[6,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 76},
    {vr_sensitivity11 + 77, "sensitivity[6,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 77},
    {vr_sensitivity11 + 78, "sensitivity[6,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 78},
    {vr_sensitivity11 + 79, "sensitivity[6,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 79},
    {vr_sensitivity11 + 80, "sensitivity[6,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 80},
    {vr_sensitivity11 + 81, "sensitivity[6,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 81},
    {vr_sensitivity11 + 82, "sensitivity[6,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 82},
    {vr_sensitivity11 + 83, "sensitivity[6,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 83},
    {vr_sensitivity11 + 84, "sensitivity[7,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 84},
    {vr_sensitivity11 + 85, "sensitivity[7,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 85},
    {vr_sensitivity11 + 86, "sensitivity[7,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 86},
    {vr_sensitivity11 + 87, "sensitivity[7,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 87},
    {vr_sensitivity11 + 88, "sensitivity[7,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 88},
    {vr_sensitivity11 + 89, "sensitivity[7,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 89},
    {vr_sensitivity11 + 90, "sensitivity[7,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 90},
    {vr_sensitivity11 + 91, "sensitivity[7,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 91},
    {vr_sensitivity11 + 92, "sensitivity[7,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 92},
    {vr_sensitivity11 + 93, "sensitivity[7,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 93},
    {vr_sensitivity11 + 94, "sensitivity[7,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 94},
    {vr_sensitivity11 + 95, "sensitivity[7,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 95},
    {vr_sensitivity11 + 96, "sensitivity[7,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 96},
    {vr_sensitivity11 + 97, "sensitivity[7,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 97},
    {vr_sensitivity11 + 98, "sensitivity[8,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 98},
    {vr_sensitivity11 + 99, "sensitivity[8,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 99},
    {vr_sensitivity11 + 100, "sensitivity[8,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 100},
    {vr_sensitivity11 + 101, "sensitivity[8,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 101},
    {vr_sensitivity11 + 102, "sensitivity[8,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 102},
    {vr_sensitivity11 + 103, "sensitivity[8,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 103},
    {vr_sensitivity11 + 104, "sensitivity[8,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 104},
    {vr_sensitivity11 + 105, "sensitivity[8,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 105},
    {vr_sensitivity11 + 106, "sensitivity[8,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 106},
    {vr_sensitivity11 + 107, "sensitivity[8,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 107},
    {vr_sensitivity11 + 108, "sensitivity[8,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 108},
    {vr_sensitivity11 + 109, "sensitivity[8,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 109},
    {vr_sensitivity11 + 110, "sensitivity[8,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 110},
    {vr_sensitivity11 + 111, "sensitivity[8,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 111},
    {vr_sensitivity11 + 112, "sensitivity[9,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 112},
    {vr_sensitivity11 + 113, "sensitivity[9,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 113},
    {vr_sensitivity11 + 114, "sensitivity[9,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 114},
    {vr_sensitivity11 + 115, "sensitivity[9,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 115},
    {vr_sensitivity11 + 116, "sensitivity[9,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 116},
    {vr_sensitivity11 + 117, "sensitivity[9,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 117},
    {vr_sensitivity11 + 118, "sensitivity[9,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 118},
    {vr_sensitivity11 + 119, "sensitivity[9,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 119},
    {vr_sensitivity11 + 120, "sensitivity[9,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 120},
    {vr_sensitivity11 + 121, "sensitivity[9,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 121},
    {vr_sensitivity11 + 122, "sensitivity[9,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 122},
    {vr_sensitivity11 + 123, "sensitivity[9,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 123},
    {vr_sensitivity11 + 124, "sensitivity[9,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 124},
    {vr_sensitivity11 + 125, "sensitivity[9,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 125},
    {vr_sensitivity11 + 126, "sensitivity[10,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 126},
    {vr_sensitivity11 + 127, "sensitivity[10,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 127},
    {vr_sensitivity11 + 128, "sensitivity[10,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 128},
    {vr_sensitivity11 + 129, "sensitivity[10,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 129},
    {vr_sensitivity11 + 130, "sensitivity[10,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 130},
    {vr_sensitivity11 + 131, "sensitivity[10,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 131},
    {vr_sensitivity11 + 132, "sensitivity[10,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 132},
    {vr_sensitivity11 + 133, "sensitivity[10,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 133},
    {vr_sensitivity11 + 134, "sensitivity[10,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 134},
    {vr_sensitivity11 + 135, "sensitivity[10,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 135},
    {vr_sensitivity11 + 136, "sensitivity[10,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 136},
    {vr_sensitivity11 + 137, "sensitivity[10,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 137},
    {vr_sensitivity11 + 138, "sensitivity[10,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 138},
    {vr_sensitivity11 + 139, "sensitivity[10,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 139},
    {vr_sensitivity11 + 140, "sensitivity[11,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 140},
    {vr_sensitivity11 + 141, "sensitivity[11,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 141},
    {vr_sensitivity11 + 142, "sensitivity[11,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 142},
    {vr_sensitivity11 + 143, "sensitivity[11,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 143},
    {vr_sensitivity11 + 144, "sensitivity[11,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 144},
    {vr_sensitivity11 + 145, "sensitivity[11,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 145},
    {vr_sensitivity11 + 146, "sensitivity[11,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 146},
    {vr_sensitivity11 + 147, "sensitivity[11,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 147},
    {vr_sensitivity11 + 148, "sensitivity[11,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 148},
    {vr_sensitivity11 + 149, "sensitivity[11,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 149},
    {vr_sensitivity11 + 150, "sensitivity[11,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 150},
    {vr_sensitivity11 + 151, "sensitivity[11,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 151},
    {vr_sensitivity11 + 152, "sensitivity[11,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 152},
    {vr_sensitivity11 + 153, "sensitivity[11,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 153},
    {vr_sensitivity11 + 154, "sensitivity[12,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 154},
    {vr_sensitivity11 + 155, "sensitivity[12,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 155},
    {vr_sensitivity11 + 156, "sensitivity[12,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 156},
    {vr_sensitivity11 + 157, "sensitivity[12,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 157},
    {vr_sensitivity11 + 158, "sensitivity[12,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 158},
    {vr_sensitivity11 + 159, "sensitivity[12,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 159},
    {vr_sensitivity11 + 160, "sensitivity[12,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 160},
    {vr_sensitivity11 + 161, "sensitivity[12,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 161},
    {vr_sensitivity11 + 162, "sensitivity[12,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 162},
    {vr_sensitivity11 + 163, "sensitivity[12,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 163},
    {vr_sensitivity11 + 164, "sensitivity[12,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 164},
    {vr_sensitivity11 + 165, "sensitivity[12,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 165},
    {vr_sensitivity11 + 166, "sensitivity[12,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 166},
    {vr_sensitivity11 + 167, "sensitivity[12,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 167},
    {vr_sensitivity11 + 168, "sensitivity[13,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 168},
    {vr_sensitivity11 + 169, "sensitivity[13,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 169},
    {vr_sensitivity11 + 170, "sensitivity[13,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 170},
    {vr_sensitivity11 + 171, "sensitivity[13,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 171},
    {vr_sensitivity11 + 172, "sensitivity[13,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 172},
    {vr_sensitivity11 + 173, "sensitivity[13,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 173},
    {vr_sensitivity11 + 174, "sensitivity[13,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 174},
    {vr_sensitivity11 + 175, "sensitivity[13,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 175},
    {vr_sensitivity11 + 176, "sensitivity[13,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 176},
    {vr_sensitivity11 + 177, "sensitivity[13,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 177},
    {vr_sensitivity11 + 178, "sensitivity[13,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 178},
    {vr_sensitivity11 + 179, "sensitivity[13,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 179},
    {vr_sensitivity11 + 180, "sensitivity[13,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 180},
    {vr_sensitivity11 + 181, "sensitivity[13,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 181},
    {vr_sensitivity11 + 182, "sensitivity[14,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 182},
    {vr_sensitivity11 + 183, "sensitivity[14,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 183},
    {vr_sensitivity11 + 184, "sensitivity[14,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 184},
    {vr_sensitivity11 + 185, "sensitivity[14,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 185},
    {vr_sensitivity11 + 186, "sensitivity[14,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 186},
    {vr_sensitivity11 + 187, "sensitivity[14,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 187},
    {vr_sensitivity11 + 188, "sensitivity[14,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 188},
    {vr_sensitivity11 + 189, "sensitivity[14,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 189},
    {vr_sensitivity11 + 190, "sensitivity[14,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 190},
    {vr_sensitivity11 + 191, "sensitivity[14,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 191},
    {vr_sensitivity11 + 192, "sensitivity[14,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 192},
    {vr_sensitivity11 + 193, "sensitivity[14,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 193},
    {vr_sensitivity11 + 194, "sensitivity[14,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 194},
    {vr_sensitivity11 + 195, "sensitivity[14,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 195},
    {vr_sensitivity11 + 196, "sensitivity[15,1]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 196},
    {vr_sensitivity11 + 197, "sensitivity[15,2]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 197},
    {vr_sensitivity11 + 198, "sensitivity[15,3]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 198},
    {vr_sensitivity11 + 199, "sensitivity[15,4]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 199},
    {vr_sensitivity11 + 200, "sensitivity[15,5]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 200},
    {vr_sensitivity11 + 201, "sensitivity[15,6]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 201},
    {vr_sensitivity11 + 202, "sensitivity[15,7]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 202},
    {vr_sensitivity11 + 203, "sensitivity[15,8]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 203},
    {vr_sensitivity11 + 204, "sensitivity[15,9]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 204},
    {vr_sensitivity11 + 205, "sensitivity[15,10]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 205},
    {vr_sensitivity11 + 206, "sensitivity[15,11]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 206},
    {vr_sensitivity11 + 207, "sensitivity[15,12]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 207},
    {vr_sensitivity11 + 208, "sensitivity[15,13]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 208},
    {vr_sensitivity11 + 209, "sensitivity[15,14]", VarReal, CausLocal, "", 0.0, -INF, INF, 0, 0, NONE, OutSensitivity11 + 209},
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

/* The model-exchange locals: the states excitationPhase, sliderPosition and the derivatives (the
 * sensitivities are co-simulation locals) */
static int modelExchangeOnly(FmiValueRef vr)
{
    return (vr >= vr_excitationPhase && vr <= vr_der_sliderPosition) ||
           (vr >= vr_modalDisplacement1 + 40 && vr < vr_modalVelocity1 + 45);
}

const FmiModel fmiModel = {
    MODEL_NAME, MODEL_GUID, VARS, (int)(sizeof VARS / sizeof VARS[0]), SOLVER_MAX_ORDER,
    sizeof(BladeData), sizeof(BladeMemory), 1, STATE_VERSION, FIELDS, (int)(sizeof FIELDS / sizeof FIELDS[0]),
    startValues, build, bladeWarnFullStickOnce, outputs, output, nonFiniteHint, doStep, validData,
    modelExchangeOnly,
};
