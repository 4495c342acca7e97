/* The ShroudContact model for the generic FMI layer: the macroslip contact between two
 * neighbouring shrouds A and B on their relative displacement u = q_A - q_B (docs/model.md s.8),
 * over physics/contact_element. Direct feedthrough: the forces at a communication point follow the
 * inputs set there (the element is first moved along the straight path from the state's u to the
 * new u, ceProject); over a step u(tau) is the difference of the two displacement polynomials,
 * each q + sum_j q^(j) tau^j / j! with the displacement's own derivatives if any is nonzero,
 * else q^(j) = (velocity)^(j-1) (a master that sets values only gets u linear in tau). Inputs not
 * set again go on as the polynomials of the step (the displacements from their end values). */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "fmi/log.h"
#include "fmi/model.h"
#include "models/ShroudContact/variables.h"
#include "physics/contact_element.h"

#define MAX_ORDER 8 /* highest input derivative order, as the blades' (model-notes s.1) */
/* the slots of par[] and ipar[] (RealParam, IntParam): variables.h, generated from model.toml */
enum { InQA = 0, InVA, InQB, InVB, InSpeed, NUM_INPUTS };

typedef struct {
    double par[PAR_NUM];
    int32_t ipar[IPAR_NUM];
    double in[NUM_INPUTS][MAX_ORDER + 1]; /* input values and derivatives [unit/s^j] */
    CeState state;
    CeModel model; /* derived */
} ScData;

typedef struct {
    CeOutputs out;
    double u; /* relative displacement of the current get call [m] */
    double E; /* dissipated energy at the current inputs [J] */
} ScMemory;

enum { OutForceA = 0, OutForceB, OutNormal, OutFriction, OutEnergy, OutU, OutState };

#define AT(member) (long)offsetof(ScData, member)
#define PAR(k) AT(par[k])
#define IPAR(k) AT(ipar[k])
#define INPUT(k) AT(in[k][0])
#define DATA(inst) ((ScData *)(inst)->data)

/* Sorted by value reference: generated from model.toml (the contact parameters keep ShroudedBlade's
 * value references). */
static const VarInfo VARS[] = {
#include "models/ShroudContact/variables.inc"
};

#define COUNT(member) (int)(sizeof(((ScData *)0)->member) / sizeof(((ScData *)0)->member[0]))
#define F64(member) {AT(member), FieldF64, 1}
#define I32(member) {AT(member), FieldI32, 1}

static const StateField FIELDS[] = {
    {AT(par), FieldF64, COUNT(par)},
    {AT(in), FieldF64, COUNT(in) * COUNT(in[0])},
    F64(state.w), F64(state.E), F64(state.uRef),
    {AT(ipar), FieldI32, COUNT(ipar)},
    I32(state.mode), I32(state.side), I32(state.slipDir),
};
/* Versions: 3 the parameter slots in the spec's order (frictionForce's start before
 * dissipatedEnergy's); 2 the start value of frictionForce joined the parameters. Older versions are
 * refused. */
#define STATE_VERSION 3

/* The displacement polynomial of one side (see the head comment). */
static void sidePoly(const ScData *d, int q, int v, CePoly *p)
{
    int own = 0;
    double fact = 1.0;
    memset(p, 0, sizeof *p);
    for (int j = 1; j <= MAX_ORDER; ++j) own |= d->in[q][j] != 0.0;
    p->c[0] = d->in[q][0];
    for (int j = 1; j <= CE_MAX_DEG; ++j) {
        fact *= (double)j;
        p->c[j] = (own ? (j <= MAX_ORDER ? d->in[q][j] : 0.0) : d->in[v][j - 1]) / fact;
    }
    p->deg = CE_MAX_DEG;
    while (p->deg > 0 && p->c[p->deg] == 0.0) --p->deg;
}

/* u(tau) = q_A(tau) - q_B(tau) and the rotor speed polynomial. */
static void stepPolys(const ScData *d, CePoly *u, CePoly *n)
{
    CePoly b;
    double fact = 1.0;
    sidePoly(d, InQA, InVA, u);
    sidePoly(d, InQB, InVB, &b);
    for (int j = 0; j <= CE_MAX_DEG; ++j) u->c[j] -= b.c[j];
    if (b.deg > u->deg) u->deg = b.deg;
    while (u->deg > 0 && u->c[u->deg] == 0.0) --u->deg;
    memset(n, 0, sizeof *n);
    for (int j = 0; j <= MAX_ORDER; ++j) {
        if (j > 0) fact *= (double)j;
        n->c[j] = d->in[InSpeed][j] / fact;
        if (n->c[j] != 0.0) n->deg = j;
    }
}

