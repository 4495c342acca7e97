/* Sensitivities of the blade's state to its start values and to B (docs/model-notes.md s.8): the
 * variational equations of eq. 27 integrated with the state, the jump conditions (saltation) at
 * every event, and the gradient of max |q| over the running period. Pure C, no allocation.
 *
 * Rows: the states y = (q, q', w) (w the Jenkins slider, model-notes s.2). Columns: the parameters
 * p = (q0, q0', F0, B): the start values of tipDisplacement, tipVelocity, jenkinsForce and the
 * parameter B. Between events the right-hand side is affine in y with mode-dependent constant
 * coefficients, so the RK4 of the variational equations on the state's stages is the exact
 * derivative of the state's RK4 step. */
#ifndef VARIATIONAL_H
#define VARIATIONAL_H

#include "physics/dynamics.h"

#define SENS_NY 3 /* q, q', w */
#define SENS_NP 4 /* q0, q0', F0, B */
/* m > 1 modes (docs/model.md s.2a): rows y = (u, u', w, q_2..q_6, q_2'..q_6') (u the tip, at the
 * places of the state vector x, dynamics.h), columns p = (u0, u0', F0, B, q_2(0)..q_6(0), q_2'(0)..
 * q_6'(0)); those above m stay 0. The one-mode blade uses the first SENS_NY rows, SENS_NP columns. */
#define SENS_NY_MAX (SENS_NY + 2 * (MODES_MAX - 1))
#define SENS_NP_MAX (SENS_NP + 2 * (MODES_MAX - 1))
#define SENS_PEAKS 3 /* the positive and the negative peak of q in the running period, the floor */

/* Two peaks of max |q| closer than this (relative) count as one kink: its gradient is their mean,
 * the limit of a central difference (a half-wave symmetric orbit has equal peaks). */
#define SENS_SYMMETRIC_RTOL 1e-8

typedef struct {
    double S[SENS_NY_MAX][SENS_NP_MAX]; /* dy/dp */
    double dB[SENS_NP_MAX];             /* dB/dp of the amplitude in use (changes at period ends) */
    double peak[SENS_PEAKS];            /* max q, max -q over the running period, the start floor [m];
                                           -1: none yet */
    double gPeak[SENS_PEAKS][SENS_NP_MAX]; /* their gradients */
    double dKeq;                        /* dK_eq/dB at the B in use [N/m^2] */
    double dCeqOmega;                   /* d(C_eq omega)/dB [N/m^2] */
    int32_t grazing;                    /* events met tangentially (their jump term left out) */
} DynSens;

/* Sensitivities at the start (after dynInitState): identity in (q0, q0'), w's dependence on q0
 * and F0 (on the friction cone, in slip, the q0 derivative is taken along the cone and the F0
 * one is 0), dB/dp = e_B, the peaks of the start (|q0| on its side, windowMax0 as a floor with
 * gradient 0). Returns DynOk or DynDescribeFailed (dK_eq/dB). */
DynStatus sensInit(const DynModel *m, const DynState *s, double windowMax0, DynSens *e);

/* One RK4 step of size h of the variational equations dS/dt = A(mode, n) S + (df/dB) dB^T over
 * the state's step with stage states x[0..3] (q, q' first; x[0] the step start) and rotor speeds
 * n (start, middle, end) [rpm]: the exact derivative of that step. */
void sensRk4(const DynModel *m, const DynState *s, DynSens *e, double h, const double n[3],
             const double *const x[4]);

/* The jump of S at the event of switching function sw. before/after: the discrete state before
 * and after dynApplyEvent (continuous state at the event instant); fMinus, fPlus: dx/dt just
 * before and after. Also records the peaks (extremum), updates dB and restarts the peaks (period
 * end). Returns DynOk or DynDescribeFailed. */
DynStatus sensEvent(const DynModel *m, const DynState *before, const DynState *after, DynSwitch sw,
                    const double fMinus[DYN_NX_MAX], const double fPlus[DYN_NX_MAX], DynSens *e);

/* Gradient of max |q| over the running period (runningMaximum): the largest peak's, or the mean
 * of the two peaks where they are equal within SENS_SYMMETRIC_RTOL. */
void sensPeakGradient(const DynSens *e, double g[SENS_NP_MAX]);

/* Gradient of the Jenkins spring force k_d (sin g q - w) (0 while open). */
void sensJenkinsForceGradient(const DynModel *m, const DynState *s, const DynSens *e, double g[SENS_NP_MAX]);

/* The Jacobian in modal coordinates (docs/model.md s.2a): J[r][c], rows the modal q_1..q_6,
 * q_1'..q_6', jenkinsForce, runningMaximum, amplitude; columns the start values of q_1..q_6,
 * q_1'..q_6', jenkinsForce and B (entries above m are 0). */
#define SENS_MODAL_ROWS (2 * MODES_MAX + 3)
#define SENS_MODAL_COLS (2 * MODES_MAX + 2)
void sensModalJacobian(const DynModel *m, const DynState *s, const DynSens *e,
                       double J[SENS_MODAL_ROWS][SENS_MODAL_COLS]);

/* 1 if every entry is finite. */
int sensFinite(const DynSens *e);

#endif
