/* ShroudedBlade FMU instance: lifecycle (new, reset, free), the model built from the parameters,
 * experiment setup and initialization, and the communication step (see instance.h). The variables
 * are in variables.c, FMU states in fmu_state.c, logging in logging.c. No global mutable state. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "instance_internal.h"

/* ------------------------------------------------------------------------------------------- */
/* Names                                                                                       */

const char *fsmStateName(int32_t state)
{
    switch (state) {
    case FsmStartEnd: return "startAndEnd";
    case FsmInstantiated: return "instantiated";
    case FsmInitializationMode: return "initializationMode";
    case FsmStepComplete: return "stepComplete";
    case FsmStepInProgress: return "stepInProgress";
    case FsmStepFailed: return "stepFailed";
    case FsmStepCanceled: return "stepCanceled";
    case FsmTerminated: return "terminated";
    case FsmError: return "error";
    case FsmFatal: return "fatal";
    default: return "unknown";
    }
}

/* ------------------------------------------------------------------------------------------- */
/* Start values, lifecycle                                                                     */

static void setStartValues(Instance *inst)
{
    InstanceData *d = &inst->d;
    memset(d, 0, sizeof *d);
    d->fsm = FsmInstantiated;
    variablesStartValues(d);
    /* by the memset: time = startTime = 0, no stop time, last status fmi2OK (0), no warning
     * given yet, model not built */
    d->solver.B = d->par[ParB]; /* rebuilt by fmi2ExitInitializationMode; consistent until then */
    d->solver.side = d->solver.slipDir = d->solver.vdir = 1;
}

static char *copyString(const char *s)
{
    size_t n;
    char *p;
    if (s == NULL) return NULL;
    n = strlen(s);
    p = (char *)malloc(n + 1);
    if (p) memcpy(p, s, n + 1);
    return p;
}

Instance *instanceNew(const char *instanceName, const char *resourceLocation,
                      fmi2CallbackLogger logger, fmi2ComponentEnvironment env, int loggingOn)
{
    Instance *inst = (Instance *)calloc(1, sizeof *inst);
    if (inst == NULL) return NULL;
    inst->magic = INSTANCE_MAGIC;
    inst->instanceName = copyString(instanceName);
    inst->resourceLocation = copyString(resourceLocation);
    if (inst->instanceName == NULL || (resourceLocation != NULL && inst->resourceLocation == NULL)) {
        free(inst->instanceName);
        free(inst->resourceLocation);
        free(inst);
        return NULL;
    }
    inst->logger = logger;
    inst->componentEnvironment = env;
    for (int k = 0; k < LOG_NUM_CATEGORIES; ++k) inst->logOn[k] = loggingOn ? 1 : 0;
    setStartValues(inst);
    return inst;
}

void instanceFree(Instance *inst)
{
    if (inst == NULL) return;
    fmuStateFreeAll(inst);
    free(inst->instanceName);
    free(inst->resourceLocation);
    inst->magic = 0;
    free(inst);
}

void instanceReset(Instance *inst) { setStartValues(inst); }

/* ------------------------------------------------------------------------------------------- */
/* Model construction                                                                          */

/* The start value of jenkinsForce must fit the start state (model-notes s.7): 0 for the
 * describing-function models and for an open contact, inside the friction cone [-L, L] (relative
 * tolerance SOLVER_CONE_RTOL) otherwise. Cross-field, so checked here, not in fmi2SetReal. */
static fmi2Status checkStartForce(Instance *inst, const char *fn)
{
    const InstanceData *d = &inst->d;
    const double F0 = d->par[ParF0], q0 = d->par[ParQ0];
    double L;
    if (F0 == 0.0) return fmi2OK;
    if (d->model.friction != FrictionMacroslipTD) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: jenkinsForce = %.15g N: its start value applies only to frictionModel 3 (the "
                          "time-domain Jenkins element), here frictionModel = %d: accepted range [0, 0] N",
                          fn, F0, (int)d->ipar[IparFrictionModel]);
        return fmi2Error;
    }
    L = solverStartForceLimit(&d->model, q0);
    if (L < 0.0) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: jenkinsForce = %.15g N, but the contact is open at the start value "
                          "tipDisplacement = %.15g m (|q0| <= d = %g m), where the spring is unloaded: "
                          "accepted range [0, 0] N", fn, F0, q0, d->model.d);
        return fmi2Error;
    }
    if (!(fabs(F0) <= L * (1.0 + SOLVER_CONE_RTOL))) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: jenkinsForce = %.15g N is outside the friction cone: accepted range "
                          "[-%.15g, %.15g] N, from tipDisplacement = %.15g m (L = mu kn cos(gamma) "
                          "(|q0| - d), mu = %g, kn = %g N/m, gamma = %g rad, d = %g m)", fn, F0, L, L, q0,
                          d->par[ParMu], d->par[ParKn], d->par[ParGamma], d->par[ParD]);
        return fmi2Error;
    }
    return fmi2OK;
}