/* The start state at u0: ceInit (the spring unloaded), then, for the Jenkins element in contact,
 * the slider put where the friction force is the start value of frictionForce:
 * F_f = kd (sin(g) u - w) in stick, so w = sin(g) u0 - F0 / kd. F0 = 0 leaves ceInit's state. */
static void startState(const ScData *d, CeState *s, double u0)
{
    const double F0 = d->par[ParF0];
    ceInit(&d->model, s, u0, d->par[ParE0]);
    if (F0 != 0.0 && d->model.friction == FrictionMacroslipTD && s->mode == ContactStick) {
        s->w = d->model.sinG * u0 - F0 / d->model.kd;
        s->slipDir = F0 > 0.0 ? 1 : -1; /* the direction it slips in if it starts on the cone */
    }
}

/* The start value of frictionForce must fit the start state: 0 for the describing-function models
 * and for an open contact (|u0| <= d), inside the friction cone |F0| <= mu kn cos(gamma) (|u0| - d)
 * (relative 1e-12) otherwise. Cross-field, so checked at the end of initialization. */
static FmiStatus checkStartForce(FmiInstance *inst, const char *fn, double u0)
{
    const ScData *d = DATA(inst);
    const double F0 = d->par[ParF0], dd = d->model.contact.d;
    double L;
    if (F0 == 0.0) return FmiOK;
    if (d->model.friction != FrictionMacroslipTD) {
        fmiLogStatus(inst, FmiError,
                     "%s: frictionForce = %.15g N: its start value applies only to frictionModel 3 (the "
                     "time-domain Jenkins element), here frictionModel = %d: accepted range [0, 0] N",
                     fn, F0, (int)d->ipar[IparFrictionModel]);
        return FmiError;
    }
    if (!(fabs(u0) > dd)) {
        fmiLogStatus(inst, FmiError,
                     "%s: frictionForce = %.15g N, but the contact is open at the start "
                     "u = displacementA - displacementB = %.15g m (|u| <= d = %g m), where the spring is "
                     "unloaded: accepted range [0, 0] N", fn, F0, u0, dd);
        return FmiError;
    }
    L = d->model.muKnCos * (fabs(u0) - dd);
    if (!(fabs(F0) <= L * (1.0 + 1e-12))) {
        fmiLogStatus(inst, FmiError,
                     "%s: frictionForce = %.15g N is outside the friction cone: accepted range "
                     "[-%.15g, %.15g] N, from u = displacementA - displacementB = %.15g m (L = mu kn "
                     "cos(gamma) (|u| - d), mu = %g, kn = %g N/m, gamma = %g rad, d = %g m)", fn, F0, L, L,
                     u0, d->par[ParMu], d->par[ParKn], d->par[ParGamma], dd);
        return FmiError;
    }
    return FmiOK;
}

static FmiStatus build(FmiInstance *inst, const char *fn, int initState)
{
    ScData *d = DATA(inst);
    const double *p = d->par;
    ContactParams cp;
    int rc;
    cp.kn = p[ParKn];
    cp.kdRatio = p[ParKdRatio];
    cp.mu = p[ParMu];
    cp.gamma = p[ParGamma];
    cp.d = p[ParD];
    rc = ceBuild(&d->model, &cp, (FrictionModel)d->ipar[IparFrictionModel], (Projection)d->ipar[IparProjection],
                 d->ipar[IparGating] != 0, p[ParB], d->ipar[IparEngineOrder]);
    if (rc != 0) {
        fmiLogStatus(inst, FmiError,
                     "%s: the contact parameters kn = %g N/m, kdRatio = %g, mu = %g, gamma = %g rad, d = %g m, "
                     "B = %g m (frictionModel %d) are not usable together%s", fn, cp.kn, cp.kdRatio, cp.mu,
                     cp.gamma, cp.d, p[ParB], (int)d->ipar[IparFrictionModel],
                     rc == 2 ? ": the describing function (eq. 7-13) failed at B" : "");
        return FmiError;
    }
    if (initState) {
        const double u0 = d->in[InQA][0] - d->in[InQB][0];
        if (checkStartForce(inst, fn, u0) != FmiOK) return FmiError;
        startState(d, &d->state, u0);
    }
    return FmiOK;
}

/* The outputs at the inputs set now: the element moved to them (ceProject) in a copy of the state;
 * before the end of initialization, the start state at them. */
static void outputs(FmiInstance *inst)
{
    const ScData *d = DATA(inst);
    ScMemory *o = (ScMemory *)inst->memory;
    CeState s = d->state;
    CePoly u, n;
    stepPolys(d, &u, &n);
    if (inst->run.initialized) (void)ceProject(&d->model, &s, u.c[0]);
    else startState(d, &s, u.c[0]);
    ceOutputs(&d->model, &s, u.c[0], u.c[1], n.c[0], &o->out);
    o->u = u.c[0];
    o->E = s.E;
}

