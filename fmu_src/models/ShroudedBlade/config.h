/* ShroudedBlade FMU: identity and value references (stable contract, see modelDescription.xml). */
#ifndef SHROUDED_BLADE_CONFIG_H
#define SHROUDED_BLADE_CONFIG_H

#define MODEL_IDENTIFIER ShroudedBlade
#define MODEL_NAME "ShroudedBlade"
/* Must equal the guid attribute of modelDescription.xml (checked by CMake at configure time). */
#define MODEL_GUID "{be1fc0de-d8b5-40e4-a0fb-399d8d12a40d}"

/* Real parameters */
#define vr_EI 1
#define vr_rho 2
#define vr_A 3
#define vr_l 4
#define vr_c 5
#define vr_m0 6
#define vr_kn 7
#define vr_kdRatio 8
#define vr_mu 9
#define vr_gamma 10
#define vr_d 11
#define vr_B 12
#define vr_maxStep 13
#define vr_Fw0 14
/* Integer parameters */
#define vr_frictionModel 20
#define vr_formulation 21
#define vr_projection 22
#define vr_amplitudeMode 23
#define vr_engineOrder 24
#define vr_bladeIndex 25
#define vr_bladeCount 26
#define vr_modes 28 /* number of bending modes m (docs/model.md s.2a) */
/* Boolean parameters */
#define vr_gating 30
#define vr_sensitivities 31
/* Range of rotorSpeed [rpm] (model-notes s.1): its max, also in modelDescription.xml */
#define ROTOR_SPEED_MAX 30000.0

/* Real inputs */
#define vr_aeroLoad 40
#define vr_rotorSpeed 41
/* Real outputs */
#define vr_tipDisplacement 50
#define vr_tipVelocity 51
#define vr_normalForce 52
#define vr_frictionForce 53
#define vr_Keq 54
#define vr_Ceq 55
#define vr_amplitude 56
#define vr_dissipatedEnergy 57
#define vr_naturalFrequency 58
#define vr_jenkinsForce 59
/* Integer outputs */
#define vr_regime 60
#define vr_contactState 61
/* Real output after the Integer ones (60, 61 were taken) */
#define vr_runningMaximum 62
/* Model exchange: the continuous states without a variable so far, and the state derivatives */
#define vr_excitationPhase 70
#define vr_sliderPosition 71
#define vr_der_tipDisplacement 80
#define vr_der_tipVelocity 81
#define vr_der_excitationPhase 82
#define vr_der_dissipatedEnergy 83
#define vr_der_sliderPosition 84
/* Sensitivities (co-simulation, parameter sensitivities = true): d(output)/d(p) for the outputs
 * tipDisplacement, tipVelocity, jenkinsForce, runningMaximum, amplitude (in this order) and
 * p = (start tipDisplacement, start tipVelocity, start jenkinsForce, B): vr_sens0 + 4 row + col */
#define vr_sens0 100
/* m modes (docs/model.md s.2a): element i = 1..6 of each array at base + i - 1 */
#define vr_modalDisplacement1 200
#define vr_modalVelocity1 210
#define vr_modeFrequency1 220
#define vr_rootMoment 230
/* the modal Jacobian sensitivity[r,c] (r = 1..15, c = 1..14, docs/model.md s.2a) at
 * vr_sensitivity11 + 14 (r - 1) + (c - 1) */
#define vr_sensitivity11 1000

#endif