/* bladeReduce into d->blade, reusing the instance's last reduction when the blade parameters and
 * the formulation are bit-identical (a reduction costs ~90 us, a period of the blade ~30 us). */
static int bladeReduceCached(Instance *inst, const BladeParams *bp)
{
    InstanceData *d = &inst->d;
    const int32_t formulation = d->ipar[IparFormulation];
    int rc;
    if (inst->bladeCacheValid && inst->bladeCacheFormulation == formulation &&
        memcmp(&inst->bladeCacheParams, bp, sizeof *bp) == 0) {
        d->blade = inst->bladeCache;
        return 0;
    }
    inst->bladeCacheValid = 0;
    rc = bladeReduce(bp, (Formulation)formulation, &d->blade);
    if (rc == 0) {
        inst->bladeCacheParams = *bp;
        inst->bladeCacheFormulation = formulation;
        inst->bladeCache = d->blade;
        inst->bladeCacheValid = 1;
    }
    return rc;
}

/* Builds blade reduction and solver model from the parameters; if initState, also the initial
 * solver state (q0, v0, E0, F0, B, windowMax0). Logs and returns fmi2Error on failure. */
fmi2Status instanceBuildModel(Instance *inst, const char *fn, int initState)
{
    InstanceData *d = &inst->d;
    const double *p = d->par;
    BladeParams bp;
    ContactParams cp;
    SolverStatus st;
    d->modelValid = 0;
    bp.EI = p[ParEI];
    bp.rho = p[ParRho];
    bp.A = p[ParA];
    bp.l = p[ParL];
    bp.c = p[ParC];
    bp.m0 = p[ParM0];
    /* bladeReduce succeeds only with finite results and M > 0; the blade must also be stiff */
    if (bladeReduceCached(inst, &bp) != 0 || !(d->blade.K0static > 0.0)) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: the Galerkin reduction (eq. 19-26) failed for EI = %g N.m2, rho = %g kg/m3, "
                          "A = %g m2, l = %g m, c = %g N.s/m2, m0 = %g kg, formulation = %d "
                          "(M = %g kg, K0 = %g N/m): the blade parameters are not usable together",
                          fn, bp.EI, bp.rho, bp.A, bp.l, bp.c, bp.m0, (int)d->ipar[IparFormulation],
                          d->blade.M, d->blade.K0static);
        return fmi2Error;
    }
    cp.kn = p[ParKn];
    cp.kdRatio = p[ParKdRatio];
    cp.mu = p[ParMu];
    cp.gamma = p[ParGamma];
    cp.d = p[ParD];
    if (!contactParamsValid(&cp) ||
        solverBuildModel(&d->model, &d->blade, &cp, (FrictionModel)d->ipar[IparFrictionModel],
                         (Projection)d->ipar[IparProjection], d->ipar[IparGating] != 0,
                         d->ipar[IparAmplitudeMode] == 2, d->ipar[IparEngineOrder]) != 0) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: the contact parameters kn = %g N/m, kdRatio = %g, mu = %g, gamma = %g rad, "
                          "d = %g m are not usable together", fn, cp.kn, cp.kdRatio, cp.mu, cp.gamma, cp.d);
        return fmi2Error;
    }
    if (initState) {
        if (checkStartForce(inst, fn) != fmi2OK) return fmi2Error;
        st = solverInitState(&d->model, &d->solver, p[ParQ0], p[ParV0], p[ParE0], p[ParF0], p[ParB],
                             p[ParWindowMax0]);
    } else {
        st = solverUpdateDescribe(&d->model, &d->solver);
    }
    if (st != SolverOk) {
        instanceLogStatus(inst, fmi2Error,
                          "%s: the describing function (eq. 7-13) failed for B = %g m (d = %g m, kn = %g N/m, "
                          "kdRatio = %g, mu = %g, gamma = %g rad)", fn, d->solver.B, cp.d, cp.kn,
                          cp.kdRatio, cp.mu, cp.gamma);
        return fmi2Error;
    }
    d->modelValid = 1;
    return fmi2OK;
}

