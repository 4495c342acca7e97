/* The communication step of the blade FMUs (see blade_step.h): ShroudedBlade and
 * BladeExternalContact step through here, the events are logged here (also those of
 * ShroudedBlade's model-exchange event iteration). */
#include <math.h>
#include <string.h>

#include "fmi/log.h"
#include "solver/blade_step.h"

static const char *contactName(int mode)
{
    return mode == ContactStick ? "stick" : (mode == ContactSlip ? "slip" : "open");
}

static const char *regimeName(int regime)
{
    return regime == RegimeStickSlip ? "stickSlip" : (regime == RegimeFullStick ? "fullStick" : "open");
}

/* logEvents: contact transitions and amplitude updates (only installed when enabled). */
void bladeLogEvent(void *ctx, DynEventKind kind, double t, const DynState *s)
{
    FmiInstance *inst = (FmiInstance *)ctx;
    switch (kind) {
    case DynEventGateOn:
        fmiLog(inst, FmiOK, LogEvents, "t = %.12g s: |q| > d, side %+d: K_eq = %g N/m and C_eq act (eq. 12-13)",
               t, (int)s->side, s->df.Keq);
        break;
    case DynEventGateOff:
        fmiLog(inst, FmiOK, LogEvents, "t = %.12g s: |q| <= d: K_eq and C_eq off (eq. 12-13)", t);
        break;
    case DynEventContact:
        fmiLog(inst, FmiOK, LogEvents, "t = %.12g s: contact on side %+d: open -> %s", t, (int)s->side,
               contactName(s->mode));
        break;
    case DynEventSeparate:
        fmiLog(inst, FmiOK, LogEvents, "t = %.12g s: separation: -> open", t);
        break;
    case DynEventStickToSlip:
        fmiLog(inst, FmiOK, LogEvents, "t = %.12g s: stick -> slip (s = %+d)", t, (int)s->slipDir);
        break;
    case DynEventSlipToStick:
        fmiLog(inst, FmiOK, LogEvents, "t = %.12g s: slip -> stick", t);
        break;
    case DynEventPeriodEnd:
        fmiLog(inst, FmiOK, LogEvents, "t = %.12g s: excitation period %.0f ended: amplitude B = %.9g m (regime %s)",
               t, s->periods, s->B, regimeName(s->df.regime));
        break;
    default:
        break;
    }
}

/* DF: a describing-function contact, whose C_eq grows like 1/omega at low speed */
static int describingFunction(const DynModel *m)
{
    return m->friction == FrictionMacroslipDF || m->friction == FrictionCoulombDF;
}

/* Addendum to an instability message: why a low speed makes a describing-function contact stiff,
 * else the model's hint. */
static const char *instabilityHint(const BladeStep *b, double n0)
{
    if (describingFunction(b->model) && n0 < 100.0)
        return "; at low rotorSpeed a describing-function contact is stiff since C_eq grows like 1/omega";
    return b->instabilityHint ? b->instabilityHint : "";
}

#define MAX_INTERNAL_STEPS 1e7

/* The state is restored and the step discarded; logs why. */
static FmiStatus discard(FmiInstance *inst, const char *fn, const BladeStep *b, DynStatus st, double tc,
                         double tFail, double n0)
{
    const double tf = tc + tFail;
    switch (st) {
    case DynNonFinite:
        fmiLogStatus(inst, FmiDiscard, "%s: the state became non-finite near t = %.17g s (numerical "
                     "instability: try a smaller maxStep = %g s%s); the step from t = %.17g s is "
                     "discarded and the state restored", fn, tf, b->maxStep, instabilityHint(b, n0), tc);
        break;
    case DynChattering:
        fmiLogStatus(inst, FmiDiscard, "%s: more than %d switching events in one internal step near "
                     "t = %.17g s (chattering); the step from t = %.17g s is discarded and the state "
                     "restored", fn, SOLVER_MAX_EVENTS_PER_STEP, tf, tc);
        break;
    case DynOmegaZero:
        fmiLogStatus(inst, FmiDiscard, "%s: rotorSpeed = 0 (omega = 0) near t = %.17g s while the "
                     "describing-function contact acts (B = %g m > d = %g m): f_c needs omega > 0; "
                     "the step from t = %.17g s is discarded and the state restored", fn, tf, b->state->B,
                     b->model->contact.d, tc);
        break;
    default:
        fmiLogStatus(inst, FmiDiscard, "%s: the describing function failed near t = %.17g s; the step "
                     "from t = %.17g s is discarded and the state restored", fn, tf, tc);
        break;
    }
    return FmiDiscard;
}

/* The external force on q: the sum of the force inputs; a derivative that is 0 in a later input
 * leaves the bits of the sum so far as they are (one input alone is that input exactly). */
