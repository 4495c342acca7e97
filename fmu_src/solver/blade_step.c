/* The ShroudedBlade communication step (model-notes s.1, s.6): internal step count from maxStep,
 * the input polynomials, the rotor speed range, solverAdvance with the events logged, the state
 * restored and the step discarded on numerical trouble, and the inputs carried to the next point. */
#include <math.h>

#include "fmi/log.h"
#include "models/shrouded_blade.h"
#include "models/shrouded_blade_config.h"

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

static const char *contactName(int mode)
{
    return mode == ContactStick ? "stick" : (mode == ContactSlip ? "slip" : "open");
}

static const char *regimeName(int regime)
{
    return regime == RegimeStickSlip ? "stickSlip" : (regime == RegimeFullStick ? "fullStick" : "open");
}

/* logEvents: contact transitions and amplitude updates (only installed when enabled; also the
 * model-exchange event iteration's log). */
void bladeEventHook(void *ctx, DynEventKind kind, double t, const DynState *s)
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

/* Re-expands the step's input polynomials at tau = h (the next communication point) into d->in,
 * so an input the master does not set again continues as the same polynomial (model-notes s.7). */
static void shiftInputs(BladeData *d, const SolverInputs *in, double h)
{
    for (int i = 0; i < SOLVER_NUM_INPUTS; ++i) solverShiftInput(in, i, h, d->in[i]);
}

/* Addendum to an instability message: why a low speed makes a describing-function contact stiff. */
static const char *stiffHint(const BladeData *d, double n0)
{
    return (d->model.friction != FrictionMacroslipTD && n0 < 100.0)
               ? "; at low rotorSpeed a describing-function contact is stiff since C_eq grows like 1/omega"
               : "";
}

#define MAX_INTERNAL_STEPS 1e7

/* The state is restored and the step discarded; logs why. */
static FmiStatus discard(FmiInstance *inst, const char *fn, DynStatus st, double tc, double tFail, double n0)
{
    const BladeData *d = BLADE_DATA(inst);
    const double tf = tc + tFail;
    switch (st) {
    case DynNonFinite:
        /* low speed with a DF contact: C_eq ~ 1/omega makes the equation stiff */
        fmiLogStatus(inst, FmiDiscard, "%s: the state became non-finite near t = %.17g s (numerical "
                     "instability: try a smaller maxStep = %g s%s); the step from t = %.17g s is "
                     "discarded and the state restored", fn, tf, d->par[ParMaxStep], stiffHint(d, n0), tc);
        break;
    case DynChattering:
        fmiLogStatus(inst, FmiDiscard, "%s: more than %d switching events in one internal step near "
                     "t = %.17g s (chattering); the step from t = %.17g s is discarded and the state "
                     "restored", fn, SOLVER_MAX_EVENTS_PER_STEP, tf, tc);
        break;
    case DynOmegaZero:
        fmiLogStatus(inst, FmiDiscard, "%s: rotorSpeed = 0 (omega = 0) near t = %.17g s while the "
                     "describing-function contact acts (B = %g m > d = %g m): f_c needs omega > 0; "
                     "the step from t = %.17g s is discarded and the state restored", fn, tf, d->state.B,
                     d->par[ParD], tc);
        break;
    default:
        fmiLogStatus(inst, FmiDiscard, "%s: the describing function failed near t = %.17g s; the step "
                     "from t = %.17g s is discarded and the state restored", fn, tf, tc);
        break;
    }
    return FmiDiscard;
}

FmiStatus bladeDoStep(FmiInstance *inst, const char *fn, double tc, double h)
{
    BladeData *d = BLADE_DATA(inst);
    double ratio, n0, n1, tFail = 0.0;
    long nSteps;
    SolverInputs in; /* the input polynomials of this step, from d->in (model-notes s.1) */
    DynState backup;
    DynSens sensBackup;
    DynSens *const sens = d->ipar[IparSensitivities] ? &d->sens : NULL; /* NULL: the hot path */
    DynStatus st;
    /* model-notes s.6: equal internal steps h / ceil(h / maxStep) (1e-9: h an exact multiple of
     * maxStep up to rounding takes h / maxStep steps) */
    ratio = h / d->par[ParMaxStep];
    if (!(ratio - 1e-9 <= MAX_INTERNAL_STEPS)) {
        fmiLogStatus(inst, FmiError, "%s: communicationStepSize = %g s needs %.3g internal steps of at most "
                     "maxStep = %g s; more than %.0f are refused: use a shorter communication step "
                     "or a larger maxStep", fn, h, ceil(ratio - 1e-9), d->par[ParMaxStep], MAX_INTERNAL_STEPS);
        return FmiError;
    }
    nSteps = (long)ceil(ratio - 1e-9);
    if (nSteps < 1) nSteps = 1;
    solverSetInputs(&in, (const double(*)[SOLVER_MAX_ORDER + 1])d->in);
    /* model-notes s.1: rotorSpeed in [0, ROTOR_SPEED_MAX] at both ends of the step */
    n0 = solverInputAt(&in, SOLVER_INPUT_SPEED, 0.0);
    n1 = solverInputAt(&in, SOLVER_INPUT_SPEED, h);
    if (!(n0 >= 0.0 && n0 <= ROTOR_SPEED_MAX && n1 >= 0.0 && n1 <= ROTOR_SPEED_MAX)) {
        fmiLogStatus(inst, FmiDiscard, "%s: rotorSpeed = %g rpm at t = %.17g s and %g rpm at the step end "
                     "t = %.17g s: it must stay in [0, %g] rpm (its derivatives extrapolate it out "
                     "of range); the step is refused, the state is unchanged", fn, n0, tc, n1, tc + h,
                     ROTOR_SPEED_MAX);
        return FmiDiscard;
    }
    backup = d->state;
    if (sens) sensBackup = *sens;
    st = solverAdvance(&d->model, &d->state, &in, tc, h, nSteps, fmiLogEnabled(inst, LogEvents) ? bladeEventHook : NULL,
                       inst, &BLADE_MEMORY(inst)->counters, &tFail, sens);
    if (st == DynOk && sens && !sensFinite(sens)) st = DynNonFinite;
    if (st != DynOk) {
        d->state = backup;
        if (sens) *sens = sensBackup;
        return discard(inst, fn, st, tc, tFail, n0);
    }
    {   /* the state is finite, but a derived force may overflow (q' ~ 1e206 times C_eq ~ 1e214) */
        DynOutputs o;
        const char *bad;
        dynOutputs(&d->model, &d->state, n1, &o);
        bad = dynNonFiniteOutput(&o);
        if (bad != NULL) {
            d->state = backup;
            if (sens) *sens = sensBackup;
            fmiLogStatus(inst, FmiDiscard, "%s: the output %s is not finite at the step end t = %.17g s "
                         "(numerical instability: try a smaller maxStep = %g s%s); the step from t = %.17g s "
                         "is discarded and the state restored", fn, bad, tc + h, d->par[ParMaxStep],
                         stiffHint(d, n0), tc);
            return FmiDiscard;
        }
    }
    shiftInputs(d, &in, h);
    return bladeWarnFullStickOnce(inst, fn);
}