int instancePreInit(const InstanceData *d)
{
    return d->fsm == FsmInstantiated || d->fsm == FsmInitializationMode;
}

/* The model is needed to evaluate outputs; before initialization it follows the parameters. */
fmi2Status instanceEnsureModel(Instance *inst, const char *fn)
{
    if (inst->d.modelValid) return fmi2OK;
    return instanceBuildModel(inst, fn, instancePreInit(&inst->d));
}

static fmi2Status warnFullStickOnce(Instance *inst, const char *fn)
{
    InstanceData *d = &inst->d;
    if (d->warnedFullStick || d->solver.df.regime != RegimeFullStick) return fmi2OK;
    d->warnedFullStick = 1;
    instanceLogStatus(inst, fmi2Warning,
                      "%s: full-stick regime (MODEL.md s.3): kd tan(gamma) = %g N/m < mu kn = %g N/m, the "
                      "macroslip loop never slips; f_c = 0 and f_k = (kd tan(gamma)/kn) p_k are used "
                      "(B = %g m)", fn, d->model.kd * tan(d->par[ParGamma]),
                      d->par[ParMu] * d->par[ParKn], d->solver.B);
    return fmi2Warning;
}

/* ------------------------------------------------------------------------------------------- */
/* Experiment, initialization                                                                  */

fmi2Status instanceSetupExperiment(Instance *inst, int toleranceDefined, double tolerance,
                                   double startTime, int stopTimeDefined, double stopTime)
{
    const char *fn = "fmi2SetupExperiment";
    if (!isfinite(startTime)) {
        instanceLogStatus(inst, fmi2Error, "%s: startTime = %g s is not a finite number", fn, startTime);
        return fmi2Error;
    }
    if (stopTimeDefined && (!isfinite(stopTime) || stopTime < startTime)) {
        instanceLogStatus(inst, fmi2Error, "%s: stopTime = %g s must be finite and >= startTime = %g s", fn,
                          stopTime, startTime);
        return fmi2Error;
    }
    if (toleranceDefined && !(tolerance >= 0.0)) {
        instanceLogStatus(inst, fmi2Error, "%s: tolerance = %g must be >= 0", fn, tolerance);
        return fmi2Error;
    }
    /* the tolerance is not used: the fixed-step RK4 error is set by maxStep */
    inst->d.startTime = startTime;
    inst->d.time = startTime;
    inst->d.stopTimeDefined = stopTimeDefined ? 1 : 0;
    inst->d.stopTime = stopTimeDefined ? stopTime : 0.0;
    return fmi2OK;
}

fmi2Status instanceExitInitialization(Instance *inst)
{
    const char *fn = "fmi2ExitInitializationMode";
    fmi2Status status = instanceBuildModel(inst, fn, 1);
    if (status != fmi2OK) return status;
    inst->d.time = inst->d.startTime;
    return warnFullStickOnce(inst, fn);
}

/* ------------------------------------------------------------------------------------------- */
/* The communication step                                                                      */

static const char *contactName(int mode)
{
    return mode == ContactStick ? "stick" : (mode == ContactSlip ? "slip" : "open");
}

static const char *regimeName(int regime)
{
    return regime == RegimeStickSlip ? "stickSlip" : (regime == RegimeFullStick ? "fullStick" : "open");
}

/* logEvents: contact transitions and amplitude updates (only installed when enabled). */
static void eventHook(void *ctx, SolverEventKind kind, double t, const SolverState *s)
{
    Instance *inst = (Instance *)ctx;
    switch (kind) {
    case SolverEventGateOn:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: |q| > d, side %+d: K_eq = %g N/m and C_eq act (eq. 12-13)",
                    t, (int)s->side, s->df.Keq);
        break;
    case SolverEventGateOff:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: |q| <= d: K_eq and C_eq off (eq. 12-13)", t);
        break;
    case SolverEventContact:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: contact on side %+d: open -> %s", t, (int)s->side,
                    contactName(s->mode));
        break;
    case SolverEventSeparate:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: separation: -> open", t);
        break;
    case SolverEventStickToSlip:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: stick -> slip (s = %+d)", t, (int)s->slipDir);
        break;
    case SolverEventSlipToStick:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: slip -> stick", t);
        break;
    case SolverEventPeriodEnd:
        instanceLog(inst, fmi2OK, LogEvents, "t = %.12g s: excitation period %.0f ended: amplitude B = %.9g m (regime %s)",
                    t, s->periods, s->B, regimeName(s->df.regime));
        break;
    default:
        break;
    }
}