static void setForce(SolverInputs *in, const BladeStep *b)
{
    double(*f)[SOLVER_MAX_ORDER + 1] = b->in + SOLVER_INPUT_FORCE;
    double F[SOLVER_MAX_ORDER + 1];
    for (int j = 0; j <= SOLVER_MAX_ORDER; ++j) {
        F[j] = f[0][j];
        for (int k = 1; k < b->nForces; ++k)
            if (f[k][j] != 0.0) F[j] += f[k][j];
    }
    solverSetForce(in, F);
}

/* Re-expands the step's input polynomials at tau = h (the next communication point) into b->in,
 * so an input the master does not set again continues as the same polynomial (model-notes s.7);
 * each force input on its own polynomial. */
static void shiftInputs(const BladeStep *b, const SolverInputs *in, double h)
{
    solverShiftInput(in, SOLVER_INPUT_AERO, h, b->in[SOLVER_INPUT_AERO]);
    solverShiftInput(in, SOLVER_INPUT_SPEED, h, b->in[SOLVER_INPUT_SPEED]);
    for (int k = 0; k < b->nForces; ++k) {
        double *f = b->in[SOLVER_INPUT_FORCE + k];
        SolverInputs one;
        memset(&one, 0, sizeof one);
        solverSetForce(&one, f);
        solverShiftInput(&one, SOLVER_INPUT_FORCE, h, f);
    }
}

FmiStatus bladeStep(FmiInstance *inst, const char *fn, const BladeStep *b, double tc, double h)
{
    double ratio, n0, n1, tFail = 0.0;
    long nSteps;
    SolverInputs in; /* the input polynomials of this step, from b->in (model-notes s.1) */
    DynState backup;
    DynSens sensBackup;
    DynSens *const sens = b->sens;
    DynStatus st;
    /* model-notes s.6: equal internal steps h / ceil(h / maxStep) (1e-9: h an exact multiple of
     * maxStep up to rounding takes h / maxStep steps) */
    ratio = h / b->maxStep;
    if (!(ratio - 1e-9 <= MAX_INTERNAL_STEPS)) {
        fmiLogStatus(inst, FmiError, "%s: communicationStepSize = %g s needs %.3g internal steps of at most "
                     "maxStep = %g s; more than %.0f are refused: use a shorter communication step "
                     "or a larger maxStep", fn, h, ceil(ratio - 1e-9), b->maxStep, MAX_INTERNAL_STEPS);
        return FmiError;
    }
    nSteps = (long)ceil(ratio - 1e-9);
    if (nSteps < 1) nSteps = 1;
    solverSetInputs(&in, (const double(*)[SOLVER_MAX_ORDER + 1])b->in);
    if (b->nForces > 0) setForce(&in, b);
    /* model-notes s.1: rotorSpeed in [0, speedMax] at both ends of the step */
    n0 = solverInputAt(&in, SOLVER_INPUT_SPEED, 0.0);
    n1 = solverInputAt(&in, SOLVER_INPUT_SPEED, h);
    if (!(n0 >= 0.0 && n0 <= b->speedMax && n1 >= 0.0 && n1 <= b->speedMax)) {
        fmiLogStatus(inst, FmiDiscard, "%s: rotorSpeed = %g rpm at t = %.17g s and %g rpm at the step end "
                     "t = %.17g s: it must stay in [0, %g] rpm (its derivatives extrapolate it out "
                     "of range); the step is refused, the state is unchanged", fn, n0, tc, n1, tc + h,
                     b->speedMax);
        return FmiDiscard;
    }
    backup = *b->state;
    if (sens) sensBackup = *sens;
    st = solverAdvance(b->model, b->state, &in, tc, h, nSteps, fmiLogEnabled(inst, LogEvents) ? bladeLogEvent : NULL,
                       inst, b->counters, &tFail, sens);
    if (st == DynOk && sens && !sensFinite(sens)) st = DynNonFinite;
    if (st != DynOk) {
        *b->state = backup;
        if (sens) *sens = sensBackup;
        return discard(inst, fn, b, st, tc, tFail, n0);
    }
    {   /* the state is finite, but a derived force may overflow (q' ~ 1e206 times C_eq ~ 1e214) */
        DynOutputs o;
        const char *bad;
        dynOutputs(b->model, b->state, n1, &o);
        bad = dynNonFiniteOutput(&o);
        if (bad != NULL) {
            *b->state = backup;
            if (sens) *sens = sensBackup;
            fmiLogStatus(inst, FmiDiscard, "%s: the output %s is not finite at the step end t = %.17g s "
                         "(numerical instability: try a smaller maxStep = %g s%s); the step from t = %.17g s "
                         "is discarded and the state restored", fn, bad, tc + h, b->maxStep,
                         instabilityHint(b, n0), tc);
            return FmiDiscard;
        }
    }
    shiftInputs(b, &in, h);
    return FmiOK;
}
