/* The m-mode blade's setup shared by the blade FMUs (ShroudedBlade, BladeExternalContact;
 * docs/model.md s.2a): the checks of `modes` against the formulation and maxStep, the modal
 * reduction into the dynamics constants, the start state from the modal start values, and the
 * outputs only the modes have (modal coordinates, mode frequencies, root moment). */
#ifndef BLADE_MODES_H
#define BLADE_MODES_H

#include "fmi/instance.h"
#include "physics/dynamics.h"

/* RK4 is stable for a linear oscillator of angular frequency w while h w <= 2 sqrt(2) (the
 * stability region's extent on the imaginary axis). */
#define BLADE_RK4_STABLE_HW 2.8284271247461903

/* Relative tolerance of a tip start value against the sum of the modal ones. */
#define BLADE_START_SUM_RTOL 1e-12

/* The model's parameters for the modes. */
typedef struct {
    int modes;          /* m, 1..MODES_MAX */
    int formulation;    /* Formulation */
    double maxStep;     /* [s] */
    double speed;       /* rotorSpeed at initialization [rpm] */
} BladeModesSetup;

/* Per-instance cache of the last modal reduction (a master that resets and restarts with the same
 * blade, shooting, skips the root search and the quadrature). */
typedef struct {
    int32_t valid;
    int32_t modes;
    BladeParams params;
    ModalReduction reduction;
} BladeModesCache;

/* After dynBuildModel: for m > 1 the modal reduction, the m-mode constants (the printed
 * formulation is refused) and, in co-simulation, the maxStep check against the highest contact-free
 * mode at the speed of initialization (m = 1 keeps the one-mode blade's behaviour: no check). *curvature receives phi_i''(0) [1/m^2] of the modes scaled to
 * phi_i(l) = 1 (m = 1: of eq. 20 with r's root). Logs and returns FmiError on failure. */
FmiStatus bladeModesBuild(FmiInstance *inst, const char *fn, const BladeModesSetup *setup, const BladeParams *bp,
                          const BladeReduction *r, BladeModesCache *cache, DynModel *model,
                          double curvature[MODES_MAX]);

/* The start tip displacement u0 and rate du0 from the tip start values (q0, v0) and the modal
 * ones (qm, vm; m entries used): u0 = sum qm unless all qm are 0 (then q0: the tip start value
 * as a first-mode displacement); a nonzero q0 must then equal sum qm (within BLADE_START_SUM_RTOL of
 * sum |qm|, the state starts from sum qm); entries above m must be 0.
 * Same for the rates. Logs and returns FmiError on a conflict. */
FmiStatus bladeModesStart(FmiInstance *inst, const char *fn, int modes, double q0, double v0,
                          const double qm[MODES_MAX], const double vm[MODES_MAX], double *u0, double *du0);

/* After dynInitState(u0, du0): the modal coordinates of s from the modal start values (all 0: the
 * tip start is a first-mode displacement, q_2.. = 0). */
void bladeModesInitState(const DynModel *m, DynState *s, const double qm[MODES_MAX], const double vm[MODES_MAX]);

/* EI sum_i phi_i''(0) q_i [N m]. */
double bladeRootMoment(const DynModel *m, const DynState *s, double EI, const double curvature[MODES_MAX]);

#endif