/* Re-expands the step's input polynomials at tau = h (the next communication point) into
 * inst->d.in, so an input the master does not set again continues as the same polynomial
 * (model-notes s.7). */
static void shiftInputs(Instance *inst, const SolverInputs *in, double h)
{
    for (int i = 0; i < SOLVER_NUM_INPUTS; ++i) {
        double c[SOLVER_MAX_ORDER + 1];
        const int top = in->top[i];
        double fact = 1.0;
        memcpy(c, in->coef[i], sizeof c);
        for (int j = 0; j < top; ++j) /* repeated synthetic division: Taylor shift */
            for (int k = top - 1; k >= j; --k) c[k] += h * c[k + 1];
        for (int j = 0; j <= SOLVER_MAX_ORDER; ++j) {
            if (j > 0) fact *= (double)j;
            inst->d.in[i][j] = j <= top ? c[j] * fact : 0.0;
        }
        inst->d.in[i][0] = solverInputAt(in, i, h); /* exactly the value checked */
    }
}

/* Addendum to an instability message: why a low speed makes a describing-function contact stiff. */
static const char *stiffHint(const InstanceData *d, double n0)
{
    return (d->model.friction != FrictionMacroslipTD && n0 < 100.0)
               ? "; at low rotorSpeed a describing-function contact is stiff since C_eq grows like 1/omega"
               : "";
}

#define MAX_INTERNAL_STEPS 1e7

/* Tolerance of a time comparison at time t [s] (model-notes s.6): 1e-9 max(1, |t|). */
static double timeTolerance(double t) { return 1e-9 * (fabs(t) > 1.0 ? fabs(t) : 1.0); }

