/* ShroudedBlade for model exchange (FMI 2.0 ME, docs/model-notes.md s.2, s.3, s.6): the continuous
 * states x = (q, q', psi, E, w) of DynState and the modal coordinates q_2..q_6, q_2'..q_6' (a fixed
 * number, DYN_NX_MAX: those above m, docs/model.md s.2a, are held at 0 with derivative 0), the right-hand side dynRhs at the current inputs, one
 * event indicator per switching function of dynSwitching, and the event iteration with
 * dynApplyEvent: the functions the co-simulation integrator (solver/rk4_events.c) uses. The
 * discrete state (gate or contact mode, side, slip direction, amplitude B, running maximum,
 * period count, direction of q') changes only at events. Only the FMI 2.0 binary links this file
 * (through fmiModelExchange): the co-simulation code never calls into it. */
#include <math.h>
#include <string.h>

#include "fmi/log.h"
#include "models/ShroudedBlade/blade_data.h"
#include "physics/dynamics_step.h"
#include "solver/blade_step.h"

/* The model-exchange part of the FMU state (inst->meData): contactState taken at the last
 * fmi2NewDiscreteStates and held until the next (a discrete variable, model-notes s.6). Zero
 * (none held) after every build, so also after deserialization: then taken from the state at the
 * next read. */
typedef struct {
    int32_t held;          /* 1: contactState below is the held value */
    int32_t contactState;
} BladeMeData;

/* Per-instance memory of model exchange (inst->meMemory). */
typedef struct {
    uint32_t fresh;        /* switching functions not seen > 0 since a switch made them active
                              (bits 1 << DynSwitch; see eventUpdate) */
} BladeMeMemory;

#define ME_DATA(inst) ((BladeMeData *)(inst)->meData)
#define ME_MEMORY(inst) ((BladeMeMemory *)(inst)->meMemory)

/* Event indicator slots: a switching function of dynSwitching goes to a fixed slot; a slot with
 * no active function holds 1 (constant between events). ZLoop..: the phases where the
 * describing-function loop changes contactState (model-notes s.4): contactState is a discrete
 * variable, so its changes must be events too (it is held between them, see holdContactState). */
enum { ZGate0 = 0, ZGate1, ZFriction0, ZFriction1, ZPeriod, ZExtremum, ZLoop, NZ = ZLoop + 5 };
/* the counts the model description declares (model.toml) are these (a negative array size otherwise) */
typedef char DescriptionAgreesWithC[(NZ == MODEL_EVENT_INDICATORS && DYN_NX_MAX == MODEL_CONTINUOUS_STATES) ? 1 : -1];

static int slotOf(DynSwitch k)
{
    switch (k) {
    case DynSwitchEnterPos: case DynSwitchLeave: return ZGate0;
    case DynSwitchEnterNeg: return ZGate1;
    case DynSwitchSlipPos: case DynSwitchStick: return ZFriction0;
    case DynSwitchSlipNeg: return ZFriction1;
    case DynSwitchPeriod: return ZPeriod;
    default: return ZExtremum;
    }
}

static void loadX(const DynState *s, double x[DYN_NX_MAX])
{
    x[0] = s->q; x[1] = s->v; x[2] = s->psi; x[3] = s->E; x[4] = s->w;
    for (int k = 0; k < MODES_MAX - 1; ++k) {
        x[DYN_NX + k] = s->qx[k];
        x[DYN_X_RATES + k] = s->vx[k];
    }
}

static void getStates(const FmiInstance *inst, double x[]) { loadX(&BLADE_DATA(inst)->state, x); }

/* the states above m stay 0 */
static void setStates(FmiInstance *inst, const double x[])
{
    BladeData *d = BLADE_DATA(inst);
    DynState *s = &d->state;
    s->q = x[0]; s->v = x[1]; s->psi = x[2]; s->E = x[3]; s->w = x[4];
    for (int k = 0; k < MODES_MAX - 1; ++k) {
        s->qx[k] = k < d->model.modes - 1 ? x[DYN_NX + k] : 0.0;
        s->vx[k] = k < d->model.modes - 1 ? x[DYN_X_RATES + k] : 0.0;
    }
}