static double output(const FmiInstance *inst, int id)
{
    const ScMemory *o = (const ScMemory *)inst->memory;
    switch (id) {
    case OutForceA: return 0.0 - o->out.contactForce; /* exactly opposite, never -0.0 */
    case OutForceB: return o->out.contactForce;
    case OutNormal: return o->out.normalForce;
    case OutFriction: return o->out.frictionForce;
    case OutEnergy: return o->E;
    case OutU: return o->u;
    default: return (double)o->out.contactState;
    }
}

static const char *failure(CeStatus st)
{
    switch (st) {
    case CeChattering: return "more than 1000 contact events in one step (chattering)";
    case CeOmegaZero: return "rotorSpeed <= 0 while the describing-function contact acts (f_c needs omega > 0)";
    default: return "the element state became non-finite";
    }
}

/* Shifts input i's Taylor polynomial to tau = h (an input the master does not set again goes on). */
static void shiftInput(double c[MAX_ORDER + 1], double h)
{
    double a[MAX_ORDER + 1], fact = 1.0;
    int top = 0;
    for (int j = 0; j <= MAX_ORDER; ++j) {
        if (j > 0) fact *= (double)j;
        a[j] = c[j] / fact;
        if (a[j] != 0.0) top = j;
    }
    for (int j = 0; j < top; ++j)
        for (int k = top - 1; k >= j; --k) a[k] += h * a[k + 1];
    fact = 1.0;
    for (int j = 0; j <= MAX_ORDER; ++j) {
        if (j > 0) fact *= (double)j;
        c[j] = j <= top ? a[j] * fact : 0.0;
    }
}

static FmiStatus doStep(FmiInstance *inst, const char *fn, double tc, double h)
{
    ScData *d = DATA(inst);
    const CeState backup = d->state;
    CePoly u, n;
    CeStatus st;
    stepPolys(d, &u, &n);
    if (d->model.friction != FrictionMacroslipTD) {
        const double n1 = cePolyAt(&n, h);
        if (!(n.c[0] >= 0.0 && n.c[0] <= max_rotorSpeed && n1 >= 0.0 && n1 <= max_rotorSpeed)) {
            fmiLogStatus(inst, FmiDiscard, "%s: rotorSpeed = %g rpm at t = %.17g s and %g rpm at the step end: "
                         "it must stay in [0, %g] rpm; the step is refused, the state is unchanged", fn, n.c[0],
                         tc, n1, max_rotorSpeed);
            return FmiDiscard;
        }
    }
    st = ceProject(&d->model, &d->state, u.c[0]);
    if (st == CeOk) st = ceAdvance(&d->model, &d->state, &u, &n, h, NULL);
    if (st != CeOk) {
        d->state = backup;
        fmiLogStatus(inst, FmiDiscard, "%s: %s in the step from t = %.17g s; the step is discarded and the "
                     "state restored", fn, failure(st), tc);
        return FmiDiscard;
    }
    /* inputs carried to the next point: each as the polynomial the step used, so a master that
     * does not set them again reads the forces at the step's end state (a displacement without
     * derivatives of its own moved along its velocity: it takes the value reached) */
    {
        CePoly pa, pb;
        sidePoly(d, InQA, InVA, &pa);
        sidePoly(d, InQB, InVB, &pb);
        for (int i = 0; i < NUM_INPUTS; ++i) shiftInput(d->in[i], h);
        d->in[InQA][0] = cePolyAt(&pa, h);
        d->in[InQB][0] = cePolyAt(&pb, h);
    }
    return FmiOK;
}

static int validData(FmiInstance *inst, const char *fn, const void *data, int initialized)
{
    const CeState *s = &((const ScData *)data)->state;
    if (initialized && (!isfinite(s->w) || !isfinite(s->E) || !isfinite(s->uRef) || s->mode < 0 ||
                        s->mode > 2 || (s->side != 1 && s->side != -1) || (s->slipDir != 1 && s->slipDir != -1))) {
        fmiLogStatus(inst, FmiError, "%s: invalid contact state in the data", fn);
        return 0;
    }
    return 1;
}

const FmiModel fmiModel = {
    .name = MODEL_NAME,
    .guid = MODEL_GUID,
    .vars = VARS,
    .nVars = (int)(sizeof VARS / sizeof VARS[0]),
    .maxInputOrder = MAX_ORDER,
    .dataSize = sizeof(ScData),
    .memorySize = sizeof(ScMemory),
    .canGetAndSetState = 1,
    .stateVersion = STATE_VERSION,
    .fields = FIELDS,
    .nFields = (int)(sizeof FIELDS / sizeof FIELDS[0]),
    .build = build,
    .outputs = outputs,
    .output = output,
    .doStep = doStep,
    .validData = validData,
};

/* co-simulation only */
const FmiModelExchange *const fmiModelExchange = NULL;