fmi2Status instanceDoStep(Instance *inst, double tc, double h)
{
    const char *fn = "fmi2DoStep";
    InstanceData *d = &inst->d;
    const double tol = timeTolerance(d->time);
    double ratio, n0, n1, tFail = 0.0;
    long nSteps;
    SolverInputs in; /* the input polynomials of this step, from d->in (model-notes s.1) */
    SolverState backup;
    SolverStatus st;
    if (!isfinite(tc) || !isfinite(h)) {
        instanceLogStatus(inst, fmi2Error, "%s: currentCommunicationPoint = %g s and communicationStepSize = %g s "
                          "must be finite numbers", fn, tc, h);
        return fmi2Error;
    }
    if (!(h > 0.0)) {
        instanceLogStatus(inst, fmi2Error, "%s: communicationStepSize = %g s must be > 0", fn, h);
        return fmi2Error;
    }
    if (tc + h == tc) {
        instanceLogStatus(inst, fmi2Error, "%s: communicationStepSize = %g s is below the time resolution at "
                          "t = %.17g s (t + h == t): time would not advance", fn, h, tc);
        return fmi2Error;
    }
    if (fabs(tc - d->time) > tol) {
        instanceLogStatus(inst, fmi2Error, "%s: currentCommunicationPoint = %.17g s does not match the FMU time "
                          "%.17g s (tolerance %g s)", fn, tc, d->time, tol);
        return fmi2Error;
    }
    if (d->stopTimeDefined && tc + h > d->stopTime + timeTolerance(d->stopTime)) {
        instanceLogStatus(inst, fmi2Error, "%s: the step to %.17g s goes past the stop time %.17g s", fn, tc + h,
                          d->stopTime);
        return fmi2Error;
    }
    /* model-notes s.6: equal internal steps h / ceil(h / maxStep) (1e-9: h an exact multiple of
     * maxStep up to rounding takes h / maxStep steps) */
    ratio = h / d->par[ParMaxStep];
    if (!(ratio - 1e-9 <= MAX_INTERNAL_STEPS)) {
        instanceLogStatus(inst, fmi2Error, "%s: communicationStepSize = %g s needs %.3g internal steps of at most "
                          "maxStep = %g s; more than %.0f are refused: use a shorter communication step "
                          "or a larger maxStep", fn, h, ceil(ratio - 1e-9), d->par[ParMaxStep], MAX_INTERNAL_STEPS);
        return fmi2Error;
    }
    nSteps = (long)ceil(ratio - 1e-9);
    if (nSteps < 1) nSteps = 1;
    solverSetInputs(&in, (const double(*)[SOLVER_MAX_ORDER + 1])d->in);
    /* model-notes s.1: rotorSpeed in [0, 30000] rpm at both ends of the step */
    n0 = solverInputAt(&in, SOLVER_INPUT_SPEED, 0.0);
    n1 = solverInputAt(&in, SOLVER_INPUT_SPEED, h);
    if (!(n0 >= 0.0 && n0 <= 30000.0 && n1 >= 0.0 && n1 <= 30000.0)) {
        instanceLogStatus(inst, fmi2Discard, "%s: rotorSpeed = %g rpm at t = %.17g s and %g rpm at the step end "
                          "t = %.17g s: it must stay in [0, 30000] rpm (its derivatives extrapolate it out "
                          "of range); the step is refused, the state is unchanged", fn, n0, tc, n1, tc + h);
        d->lastDoStepStatus = fmi2Discard;
        return fmi2Discard;
    }
    backup = d->solver;
    st = solverAdvance(&d->model, &d->solver, &in, tc, h, nSteps,
                       instanceLogEnabled(inst, LogEvents) ? eventHook : NULL, inst, &inst->counters, &tFail);
    if (st != SolverOk) {
        const double tf = tc + tFail;
        d->solver = backup;
        switch (st) {
        case SolverNonFinite:
            /* low speed with a DF contact: C_eq ~ 1/omega makes the equation stiff */
            instanceLogStatus(inst, fmi2Discard, "%s: the state became non-finite near t = %.17g s (numerical "
                              "instability: try a smaller maxStep = %g s%s); the step from t = %.17g s is "
                              "discarded and the state restored", fn, tf, d->par[ParMaxStep],
                              stiffHint(d, n0), tc);
            break;
        case SolverChattering:
            instanceLogStatus(inst, fmi2Discard, "%s: more than %d switching events in one internal step near "
                              "t = %.17g s (chattering); the step from t = %.17g s is discarded and the state "
                              "restored", fn, SOLVER_MAX_EVENTS_PER_STEP, tf, tc);
            break;
        case SolverOmegaZero:
            instanceLogStatus(inst, fmi2Discard, "%s: rotorSpeed = 0 (omega = 0) near t = %.17g s while the "
                              "describing-function contact acts (B = %g m > d = %g m): f_c needs omega > 0; "
                              "the step from t = %.17g s is discarded and the state restored", fn, tf,
                              d->solver.B, d->par[ParD], tc);
            break;
        default:
            instanceLogStatus(inst, fmi2Discard, "%s: the describing function failed near t = %.17g s; the step "
                              "from t = %.17g s is discarded and the state restored", fn, tf, tc);
            break;
        }
        d->lastDoStepStatus = fmi2Discard;
        return fmi2Discard;
    }
    {   /* the state is finite, but a derived force may overflow (q' ~ 1e206 times C_eq ~ 1e214) */
        SolverOutputs o;
        const char *bad;
        solverOutputs(&d->model, &d->solver, n1, &o);
        bad = solverNonFiniteOutput(&o);
        if (bad != NULL) {
            d->solver = backup;
            instanceLogStatus(inst, fmi2Discard, "%s: the output %s is not finite at the step end t = %.17g s "
                              "(numerical instability: try a smaller maxStep = %g s%s); the step from t = %.17g s "
                              "is discarded and the state restored", fn, bad, tc + h, d->par[ParMaxStep],
                              stiffHint(d, n0), tc);
            d->lastDoStepStatus = fmi2Discard;
            return fmi2Discard;
        }
    }
    d->time = tc + h; /* model-notes s.6: the master's communication point plus h */
    shiftInputs(inst, &in, h);
    d->lastDoStepStatus = warnFullStickOnce(inst, fn);
    return (fmi2Status)d->lastDoStepStatus;
}