/* Scales of the states (an integrator's absolute tolerance is relative tolerance x nominal): the
 * gap or the amplitude parameter for q and w, times the contact-free angular frequency for q',
 * one period for psi, the elastic energy at that scale for E. From the parameters only. */
static void nominals(const FmiInstance *inst, double x[])
{
    const BladeData *d = BLADE_DATA(inst);
    double qn = d->par[ParD] > d->par[ParB] ? d->par[ParD] : d->par[ParB];
    double wn = inst->built && d->blade.M > 0.0 ? sqrt(d->blade.K0static / d->blade.M) : 0.0;
    double en = inst->built ? d->blade.K0static * qn * qn : 0.0;
    if (!(qn > 0.0) || !isfinite(qn)) qn = 1e-5;
    if (!(wn > 0.0) || !isfinite(wn)) wn = 1e3;
    if (!(en > 0.0) || !isfinite(en)) en = 1e-3;
    x[0] = qn;
    x[1] = qn * wn;
    x[2] = DYN_TWO_PI;
    x[3] = en;
    x[4] = qn;
    for (int k = 0; k < MODES_MAX - 1; ++k) { /* the higher modes: the scales of q and q' */
        x[DYN_NX + k] = x[0];
        x[DYN_X_RATES + k] = x[1];
    }
}

static FmiStatus derivatives(FmiInstance *inst, const char *fn, double dx[])
{
    const BladeData *d = BLADE_DATA(inst);
    double x[DYN_NX_MAX];
    loadX(&d->state, x);
    for (int i = DYN_NX; i < DYN_NX_MAX; ++i) dx[i] = 0.0; /* m = 1: the held higher modes */
    if (dynRhs(&d->model, &d->state, d->in[SOLVER_INPUT_AERO][0], d->in[SOLVER_INPUT_SPEED][0], x, dx)) {
        fmiLogStatus(inst, FmiDiscard, "%s: rotorSpeed = 0 (omega = 0) at t = %.17g s while the "
                     "describing-function contact acts (B = %g m > d = %g m): f_c needs omega > 0", fn,
                     inst->run.time, d->state.B, d->par[ParD]);
        return FmiDiscard;
    }
    for (int i = 0; i < DYN_NX_MAX; ++i) {
        if (!isfinite(dx[i])) { /* a state set far out (e.g. q = 1e300): no silent inf for the solver */
            fmiLogStatus(inst, FmiDiscard, "%s: der(x[%d]) = %g is not finite at t = %.17g s (q = %g m, q' = %g m/s)",
                         fn, i, dx[i], inst->run.time, d->state.q, d->state.v);
            return FmiDiscard;
        }
    }
    return FmiOK;
}

/* The active switching functions at the current state, with their slopes (h = 1). */
static int switching(const BladeData *d, DynSwitchValue sv[DYN_MAX_SWITCHING])
{
    double x[DYN_NX_MAX], f[DYN_NX_MAX];
    loadX(&d->state, x);
    (void)dynRhs(&d->model, &d->state, d->in[SOLVER_INPUT_AERO][0], d->in[SOLVER_INPUT_SPEED][0], x, f);
    return dynSwitching(&d->model, &d->state, 1.0, x, f, sv);
}

/* Kinds as bits (DynSwitch values are < 32). */
#define BIT(k) (1u << (unsigned)(k))

/* Switching functions seen > 0 leave the set of fresh ones (see eventUpdate). */
static void unfresh(FmiInstance *inst, const DynSwitchValue sv[], int n)
{
    BladeMeMemory *mem = ME_MEMORY(inst);
    for (int i = 0; i < n; ++i)
        if (sv[i].g > 0.0) mem->fresh &= ~BIT(sv[i].kind);
}

