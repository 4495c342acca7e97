/* The m-mode blade's setup shared by the blade FMUs (see blade_modes.h; docs/model.md s.2a). */
#include "solver/blade_modes.h"

#include <math.h>
#include <string.h>

#include "fmi/log.h"

static int modalReduceCached(BladeModesCache *c, const BladeParams *bp, int modes)
{
    int rc;
    if (c->valid && c->modes == modes && memcmp(&c->params, bp, sizeof *bp) == 0) return 0;
    c->valid = 0;
    rc = modesReduce(bp, modes, &c->reduction);
    if (rc == 0) {
        c->valid = 1;
        c->modes = modes;
        c->params = *bp;
    }
    return rc;
}

/* The stable-step rule: maxStep w_max <= 2 sqrt(2), w_max the highest contact-free mode at the
 * speed of initialization. Co-simulation only: in model exchange the importer's solver takes the
 * steps and maxStep is not used. */
static FmiStatus checkMaxStep(FmiInstance *inst, const char *fn, const BladeModesSetup *setup, const DynModel *m)
{
    double f[MODES_MAX], w, hMax;
    if (inst->me != NULL) return FmiOK;
    dynModeFrequencies(m, setup->speed, f);
    w = DYN_TWO_PI * f[m->modes - 1];
    hMax = BLADE_RK4_STABLE_HW / w;
    if (isfinite(w) && !(setup->maxStep <= hMax)) {
        fmiLogStatus(inst, FmiError,
                     "%s: maxStep = %g s is too large for mode %d of modes = %d (%.6g Hz at rotorSpeed = %g "
                     "rpm): RK4 is stable only for maxStep * omega <= 2 sqrt(2), i.e. maxStep <= %.4g s "
                     "(docs/model.md s.2a)", fn, setup->maxStep, m->modes, m->modes, f[m->modes - 1],
                     setup->speed, hMax);
        return FmiError;
    }
    return FmiOK;
}

FmiStatus bladeModesBuild(FmiInstance *inst, const char *fn, const BladeModesSetup *setup, const BladeParams *bp,
                          const BladeReduction *r, BladeModesCache *cache, DynModel *model,
                          double curvature[MODES_MAX])
{
    memset(curvature, 0, sizeof(double) * MODES_MAX);
    if (setup->modes < 1 || setup->modes > MODES_MAX) { /* the variable table's range checks first */
        fmiLogStatus(inst, FmiError, "%s: modes = %d is outside its range [1, %d]", fn, setup->modes, MODES_MAX);
        return FmiError;
    }
    if (setup->modes == 1) { /* the one-mode blade as it always was: no step check */
        curvature[0] = modesRootCurvature(r->lambdaL, bp->l);
        return FmiOK;
    }
    if (setup->formulation != FormulationConsistent) {
        fmiLogStatus(inst, FmiError,
                     "%s: modes = %d needs formulation = 2 (consistent): the printed formulation (eq. 26, "
                     "formulation = 1) lets the contact act on q as if q were the tip displacement and leaves "
                     "out the inertia of the tip mass, which has no m-mode form; modes > 1 is accepted in "
                     "[2, %d] only with formulation = 2 (with formulation = 1 the range of modes is [1, 1])",
                     fn, setup->modes, MODES_MAX);
        return FmiError;
    }
    if (modalReduceCached(cache, bp, setup->modes) != 0 || dynBuildModes(model, &cache->reduction) != 0) {
        fmiLogStatus(inst, FmiError,
                     "%s: the %d-mode reduction (eq. 19-21) failed for EI = %g N.m2, rho = %g kg/m3, A = %g m2, "
                     "l = %g m, c = %g N.s/m2, m0 = %g kg: the blade parameters are not usable together",
                     fn, setup->modes, bp->EI, bp->rho, bp->A, bp->l, bp->c, bp->m0);
        return FmiError;
    }
    memcpy(curvature, cache->reduction.curvature0, sizeof(double) * MODES_MAX);
    return checkMaxStep(inst, fn, setup, model);
}

/* One of the two start sums (displacements or rates), see bladeModesStart. */
static FmiStatus startSum(FmiInstance *inst, const char *fn, int modes, double tip, const double a[MODES_MAX],
                          const char *tipName, const char *modalName, double *u)
{
    int any = 0;
    for (int k = 0; k < MODES_MAX; ++k) {
        if (a[k] == 0.0) continue;
        if (k >= modes) {
            fmiLogStatus(inst, FmiError, "%s: %s[%d] = %.15g, but modes = %d: the start values of %s[%d..%d] "
                         "must be 0 (accepted range [0, 0])", fn, modalName, k + 1, a[k], modes, modalName,
                         modes + 1, MODES_MAX);
            return FmiError;
        }
        any = 1;
    }
    if (!any) {
        *u = tip;
        return FmiOK;
    }
    *u = a[0];
    double size = fabs(a[0]);
    for (int k = 1; k < modes; ++k) {
        *u += a[k];
        size += fabs(a[k]);
    }
    /* a tip read back from the outputs may differ from the sum by rounding */
    if (tip != 0.0 && !(fabs(tip - *u) <= BLADE_START_SUM_RTOL * size)) {
        fmiLogStatus(inst, FmiError, "%s: %s = %.17g disagrees with the sum of the start values of %s[1..%d] "
                     "= %.17g (the tip is their sum; accepted: within %g of sum |%s[i]|): set one of the two "
                     "(the other 0) or both consistently", fn, tipName, tip, modalName, modes, *u,
                     BLADE_START_SUM_RTOL, modalName);
        return FmiError;
    }
    return FmiOK;
}

FmiStatus bladeModesStart(FmiInstance *inst, const char *fn, int modes, double q0, double v0,
                          const double qm[MODES_MAX], const double vm[MODES_MAX], double *u0, double *du0)
{
    if (startSum(inst, fn, modes, q0, qm, "tipDisplacement", "modalDisplacement", u0) != FmiOK) return FmiError;
    return startSum(inst, fn, modes, v0, vm, "tipVelocity", "modalVelocity", du0);
}

void bladeModesInitState(const DynModel *m, DynState *s, const double qm[MODES_MAX], const double vm[MODES_MAX])
{
    if (m->modes > 1) dynSetModalStart(m, s, qm, vm);
}

double bladeRootMoment(const DynModel *m, const DynState *s, double EI, const double curvature[MODES_MAX])
{
    double q[MODES_MAX], v[MODES_MAX], M = 0.0;
    dynModalState(m, s, q, v);
    for (int k = 0; k < m->modes; ++k) M += curvature[k] * q[k];
    return EI * M;
}