/* The loop phase theta = atan2(y, x), x = q, y = -q'/omega, of dynOutputs crosses a switching
 * angle a (or a + pi) where r sin(theta - a) = y cos a - x sin a [m] changes sign. Only in a
 * describing-function contact in the stick-slip regime at omega > 0; else the slots hold 1. */
static void loopIndicators(const BladeData *d, double z[5])
{
    const DynModel *m = &d->model;
    const DynState *s = &d->state;
    const double omega = m->omegaPerRpm * d->in[SOLVER_INPUT_SPEED][0];
    double a[5];
    int n = 0;
    if (m->friction != FrictionMacroslipTD && omega > 0.0 && dynContactOn(m, s) && s->df.regime == RegimeStickSlip)
        n = contactLoopSwitchAngles(&m->contact, m->friction, s->B, a);
    for (int i = 0; i < 5; ++i)
        z[i] = i < n ? (-s->v / omega) * cos(a[i]) - s->q * sin(a[i]) : 1.0;
}

/* The contactState an event leaves: as dynOutputs computes it, but a describing-function loop state
 * is taken a little ahead (LOOP_AHEAD rad) along the phase's motion: a root finder stops within its
 * tolerance on either side of a crossing, and the event is the change to the next state. */
#define LOOP_AHEAD 1e-8

static void holdContactState(FmiInstance *inst)
{
    BladeData *d = BLADE_DATA(inst);
    BladeMeData *me = ME_DATA(inst);
    const DynModel *m = &d->model;
    const DynState *s = &d->state;
    const double omega = m->omegaPerRpm * d->in[SOLVER_INPUT_SPEED][0];
    DynOutputs o;
    dynOutputs(m, s, d->in[SOLVER_INPUT_SPEED][0], &o);
    me->held = 1;
    me->contactState = o.contactState;
    if (m->friction != FrictionMacroslipTD && omega > 0.0 && dynContactOn(m, s) && s->df.regime == RegimeStickSlip) {
        double x[DYN_NX_MAX], f[DYN_NX_MAX], theta;
        loadX(s, x);
        (void)dynRhs(m, s, d->in[SOLVER_INPUT_AERO][0], d->in[SOLVER_INPUT_SPEED][0], x, f);
        /* d theta/dt has the sign of v^2 - q a (theta = atan2(-v/omega, q), omega > 0) */
        theta = atan2(-s->v / omega, s->q) + (s->v * s->v - s->q * f[1] >= 0.0 ? LOOP_AHEAD : -LOOP_AHEAD);
        me->contactState = (int32_t)contactLoopState(&m->contact, m->friction, s->B, theta);
    }
}

static FmiStatus eventIndicators(FmiInstance *inst, const char *fn, double z[])
{
    DynSwitchValue sv[DYN_MAX_SWITCHING];
    const int n = switching(BLADE_DATA(inst), sv);
    for (int i = 0; i < NZ; ++i) z[i] = 1.0;
    for (int i = 0; i < n; ++i) z[slotOf(sv[i].kind)] = sv[i].g;
    loopIndicators(BLADE_DATA(inst), z + ZLoop);
    unfresh(inst, sv, n);
    for (int i = 0; i < NZ; ++i) {
        if (!isfinite(z[i])) {
            fmiLogStatus(inst, FmiDiscard, "%s: event indicator %d = %g is not finite at t = %.17g s", fn, i, z[i],
                         inst->run.time);
            return FmiDiscard;
        }
    }
    return FmiOK;
}

/* The event iteration (model-notes s.6), the first triggered function in priority order applied,
 * then the list evaluated again. A function triggers when it is < 0, or when it is 0 and
 * decreasing (a root finder may stop exactly on 0, e.g. psi = 2 pi k). A fresh function (made
 * active or redefined by a switch and not seen > 0 since) triggers only when it is <= 0 and
 * decreasing: right after a switch it may start a rounding error below 0 with a slope away from 0
 * (e.g. the slip functions at a slip -> stick switch), which must not switch back; the
 * co-simulation integrator likewise clamps such a start to 0. */
static FmiStatus eventUpdate(FmiInstance *inst, const char *fn, int *statesChanged)
{
    BladeData *d = BLADE_DATA(inst);
    BladeMeMemory *mem = ME_MEMORY(inst);
    int events = 0;
    *statesChanged = 0;
    for (;;) {
        DynSwitchValue sv[DYN_MAX_SWITCHING], after[DYN_MAX_SWITCHING];
        const int n = switching(d, sv);
        DynSwitch ev = DynSwitchNone;
        DynEventKind kind = DynEventGateOn;
        unsigned before = 0;
        int na;
        unfresh(inst, sv, n);
        for (int i = 0; i < n; ++i) {
            const int fresh = (mem->fresh & BIT(sv[i].kind)) != 0;
            before |= BIT(sv[i].kind);
            if (ev == DynSwitchNone && sv[i].g <= 0.0 && (sv[i].hdg < 0.0 || (sv[i].g < 0.0 && !fresh)))
                ev = sv[i].kind;
        }
        if (ev == DynSwitchNone) break;
        if (++events > SOLVER_MAX_EVENTS_PER_STEP) {
            fmiLogStatus(inst, FmiError, "%s: more than %d switching events at t = %.17g s (chattering)", fn,
                         SOLVER_MAX_EVENTS_PER_STEP, inst->run.time);
            return FmiError;
        }
        if (dynApplyEvent(&d->model, &d->state, ev, &kind) != DynOk) {
            fmiLogStatus(inst, FmiError, "%s: the describing function failed at t = %.17g s for B = %g m", fn,
                         inst->run.time, d->state.B);
            return FmiError;
        }
        *statesChanged = 1;
        if (fmiLogEnabled(inst, LogEvents)) bladeLogEvent(inst, kind, inst->run.time, &d->state);
        /* fresh: the functions the switch made active, and the switched one (redefined) */
        mem->fresh |= BIT(ev);
        na = switching(d, after);
        for (int i = 0; i < na; ++i)
            if (!(before & BIT(after[i].kind))) mem->fresh |= BIT(after[i].kind);
    }
    holdContactState(inst); /* the discrete contactState of this event, until the next one */
    return bladeWarnFullStickOnce(inst, fn);
}

/* After a build: no contactState held yet; sensitivities are refused. */
static FmiStatus afterBuild(FmiInstance *inst, const char *fn, int initState)
{
    ME_DATA(inst)->held = 0;
    if (initState && BLADE_DATA(inst)->ipar[IparSensitivities]) {
        fmiLogStatus(inst, FmiError, "%s: sensitivities = true is for co-simulation only (a model-exchange "
                     "master integrates the states itself): accepted value false", fn);
        return FmiError;
    }
    return FmiOK;
}

/* contactState is discrete: after initialization it is the value taken at the last event
 * (fmi2NewDiscreteStates; event indicators at the loop phases), held in between, also where the
 * phase has moved past a crossing whose event is not yet handled. */
static void heldOutputs(FmiInstance *inst)
{
    if (fsmPreInit(inst->fsm)) return;
    if (!ME_DATA(inst)->held) holdContactState(inst); /* no event since a build or a restore */
    BLADE_MEMORY(inst)->out.contactState = ME_DATA(inst)->contactState;
}

static const FmiModelExchange BLADE_ME = {
    .nx = DYN_NX_MAX,
    .nz = NZ,
    .dataSize = sizeof(BladeMeData),
    .memorySize = sizeof(BladeMeMemory),
    .getStates = getStates,
    .setStates = setStates,
    .nominals = nominals,
    .derivatives = derivatives,
    .eventIndicators = eventIndicators,
    .eventUpdate = eventUpdate,
    .built = afterBuild,
    .outputs = heldOutputs,
};

const FmiModelExchange *const fmiModelExchange = &BLADE_ME;
