/* sb_importer: a small FMI 2.0 co-simulation importer that drives the raw C API of the
 * ShroudedBlade FMU binary (dlopen), built together with the FMU under AddressSanitizer and
 * UndefinedBehaviorSanitizer (tests/c/CMakeLists.txt, option SB_SANITIZE) and run by
 * tests/test_fmu_sanitizers.py and tests/test_fmu_leaks.py.
 *
 *   sb_importer <binary.so> full                 full runs (3000 steps, states, reset) + error paths
 *   sb_importer <binary.so> leaks <nInst> <nReset>  instantiate/free and reset cycles
 *
 * Every check that fails prints "FAIL: ..." to stderr; the exit code is 0 only if all passed.
 * The logger is a real variadic FMI logger (vsnprintf) that records what the FMU says and checks
 * every call: instance name, category known and enabled, status valid, environment pointer. */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include <float.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

/* value references (modelDescription.xml) */
enum {
    vrEI = 1, vrRho = 2, vrA = 3, vrL = 4, vrC = 5, vrM0 = 6, vrKn = 7, vrKdRatio = 8, vrMu = 9,
    vrGamma = 10, vrD = 11, vrB = 12, vrMaxStep = 13, vrFrictionModel = 20, vrFormulation = 21,
    vrProjection = 22, vrAmplitudeMode = 23, vrEngineOrder = 24, vrGating = 30, vrAeroLoad = 40,
    vrRotorSpeed = 41, vrFw0 = 14
};
static const fmi2ValueReference realOutputs[] = {50, 51, 52, 53, 54, 55, 56, 57, 58, 59, 62};
static const fmi2ValueReference intOutputs[] = {60, 61};
#define N_REAL_OUT 11
#define N_INT_OUT 2
#define N_OUT (N_REAL_OUT + N_INT_OUT)

static const char *const categories[] = {"logEvents", "logStatusWarning", "logStatusDiscard",
                                         "logStatusError", "logStatusFatal", "logAll", "logCalls"};
#define N_CATEGORIES 7
#define CATEGORY_LOG_ALL 5

static const char *guid = NULL;   /* read from the command line (default below) */
static const char *resourceUri = "file:///tmp/sb%20importer/resources";

/* ---------------------------------------------------------------------------------------------
 * checks */

static long nChecks = 0;
static long nFailures = 0;

static void check(int ok, const char *what, const char *detail) {
    ++nChecks;
    if (!ok) {
        ++nFailures;
        fprintf(stderr, "FAIL: %s%s%s\n", what, detail ? ": " : "", detail ? detail : "");
    }
}

static int isRefusal(fmi2Status s) { return s == fmi2Error || s == fmi2Discard; }
static int isValidStatus(int s) { return s >= fmi2OK && s <= fmi2Pending; }

static const char *statusName(int s) {
    static const char *const names[] = {"OK", "Warning", "Discard", "Error", "Fatal", "Pending"};
    return isValidStatus(s) ? names[s] : "INVALID";
}

/* ---------------------------------------------------------------------------------------------
 * the recording logger */

#define LOG_MAGIC 0x10661066u
#define LOG_TEXT 65536

typedef struct {
    unsigned magic;
    long calls;                     /* logger calls since creation */
    long badCalls;                  /* calls that broke a logger rule */
    int allEnabled;                 /* mirror of the FMU's enabled categories */
    int enabled[N_CATEGORIES];
    char text[LOG_TEXT];            /* messages since the last logClear, newline separated */
    size_t textLen;
    char lastBad[512];              /* description of the last broken rule */
} LogEnv;

static void logClear(LogEnv *env) {
    env->text[0] = '\0';
    env->textLen = 0;
}

static int categoryIndex(const char *category) {
    int i;
    if (category == NULL) return -1;
    for (i = 0; i < N_CATEGORIES; ++i)
        if (strcmp(category, categories[i]) == 0) return i;
    return -1;
}

static void logger(fmi2ComponentEnvironment componentEnvironment, fmi2String instanceName,
                   fmi2Status status, fmi2String category, fmi2String message, ...) {
    LogEnv *env = (LogEnv *)componentEnvironment;
    char buf[4096];
    int cat;
    va_list args;
    if (env == NULL || env->magic != LOG_MAGIC) {
        ++nChecks;
        ++nFailures;
        fprintf(stderr, "FAIL: logger called with a foreign componentEnvironment %p\n",
                (void *)env);
        return;
    }
    ++env->calls;
    buf[0] = '\0';
    if (message != NULL) {
        va_start(args, message);
        vsnprintf(buf, sizeof buf, message, args);
        va_end(args);
    }
    cat = categoryIndex(category);
    if (instanceName == NULL || message == NULL || !isValidStatus((int)status) || cat < 0 ||
        !(env->allEnabled || env->enabled[cat] || env->enabled[CATEGORY_LOG_ALL])) {
        ++env->badCalls;
        snprintf(env->lastBad, sizeof env->lastBad, "name=%s status=%d category=%s message=%.300s",
                 instanceName ? instanceName : "(NULL)", (int)status,
                 category ? category : "(NULL)", message ? buf : "(NULL)");
    }
    if (env->textLen + strlen(buf) + 2 < LOG_TEXT) {
        memcpy(env->text + env->textLen, buf, strlen(buf));
        env->textLen += strlen(buf);
        env->text[env->textLen++] = '\n';
        env->text[env->textLen] = '\0';
    }
}

/* ---------------------------------------------------------------------------------------------
 * the API */

typedef struct {
    void *handle;
    fmi2GetTypesPlatformTYPE *getTypesPlatform;
    fmi2GetVersionTYPE *getVersion;
    fmi2SetDebugLoggingTYPE *setDebugLogging;
    fmi2InstantiateTYPE *instantiate;
    fmi2FreeInstanceTYPE *freeInstance;
    fmi2SetupExperimentTYPE *setupExperiment;
    fmi2EnterInitializationModeTYPE *enterInitializationMode;
    fmi2ExitInitializationModeTYPE *exitInitializationMode;
    fmi2TerminateTYPE *terminate;
    fmi2ResetTYPE *reset;
    fmi2GetRealTYPE *getReal;
    fmi2GetIntegerTYPE *getInteger;
    fmi2GetBooleanTYPE *getBoolean;
    fmi2GetStringTYPE *getString;
    fmi2SetRealTYPE *setReal;
    fmi2SetIntegerTYPE *setInteger;
    fmi2SetBooleanTYPE *setBoolean;
    fmi2SetStringTYPE *setString;
    fmi2GetFMUstateTYPE *getFMUstate;
    fmi2SetFMUstateTYPE *setFMUstate;
    fmi2FreeFMUstateTYPE *freeFMUstate;
    fmi2SerializedFMUstateSizeTYPE *serializedFMUstateSize;
    fmi2SerializeFMUstateTYPE *serializeFMUstate;
    fmi2DeSerializeFMUstateTYPE *deSerializeFMUstate;
    fmi2GetDirectionalDerivativeTYPE *getDirectionalDerivative;
    fmi2SetRealInputDerivativesTYPE *setRealInputDerivatives;
    fmi2GetRealOutputDerivativesTYPE *getRealOutputDerivatives;
    fmi2DoStepTYPE *doStep;
    fmi2CancelStepTYPE *cancelStep;
    fmi2GetStatusTYPE *getStatus;
    fmi2GetRealStatusTYPE *getRealStatus;
    fmi2GetIntegerStatusTYPE *getIntegerStatus;
    fmi2GetBooleanStatusTYPE *getBooleanStatus;
    fmi2GetStringStatusTYPE *getStringStatus;
} Api;

static int loadSymbol(void *handle, const char *name, void *dst) {
    void *p = dlsym(handle, name);
    memcpy(dst, &p, sizeof p); /* object -> function pointer without a pedantic cast */
    if (p == NULL) fprintf(stderr, "FAIL: %s is not exported\n", name);
    return p != NULL;
}

static int loadApi(const char *path, Api *api) {
    int ok = 1;
    memset(api, 0, sizeof *api);
    api->handle = dlopen(path, RTLD_NOW | RTLD_LOCAL);
    if (api->handle == NULL) {
        fprintf(stderr, "FAIL: dlopen(%s): %s\n", path, dlerror());
        return 0;
    }
#define LOAD(member, name) ok &= loadSymbol(api->handle, name, &api->member)
    LOAD(getTypesPlatform, "fmi2GetTypesPlatform");
    LOAD(getVersion, "fmi2GetVersion");
    LOAD(setDebugLogging, "fmi2SetDebugLogging");
    LOAD(instantiate, "fmi2Instantiate");
    LOAD(freeInstance, "fmi2FreeInstance");
    LOAD(setupExperiment, "fmi2SetupExperiment");
    LOAD(enterInitializationMode, "fmi2EnterInitializationMode");
    LOAD(exitInitializationMode, "fmi2ExitInitializationMode");
    LOAD(terminate, "fmi2Terminate");
    LOAD(reset, "fmi2Reset");
    LOAD(getReal, "fmi2GetReal");
    LOAD(getInteger, "fmi2GetInteger");
    LOAD(getBoolean, "fmi2GetBoolean");
    LOAD(getString, "fmi2GetString");
    LOAD(setReal, "fmi2SetReal");
    LOAD(setInteger, "fmi2SetInteger");
    LOAD(setBoolean, "fmi2SetBoolean");
    LOAD(setString, "fmi2SetString");
    LOAD(getFMUstate, "fmi2GetFMUstate");
    LOAD(setFMUstate, "fmi2SetFMUstate");
    LOAD(freeFMUstate, "fmi2FreeFMUstate");
    LOAD(serializedFMUstateSize, "fmi2SerializedFMUstateSize");
    LOAD(serializeFMUstate, "fmi2SerializeFMUstate");
    LOAD(deSerializeFMUstate, "fmi2DeSerializeFMUstate");
    LOAD(getDirectionalDerivative, "fmi2GetDirectionalDerivative");
    LOAD(setRealInputDerivatives, "fmi2SetRealInputDerivatives");
    LOAD(getRealOutputDerivatives, "fmi2GetRealOutputDerivatives");
    LOAD(doStep, "fmi2DoStep");
    LOAD(cancelStep, "fmi2CancelStep");
    LOAD(getStatus, "fmi2GetStatus");
    LOAD(getRealStatus, "fmi2GetRealStatus");
    LOAD(getIntegerStatus, "fmi2GetIntegerStatus");
    LOAD(getBooleanStatus, "fmi2GetBooleanStatus");
    LOAD(getStringStatus, "fmi2GetStringStatus");
#undef LOAD
    return ok;
}

/* ---------------------------------------------------------------------------------------------
 * instances */

typedef struct {
    fmi2Component c;
    LogEnv *env;
    fmi2CallbackFunctions *callbacks;
} Inst;

static Inst newInstance(const Api *api, const char *name, fmi2Boolean loggingOn) {
    Inst in;
    in.env = (LogEnv *)calloc(1, sizeof *in.env);
    in.callbacks = (fmi2CallbackFunctions *)calloc(1, sizeof *in.callbacks);
    in.env->magic = LOG_MAGIC;
    in.env->allEnabled = loggingOn ? 1 : 0;
    in.callbacks->logger = logger;
    in.callbacks->allocateMemory = calloc;
    in.callbacks->freeMemory = free;
    in.callbacks->stepFinished = NULL;
    in.callbacks->componentEnvironment = in.env;
    in.c = api->instantiate(name, fmi2CoSimulation, guid, resourceUri, in.callbacks, fmi2False,
                            loggingOn);
    return in;
}

static void freeInst(const Api *api, Inst *in) {
    if (in->c != NULL) api->freeInstance(in->c);
    in->c = NULL;
    if (in->env != NULL && in->env->badCalls > 0)
        check(0, "logger rules (name, category known and enabled, status, message)",
              in->env->lastBad);
    free(in->env);
    free(in->callbacks);
    in->env = NULL;
    in->callbacks = NULL;
}

typedef struct {
    int frictionModel;
    int amplitudeMode;
    double d;           /* gap [m] */
    double maxStep;     /* [s] */
} RunParams;

static fmi2Status setParams(const Api *api, fmi2Component c, const RunParams *p) {
    /* Fw0 = 0: this importer feeds aeroLoad itself (setInputs), the FMU's built-in load is off */
    fmi2ValueReference rv[3] = {vrD, vrMaxStep, vrFw0};
    fmi2Real rx[3];
    fmi2ValueReference iv[2] = {vrFrictionModel, vrAmplitudeMode};
    fmi2Integer ix[2];
    fmi2ValueReference bv[1] = {vrGating};
    fmi2Boolean bx[1] = {fmi2True};
    fmi2Status s1, s2, s3;
    rx[0] = p->d;
    rx[1] = p->maxStep;
    rx[2] = 0.0;
    ix[0] = p->frictionModel;
    ix[1] = p->amplitudeMode;
    s1 = api->setReal(c, rv, 3, rx);
    s2 = api->setInteger(c, iv, 2, ix);
    s3 = api->setBoolean(c, bv, 1, bx);
    return s1 > s2 ? (s1 > s3 ? s1 : s3) : (s2 > s3 ? s2 : s3);
}

static fmi2Status initialize(const Api *api, fmi2Component c, const RunParams *p) {
    fmi2Status s = api->setupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    if (s != fmi2OK) return s;
    if ((s = setParams(api, c, p)) != fmi2OK) return s;
    if ((s = api->enterInitializationMode(c)) != fmi2OK) return s;
    return api->exitInitializationMode(c);
}

/* Sets the inputs of step k (aeroLoad = Fw0 sin(omega t) with derivatives 1..8, rotorSpeed
 * constant) and does the step; fills out[N_OUT]. */
static fmi2Status step(const Api *api, fmi2Component c, int k, double h, double out[N_OUT]) {
    const double Fw0 = 100.0, speed = 5000.0;
    const double omega = 3.0 * 2.0 * 3.14159265358979323846 * speed / 60.0;
    double t = k * h;
    fmi2ValueReference vr[2] = {vrAeroLoad, vrRotorSpeed};
    fmi2Real x[2];
    fmi2ValueReference dvr[8];
    fmi2Integer order[8];
    fmi2Real dx[8];
    fmi2Integer io[N_INT_OUT];
    fmi2Status s;
    int j;
    x[0] = Fw0 * sin(omega * t);
    x[1] = speed;
    for (j = 0; j < 8; ++j) {
        dvr[j] = vrAeroLoad;
        order[j] = j + 1;
        dx[j] = Fw0 * pow(omega, j + 1) * sin(omega * t + (j + 1) * 1.5707963267948966);
    }
    if ((s = api->setReal(c, vr, 2, x)) != fmi2OK) return s;
    if ((s = api->setRealInputDerivatives(c, dvr, 8, order, dx)) != fmi2OK) return s;
    if ((s = api->doStep(c, t, h, fmi2True)) != fmi2OK) return s;
    if ((s = api->getReal(c, realOutputs, N_REAL_OUT, out)) != fmi2OK) return s;
    if ((s = api->getInteger(c, intOutputs, N_INT_OUT, io)) != fmi2OK) return s;
    for (j = 0; j < N_INT_OUT; ++j) out[N_REAL_OUT + j] = io[j];
    return fmi2OK;
}

static int runSteps(const Api *api, fmi2Component c, int k0, int k1, double h, double *rows) {
    int k, j;
    for (k = k0; k < k1; ++k) {
        double *row = rows + (size_t)(k - k0) * N_OUT;
        fmi2Status s = step(api, c, k, h, row);
        if (s != fmi2OK) {
            char d[128];
            snprintf(d, sizeof d, "step %d returned %s", k, statusName(s));
            check(0, "run step", d);
            return 0;
        }
        for (j = 0; j < N_OUT; ++j)
            if (!isfinite(row[j])) {
                char d[128];
                snprintf(d, sizeof d, "step %d output %d = %g", k, j, row[j]);
                check(0, "finite outputs", d);
                return 0;
            }
    }
    return 1;
}

static void checkSame(const double *a, const double *b, size_t n, const char *what) {
    check(memcmp(a, b, n * sizeof(double)) == 0, what, "not bit-identical");
}

/* ---------------------------------------------------------------------------------------------
 * full runs: 3000 steps, state get/set, serialize/deserialize into a new instance, reset, rerun */

static void fullRun(const Api *api, const RunParams *p) {
    const int n = 3000, k1 = 1000, k2 = 2000;
    const double h = 1e-4;
    double *first = (double *)calloc((size_t)n * N_OUT, sizeof(double));
    double *again = (double *)calloc((size_t)n * N_OUT, sizeof(double));
    Inst a = newInstance(api, "fullRun", fmi2True), b;
    fmi2FMUstate s1 = NULL, s2 = NULL;
    size_t size = 0;
    fmi2Byte *blob = NULL;
    fmi2Real lastTime = -1.0;
    check(a.c != NULL, "instantiate", NULL);
    if (a.c == NULL) goto done;
    check(api->setDebugLogging(a.c, fmi2True, 0, NULL) == fmi2OK, "setDebugLogging all", NULL);
    check(initialize(api, a.c, p) == fmi2OK, "initialize", NULL);
    if (!runSteps(api, a.c, 0, k1, h, first)) goto done;
    check(api->getFMUstate(a.c, &s1) == fmi2OK && s1 != NULL, "getFMUstate", NULL);
    check(api->serializedFMUstateSize(a.c, s1, &size) == fmi2OK && size > 0, "state size", NULL);
    blob = (fmi2Byte *)malloc(size);
    check(api->serializeFMUstate(a.c, s1, blob, size) == fmi2OK, "serialize", NULL);
    if (!runSteps(api, a.c, k1, n, h, first + (size_t)k1 * N_OUT)) goto done;
    check(api->getRealStatus(a.c, fmi2LastSuccessfulTime, &lastTime) == fmi2OK &&
              fabs(lastTime - n * h) <= 1e-12, "lastSuccessfulTime", NULL);
    /* back to step k1 with fmi2SetFMUstate */
    check(api->setFMUstate(a.c, s1) == fmi2OK, "setFMUstate", NULL);
    if (runSteps(api, a.c, k1, k2, h, again))
        checkSame(first + (size_t)k1 * N_OUT, again, (size_t)(k2 - k1) * N_OUT,
                  "continuation after setFMUstate");
    /* the serialized state in a fresh instance (never initialized) */
    b = newInstance(api, "fullRunCopy", fmi2True);
    check(b.c != NULL, "instantiate copy", NULL);
    if (b.c != NULL) {
        check(api->deSerializeFMUstate(b.c, blob, size, &s2) == fmi2OK && s2 != NULL,
              "deSerializeFMUstate", NULL);
        check(api->setFMUstate(b.c, s2) == fmi2OK, "setFMUstate from blob", NULL);
        if (runSteps(api, b.c, k1, n, h, again))
            checkSame(first + (size_t)k1 * N_OUT, again, (size_t)(n - k1) * N_OUT,
                      "continuation after deserialization in a new instance");
        check(api->freeFMUstate(b.c, &s2) == fmi2OK && s2 == NULL, "freeFMUstate copy", NULL);
    }
    freeInst(api, &b);
    check(api->freeFMUstate(a.c, &s1) == fmi2OK && s1 == NULL, "freeFMUstate", NULL);
    /* terminate, reset, rerun from scratch: bit-identical */
    check(api->terminate(a.c) == fmi2OK, "terminate", NULL);
    check(api->reset(a.c) == fmi2OK, "reset", NULL);
    check(initialize(api, a.c, p) == fmi2OK, "initialize after reset", NULL);
    if (runSteps(api, a.c, 0, n, h, again))
        checkSame(first, again, (size_t)n * N_OUT, "rerun after reset");
done:
    if (s1 != NULL && a.c != NULL) api->freeFMUstate(a.c, &s1);
    freeInst(api, &a);
    free(blob);
    free(first);
    free(again);
}

/* ---------------------------------------------------------------------------------------------
 * error paths: each case on a fresh instance; the answer must be a refusal (Error or Discard),
 * never a crash, and a message naming the culprit must be logged */

static const RunParams defaults = {1, 2, 3e-5, 1e-5};

static Inst readyInstance(const Api *api, const char *name) {
    Inst in = newInstance(api, name, fmi2True);
    if (in.c != NULL && initialize(api, in.c, &defaults) != fmi2OK) check(0, "initialize", name);
    if (in.env != NULL) logClear(in.env);
    return in;
}

static void expectLogged(const Inst *in, const char *needle, const char *what) {
    char d[600];
    if (in->env == NULL) return;
    snprintf(d, sizeof d, "log does not mention '%s'; log: %.400s", needle, in->env->text);
    check(strstr(in->env->text, needle) != NULL, what, d);
}

static void badReal(const Api *api, const char *name, fmi2ValueReference vr, double value) {
    Inst in = newInstance(api, name, fmi2True);
    char what[160];
    fmi2Status s;
    snprintf(what, sizeof what, "invalid parameter %s = %g refused", name, value);
    if (in.c == NULL) {
        check(0, what, "instantiate failed");
        return;
    }
    api->setupExperiment(in.c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    s = api->setReal(in.c, &vr, 1, &value);
    if (!isRefusal(s)) {
        s = api->enterInitializationMode(in.c);
        if (!isRefusal(s)) s = api->exitInitializationMode(in.c);
    }
    check(isRefusal(s), what, statusName(s));
    expectLogged(&in, name, what);
    if (!isRefusal(s)) {
        double out[N_OUT];
        check(isRefusal(step(api, in.c, 0, 1e-4, out)), what, "a step was accepted");
    }
    freeInst(api, &in);
}

static void badInteger(const Api *api, const char *name, fmi2ValueReference vr, int value) {
    Inst in = newInstance(api, name, fmi2True);
    char what[160];
    fmi2Status s;
    snprintf(what, sizeof what, "invalid parameter %s = %d refused", name, value);
    if (in.c == NULL) {
        check(0, what, "instantiate failed");
        return;
    }
    s = api->setInteger(in.c, &vr, 1, &value);
    if (!isRefusal(s)) {
        s = api->enterInitializationMode(in.c);
        if (!isRefusal(s)) s = api->exitInitializationMode(in.c);
    }
    check(isRefusal(s), what, statusName(s));
    expectLogged(&in, name, what);
    freeInst(api, &in);
}

static void invalidParameters(const Api *api) {
    const double nan = NAN, inf = INFINITY;
    const struct { const char *name; fmi2ValueReference vr; } positive[] = {
        {"EI", vrEI}, {"rho", vrRho}, {"A", vrA}, {"l", vrL}, {"kn", vrKn},
        {"kdRatio", vrKdRatio}, {"B", vrB}};
    const struct { const char *name; fmi2ValueReference vr; } nonNegative[] = {
        {"c", vrC}, {"m0", vrM0}, {"d", vrD}, {"mu", vrMu}};
    const struct { const char *name; fmi2ValueReference vr; } reals[] = {
        {"EI", vrEI}, {"rho", vrRho}, {"A", vrA}, {"l", vrL}, {"c", vrC}, {"m0", vrM0},
        {"kn", vrKn}, {"kdRatio", vrKdRatio}, {"mu", vrMu}, {"gamma", vrGamma}, {"d", vrD},
        {"B", vrB}, {"maxStep", vrMaxStep}};
    size_t i;
    for (i = 0; i < sizeof positive / sizeof positive[0]; ++i) {
        badReal(api, positive[i].name, positive[i].vr, 0.0);
        badReal(api, positive[i].name, positive[i].vr, -1.0);
    }
    for (i = 0; i < sizeof nonNegative / sizeof nonNegative[0]; ++i)
        badReal(api, nonNegative[i].name, nonNegative[i].vr, -1e-3);
    badReal(api, "gamma", vrGamma, 0.0);
    badReal(api, "gamma", vrGamma, -0.5);
    badReal(api, "gamma", vrGamma, 1.5707963267948966);
    badReal(api, "gamma", vrGamma, 2.0);
    badReal(api, "maxStep", vrMaxStep, 0.0);
    badReal(api, "maxStep", vrMaxStep, -1e-5);
    badReal(api, "maxStep", vrMaxStep, 1e-9);
    badReal(api, "maxStep", vrMaxStep, 2e-3);
    for (i = 0; i < sizeof reals / sizeof reals[0]; ++i) {
        badReal(api, reals[i].name, reals[i].vr, nan);
        badReal(api, reals[i].name, reals[i].vr, inf);
        badReal(api, reals[i].name, reals[i].vr, -inf);
    }
    badInteger(api, "frictionModel", vrFrictionModel, 0);
    badInteger(api, "frictionModel", vrFrictionModel, 4);
    badInteger(api, "formulation", vrFormulation, 0);
    badInteger(api, "formulation", vrFormulation, 3);
    badInteger(api, "projection", vrProjection, 0);
    badInteger(api, "projection", vrProjection, 3);
    badInteger(api, "amplitudeMode", vrAmplitudeMode, 0);
    badInteger(api, "amplitudeMode", vrAmplitudeMode, 3);
    badInteger(api, "engineOrder", vrEngineOrder, 0);
    badInteger(api, "engineOrder", vrEngineOrder, 101);
    badInteger(api, "engineOrder", vrEngineOrder, -2147483647 - 1);
}

static void invalidInputs(const Api *api) {
    const double values[] = {NAN, INFINITY, -INFINITY};
    const fmi2ValueReference inputs[] = {vrAeroLoad, vrRotorSpeed};
    const char *names[] = {"aeroLoad", "rotorSpeed"};
    size_t i, j;
    for (j = 0; j < 2; ++j)
        for (i = 0; i < 3; ++i) {
            Inst in = readyInstance(api, "badInput");
            fmi2Status s;
            char what[128];
            snprintf(what, sizeof what, "input %s = %g refused", names[j], values[i]);
            if (in.c == NULL) continue;
            s = api->setReal(in.c, &inputs[j], 1, &values[i]);
            if (!isRefusal(s)) s = api->doStep(in.c, 0.0, 1e-4, fmi2True);
            check(isRefusal(s), what, statusName(s));
            expectLogged(&in, names[j], what);
            freeInst(api, &in);
        }
    {   /* rotor speed outside [0, 30000] rpm, at the start or the end of a step */
        const double speeds[] = {-1.0, 30001.0};
        for (i = 0; i < 2; ++i) {
            Inst in = readyInstance(api, "badSpeed");
            fmi2ValueReference vr = vrRotorSpeed;
            fmi2Status s;
            if (in.c == NULL) continue;
            s = api->setReal(in.c, &vr, 1, &speeds[i]);
            if (!isRefusal(s)) s = api->doStep(in.c, 0.0, 1e-4, fmi2True);
            check(isRefusal(s), "rotorSpeed outside [0, 30000] refused", statusName(s));
            expectLogged(&in, "rotorSpeed", "rotorSpeed outside [0, 30000]");
            freeInst(api, &in);
        }
        {
            Inst in = readyInstance(api, "speedRamp");
            fmi2ValueReference vr = vrRotorSpeed;
            fmi2Integer order = 1;
            double n0 = 29999.0, slope = 1e7; /* rpm/s: leaves the range within the step */
            fmi2Status s;
            if (in.c != NULL) {
                api->setReal(in.c, &vr, 1, &n0);
                s = api->setRealInputDerivatives(in.c, &vr, 1, &order, &slope);
                if (!isRefusal(s)) s = api->doStep(in.c, 0.0, 1e-3, fmi2True);
                check(isRefusal(s), "rotorSpeed leaving [0, 30000] within a step refused",
                      statusName(s));
            }
            freeInst(api, &in);
        }
    }
    {   /* derivative orders and NaN derivatives */
        Inst in = readyInstance(api, "badDerivatives");
        fmi2ValueReference vr = vrAeroLoad, out = 50, par = vrEI;
        fmi2Integer o0 = 0, o9 = 9, o1 = 1, oNeg = -1;
        double one = 1.0, nan = NAN;
        if (in.c != NULL) {
            check(isRefusal(api->setRealInputDerivatives(in.c, &vr, 1, &o0, &one)),
                  "input derivative order 0 refused", NULL);
            check(isRefusal(api->setRealInputDerivatives(in.c, &vr, 1, &o9, &one)),
                  "input derivative order 9 refused", NULL);
            check(isRefusal(api->setRealInputDerivatives(in.c, &vr, 1, &oNeg, &one)),
                  "input derivative order -1 refused", NULL);
            check(isRefusal(api->setRealInputDerivatives(in.c, &out, 1, &o1, &one)),
                  "derivative of an output refused", NULL);
            check(isRefusal(api->setRealInputDerivatives(in.c, &par, 1, &o1, &one)),
                  "derivative of a parameter refused", NULL);
            {
                fmi2Status s = api->setRealInputDerivatives(in.c, &vr, 1, &o1, &nan);
                if (!isRefusal(s)) s = api->doStep(in.c, 0.0, 1e-4, fmi2True);
                check(isRefusal(s), "NaN input derivative refused", statusName(s));
            }
        }
        freeInst(api, &in);
    }
}

static void callOrder(const Api *api) {
    double out[N_OUT], x = 1.0, t = -1.0;
    fmi2ValueReference vrEi = vrEI, vrOut = 50;
    Inst in = newInstance(api, "order", fmi2True);
    if (in.c == NULL) return;
    check(isRefusal(api->doStep(in.c, 0.0, 1e-4, fmi2True)), "doStep before init refused", NULL);
    freeInst(api, &in);
    in = newInstance(api, "order", fmi2True);
    check(isRefusal(api->exitInitializationMode(in.c)), "exitInit before enterInit refused", NULL);
    freeInst(api, &in);
    in = newInstance(api, "order", fmi2True);
    api->getReal(in.c, &vrOut, 1, &x); /* allowed or refused: only must not crash */
    check(isRefusal(api->terminate(in.c)), "terminate before init refused", NULL);
    freeInst(api, &in);
    in = newInstance(api, "order", fmi2True);
    api->setupExperiment(in.c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    api->enterInitializationMode(in.c);
    check(isRefusal(api->doStep(in.c, 0.0, 1e-4, fmi2True)), "doStep in init mode refused", NULL);
    freeInst(api, &in);
    in = newInstance(api, "order", fmi2True);
    api->setupExperiment(in.c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    api->enterInitializationMode(in.c);
    check(isRefusal(api->enterInitializationMode(in.c)), "enterInit twice refused", NULL);
    freeInst(api, &in);
    in = newInstance(api, "order", fmi2True);
    api->setupExperiment(in.c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    api->enterInitializationMode(in.c);
    check(isRefusal(api->setupExperiment(in.c, fmi2False, 0.0, 0.0, fmi2False, 0.0)),
          "setupExperiment in init mode refused", NULL);
    freeInst(api, &in);
    in = readyInstance(api, "order");
    check(isRefusal(api->setReal(in.c, &vrEi, 1, &x)), "set fixed parameter after init refused",
          NULL);
    expectLogged(&in, "EI", "set fixed parameter after init");
    freeInst(api, &in);
    in = readyInstance(api, "order");
    check(isRefusal(api->setupExperiment(in.c, fmi2False, 0.0, 0.0, fmi2False, 0.0)),
          "setupExperiment after init refused", NULL);
    freeInst(api, &in);
    in = readyInstance(api, "order");
    check(isRefusal(api->enterInitializationMode(in.c)), "enterInit after init refused", NULL);
    freeInst(api, &in);
    in = readyInstance(api, "order");
    check(api->terminate(in.c) == fmi2OK, "terminate", NULL);
    check(isRefusal(api->doStep(in.c, 0.0, 1e-4, fmi2True)), "doStep after terminate refused",
          NULL);
    check(api->getRealStatus(in.c, fmi2LastSuccessfulTime, &t) == fmi2OK && t == 0.0,
          "lastSuccessfulTime after terminate at t = 0", NULL);
    check(isRefusal(api->terminate(in.c)), "terminate twice refused", NULL);
    check(api->reset(in.c) == fmi2OK, "reset after terminate", NULL);
    check(initialize(api, in.c, &defaults) == fmi2OK, "init after reset", NULL);
    check(step(api, in.c, 0, 1e-4, out) == fmi2OK, "step after reset", NULL);
    freeInst(api, &in);
}

static void badSteps(const Api *api) {
    const struct { double t, h; const char *what; } cases[] = {
        {0.0, 0.0, "h = 0"},
        {0.0, -1e-4, "h < 0"},
        {0.0, NAN, "h = NaN"},
        {0.0, INFINITY, "h = inf"},
        {0.0, DBL_MAX, "h = DBL_MAX (huge)"},
        {0.0, 1e300, "h = 1e300 (huge)"},
        {0.0, 1e3, "h = 1e3 s (1e8 internal steps > 1e7)"},
        {1e-3, 1e-4, "communication point ahead"},
        {-1e-3, 1e-4, "communication point behind"},
        {NAN, 1e-4, "communication point NaN"},
        {INFINITY, 1e-4, "communication point inf"},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        Inst in = readyInstance(api, "badStep");
        fmi2Status s;
        double out[N_OUT];
        if (in.c == NULL) continue;
        s = api->doStep(in.c, cases[i].t, cases[i].h, fmi2True);
        check(isRefusal(s), cases[i].what, statusName(s));
        check(in.env->calls > 0, cases[i].what, "refused without a log message");
        s = step(api, in.c, 0, 1e-4, out); /* afterwards: anything but a crash */
        check(isValidStatus((int)s), "valid status after a refused step", NULL);
        freeInst(api, &in);
    }
    {   /* a huge step with the smallest maxStep: 1e-8 s internal steps */
        Inst in = newInstance(api, "hugeStep", fmi2True);
        RunParams p = defaults;
        p.maxStep = 1e-8;
        if (in.c != NULL && initialize(api, in.c, &p) == fmi2OK) {
            fmi2Status s = api->doStep(in.c, 0.0, 1.0, fmi2True);
            check(isRefusal(s), "h = 1 s with maxStep 1e-8 (1e8 internal steps) refused",
                  statusName(s));
        }
        freeInst(api, &in);
    }
}

static void badReferencesAndPointers(const Api *api) {
    Inst in = readyInstance(api, "badRefs");
    fmi2ValueReference bad[] = {0, 15, 27, 32, 42, 49, 63, 999, 0xFFFFFFFFu};
    fmi2ValueReference good = 50, ivr = 60, rvr = vrEI, bvr = vrGating, ovr = 50;
    double x = 0.0;
    fmi2Integer i = 0;
    fmi2Boolean b = 0;
    fmi2String s = NULL;
    fmi2String sv = "x";
    fmi2Status st;
    fmi2FMUstate state = NULL;
    size_t n, k;
    fmi2Real dv = 0.0;
    if (in.c == NULL) return;
    for (k = 0; k < sizeof bad / sizeof bad[0]; ++k) {
        check(isRefusal(api->getReal(in.c, &bad[k], 1, &x)), "getReal bad vr refused", NULL);
        check(isRefusal(api->getInteger(in.c, &bad[k], 1, &i)), "getInteger bad vr", NULL);
        check(isRefusal(api->getBoolean(in.c, &bad[k], 1, &b)), "getBoolean bad vr", NULL);
        check(isRefusal(api->setReal(in.c, &bad[k], 1, &x)), "setReal bad vr refused", NULL);
    }
    check(isRefusal(api->getReal(in.c, &ivr, 1, &x)), "getReal of an Integer refused", NULL);
    check(isRefusal(api->getInteger(in.c, &good, 1, &i)), "getInteger of a Real refused", NULL);
    check(isRefusal(api->setInteger(in.c, &rvr, 1, &i)), "setInteger of a Real refused", NULL);
    check(isRefusal(api->setBoolean(in.c, &rvr, 1, &b)), "setBoolean of a Real refused", NULL);
    check(isRefusal(api->setReal(in.c, &bvr, 1, &x)), "setReal of a Boolean refused", NULL);
    check(isRefusal(api->setReal(in.c, &ovr, 1, &x)), "setReal of an output refused", NULL);
    check(isRefusal(api->getString(in.c, &good, 1, &s)), "getString refused", NULL);
    check(isRefusal(api->setString(in.c, &good, 1, &sv)), "setString refused", NULL);
    /* NULL arrays */
    check(isRefusal(api->getReal(in.c, NULL, 1, &x)), "getReal vr NULL", NULL);
    check(isRefusal(api->getReal(in.c, &good, 1, NULL)), "getReal value NULL", NULL);
    check(isRefusal(api->setReal(in.c, NULL, 1, &x)), "setReal vr NULL", NULL);
    check(isRefusal(api->setReal(in.c, &good, 1, NULL)), "setReal value NULL", NULL);
    check(isRefusal(api->getInteger(in.c, &ivr, 1, NULL)), "getInteger value NULL", NULL);
    check(isRefusal(api->setInteger(in.c, NULL, 1, &i)), "setInteger vr NULL", NULL);
    check(isRefusal(api->getBoolean(in.c, NULL, 1, &b)), "getBoolean vr NULL", NULL);
    check(isRefusal(api->setBoolean(in.c, &bvr, 1, NULL)), "setBoolean value NULL", NULL);
    check(isRefusal(api->setRealInputDerivatives(in.c, NULL, 1, NULL, NULL)),
          "setRealInputDerivatives NULL", NULL);
    check(isRefusal(api->getRealOutputDerivatives(in.c, &good, 1, NULL, &x)),
          "getRealOutputDerivatives NULL order", NULL);
    st = api->getReal(in.c, NULL, 0, NULL);
    check(st == fmi2OK || isRefusal(st), "getReal nvr 0 with NULL arrays", statusName(st));
    check(isRefusal(api->getFMUstate(in.c, NULL)), "getFMUstate NULL", NULL);
    check(isRefusal(api->setFMUstate(in.c, NULL)), "setFMUstate NULL", NULL);
    st = api->freeFMUstate(in.c, NULL);
    check(isValidStatus((int)st), "freeFMUstate NULL pointer", statusName(st));
    check(api->freeFMUstate(in.c, &state) == fmi2OK, "freeFMUstate of a NULL state is a no-op",
          NULL);
    check(isRefusal(api->serializedFMUstateSize(in.c, NULL, &n)), "state size NULL state", NULL);
    check(api->getFMUstate(in.c, &state) == fmi2OK, "getFMUstate", NULL);
    check(isRefusal(api->serializedFMUstateSize(in.c, state, NULL)), "state size NULL", NULL);
    check(isRefusal(api->serializeFMUstate(in.c, state, NULL, 100)), "serialize NULL", NULL);
    if (api->serializedFMUstateSize(in.c, state, &n) == fmi2OK && n > 1) {
        fmi2Byte *buf = (fmi2Byte *)malloc(n);
        check(isRefusal(api->serializeFMUstate(in.c, state, buf, n - 1)),
              "serialize into a too small buffer refused", NULL);
        free(buf);
    }
    check(isRefusal(api->deSerializeFMUstate(in.c, NULL, 10, &state)), "deserialize NULL", NULL);
    api->freeFMUstate(in.c, &state);
    check(isRefusal(api->getRealStatus(in.c, fmi2LastSuccessfulTime, NULL)),
          "getRealStatus NULL", NULL);
    check(isRefusal(api->getStatus(in.c, fmi2DoStepStatus, NULL)), "getStatus NULL", NULL);
    check(isRefusal(api->getRealStatus(in.c, (fmi2StatusKind)99, &x)), "status kind 99", NULL);
    st = api->getStringStatus(in.c, fmi2PendingStatus, &s);
    check(isValidStatus((int)st), "getStringStatus", NULL);
    check(isRefusal(api->cancelStep(in.c)), "cancelStep refused (no asynchronous steps)", NULL);
    check(isRefusal(api->getDirectionalDerivative(in.c, &good, 1, &rvr, 1, &dv, &x)),
          "getDirectionalDerivative refused", NULL);
    {
        fmi2Integer order = 1;
        check(isRefusal(api->getRealOutputDerivatives(in.c, &good, 1, &order, &x)),
              "getRealOutputDerivatives refused (maxOutputDerivativeOrder 0)", NULL);
    }
    {   /* logging categories */
        fmi2String unknown[] = {"logNoSuchCategory"};
        fmi2String withNull[] = {NULL};
        check(isRefusal(api->setDebugLogging(in.c, fmi2True, 1, unknown)),
              "unknown log category refused", NULL);
        check(isRefusal(api->setDebugLogging(in.c, fmi2True, 1, withNull)),
              "NULL log category refused", NULL);
        check(isRefusal(api->setDebugLogging(in.c, fmi2True, 3, NULL)),
              "NULL category array refused", NULL);
        check(api->setDebugLogging(in.c, fmi2True, 0, NULL) == fmi2OK, "all categories", NULL);
    }
    freeInst(api, &in);
    /* a NULL component in every function taking one */
    api->freeInstance(NULL);
    check(isRefusal(api->setDebugLogging(NULL, fmi2True, 0, NULL)), "NULL c setDebugLogging", NULL);
    check(isRefusal(api->setupExperiment(NULL, fmi2False, 0, 0, fmi2False, 0)), "NULL c setup",
          NULL);
    check(isRefusal(api->enterInitializationMode(NULL)), "NULL c enterInit", NULL);
    check(isRefusal(api->exitInitializationMode(NULL)), "NULL c exitInit", NULL);
    check(isRefusal(api->terminate(NULL)), "NULL c terminate", NULL);
    check(isRefusal(api->reset(NULL)), "NULL c reset", NULL);
    check(isRefusal(api->getReal(NULL, &good, 1, &x)), "NULL c getReal", NULL);
    check(isRefusal(api->getInteger(NULL, &ivr, 1, &i)), "NULL c getInteger", NULL);
    check(isRefusal(api->getBoolean(NULL, &bvr, 1, &b)), "NULL c getBoolean", NULL);
    check(isRefusal(api->getString(NULL, &good, 1, &s)), "NULL c getString", NULL);
    check(isRefusal(api->setReal(NULL, &good, 1, &x)), "NULL c setReal", NULL);
    check(isRefusal(api->setInteger(NULL, &ivr, 1, &i)), "NULL c setInteger", NULL);
    check(isRefusal(api->setBoolean(NULL, &bvr, 1, &b)), "NULL c setBoolean", NULL);
    check(isRefusal(api->setString(NULL, &good, 1, &sv)), "NULL c setString", NULL);
    check(isRefusal(api->getFMUstate(NULL, &state)), "NULL c getFMUstate", NULL);
    check(isRefusal(api->setFMUstate(NULL, state)), "NULL c setFMUstate", NULL);
    check(isRefusal(api->freeFMUstate(NULL, &state)), "NULL c freeFMUstate", NULL);
    check(isRefusal(api->serializedFMUstateSize(NULL, state, &n)), "NULL c state size", NULL);
    check(isRefusal(api->deSerializeFMUstate(NULL, (const fmi2Byte *)"x", 1, &state)),
          "NULL c deserialize", NULL);
    check(isRefusal(api->doStep(NULL, 0.0, 1e-4, fmi2True)), "NULL c doStep", NULL);
    check(isRefusal(api->cancelStep(NULL)), "NULL c cancelStep", NULL);
    check(isRefusal(api->getRealStatus(NULL, fmi2LastSuccessfulTime, &x)), "NULL c status", NULL);
    check(isRefusal(api->getStatus(NULL, fmi2DoStepStatus, &st)), "NULL c getStatus", NULL);
    check(isRefusal(api->setRealInputDerivatives(NULL, &good, 1, &i, &x)), "NULL c derivs", NULL);
}

static void badInstantiation(const Api *api) {
    LogEnv *env = (LogEnv *)calloc(1, sizeof *env);
    fmi2CallbackFunctions cb, cbNoLogger;
    fmi2Component c;
    char *longName = (char *)malloc(100001);
    char name[32] = "copiedName";
    const char *uris[] = {"file:///tmp/with space/resources", "file:/tmp/with space/resources",
                          "file:///tmp/with%20space/resources", "file://localhost/tmp/x",
                          "", "http://example.com/resources", "not a uri \x01\xff", NULL};
    size_t k;
    env->magic = LOG_MAGIC;
    env->allEnabled = 1;
    memset(&cb, 0, sizeof cb);
    cb.logger = logger;
    cb.allocateMemory = calloc;
    cb.freeMemory = free;
    cb.componentEnvironment = env;
    cbNoLogger = cb;
    cbNoLogger.logger = NULL;
    logClear(env);
    c = api->instantiate("g", fmi2CoSimulation, "{00000000-0000-0000-0000-000000000000}",
                         resourceUri, &cb, fmi2False, fmi2True);
    check(c == NULL, "wrong GUID refused", NULL);
    check(strstr(env->text, "GUID") != NULL || strstr(env->text, "guid") != NULL,
          "wrong GUID logged", env->text);
    if (c) api->freeInstance(c);
    c = api->instantiate("g", fmi2CoSimulation, NULL, resourceUri, &cb, fmi2False, fmi2True);
    check(c == NULL, "NULL GUID refused", NULL);
    if (c) api->freeInstance(c);
    /* the FMU also carries <ModelExchange>: accepted, and a co-simulation call is refused */
    c = api->instantiate("t", fmi2ModelExchange, guid, resourceUri, &cb, fmi2False, fmi2True);
    check(c != NULL, "fmuType ModelExchange accepted", NULL);
    if (c) {
        check(isRefusal(api->doStep(c, 0.0, 1e-4, fmi2True)), "fmi2DoStep refused for a model-exchange instance",
              NULL);
        api->freeInstance(c);
    }
    c = api->instantiate("t", (fmi2Type)7, guid, resourceUri, &cb, fmi2False, fmi2True);
    check(c == NULL, "fmuType 7 refused", NULL);
    if (c) api->freeInstance(c);
    c = api->instantiate("", fmi2CoSimulation, guid, resourceUri, &cb, fmi2False, fmi2True);
    check(c == NULL, "empty instance name refused", NULL);
    if (c) api->freeInstance(c);
    c = api->instantiate(NULL, fmi2CoSimulation, guid, resourceUri, &cb, fmi2False, fmi2True);
    check(c == NULL, "NULL instance name refused", NULL);
    if (c) api->freeInstance(c);
    c = api->instantiate("n", fmi2CoSimulation, guid, resourceUri, NULL, fmi2False, fmi2True);
    check(c == NULL, "NULL callbacks refused", NULL);
    if (c) api->freeInstance(c);
    c = api->instantiate("n", fmi2CoSimulation, guid, resourceUri, &cbNoLogger, fmi2False,
                         fmi2True);
    if (c) { /* accepted without a logger: errors must still not crash */
        fmi2ValueReference bad = 999;
        double x;
        check(isRefusal(api->getReal(c, &bad, 1, &x)), "no logger: bad vr refused", NULL);
        api->freeInstance(c);
    }
    for (k = 0; k < sizeof uris / sizeof uris[0]; ++k) {
        c = api->instantiate("uri", fmi2CoSimulation, guid, uris[k], &cb, fmi2False, fmi2True);
        if (k < 3) check(c != NULL, "file URI (with spaces, file:/ and file:///) accepted",
                         uris[k]);
        if (c) {
            check(initialize(api, c, &defaults) == fmi2OK, "init with that URI", uris[k]);
            api->freeInstance(c);
        }
    }
    memset(longName, 'x', 100000);
    longName[100000] = '\0';
    c = api->instantiate(longName, fmi2CoSimulation, guid, resourceUri, &cb, fmi2False, fmi2True);
    check(c != NULL, "100000-character instance name accepted", NULL);
    if (c) api->freeInstance(c);
    /* the FMU must copy the instance name, GUID and URI strings */
    c = api->instantiate(name, fmi2CoSimulation, guid, resourceUri, &cb, fmi2False, fmi2True);
    if (c) {
        fmi2ValueReference bad = 999;
        double x;
        memset(name, 'Z', sizeof name - 1);
        logClear(env);
        api->getReal(c, &bad, 1, &x);
        check(strstr(env->text, "ZZZZ") == NULL, "instance name copied at instantiation", NULL);
        api->freeInstance(c);
    }
    check(strcmp(api->getVersion(), "2.0") == 0, "fmi2GetVersion", NULL);
    check(strcmp(api->getTypesPlatform(), "default") == 0, "fmi2GetTypesPlatform", NULL);
    if (env->badCalls) check(0, "logger rules during instantiation", env->lastBad);
    free(longName);
    free(env);
}

/* State blobs: every truncation, every single-byte corruption, extension. A refused blob must
 * give fmi2Error; an accepted one (corruption the format cannot see) must still be safe. */
static void badBlobs(const Api *api) {
    Inst in = readyInstance(api, "blobs");
    fmi2FMUstate st = NULL, dst = NULL;
    size_t size = 0, k;
    fmi2Byte *blob, *work;
    double out[N_OUT];
    int accepted = 0;
    if (in.c == NULL) return;
    step(api, in.c, 0, 1e-4, out);
    api->getFMUstate(in.c, &st);
    api->serializedFMUstateSize(in.c, st, &size);
    blob = (fmi2Byte *)malloc(size + 16);
    work = (fmi2Byte *)malloc(size + 16);
    api->serializeFMUstate(in.c, st, blob, size);
    api->freeFMUstate(in.c, &st);
    for (k = 0; k < size; ++k) { /* truncated: every shorter length */
        fmi2Status s;
        memcpy(work, blob, k);
        dst = NULL;
        s = api->deSerializeFMUstate(in.c, work, k, &dst);
        if (s != fmi2Error) {
            char d[64];
            snprintf(d, sizeof d, "length %lu of %lu: %s", (unsigned long)k, (unsigned long)size,
                     statusName(s));
            check(0, "truncated state blob gives fmi2Error", d);
        }
        if (dst) api->freeFMUstate(in.c, &dst);
    }
    memcpy(work, blob, size);
    work[size] = 0;
    dst = NULL;
    check(api->deSerializeFMUstate(in.c, work, size + 1, &dst) == fmi2Error,
          "state blob with an extra byte gives fmi2Error", NULL);
    if (dst) api->freeFMUstate(in.c, &dst);
    for (k = 0; k < size; ++k) { /* each byte corrupted in turn */
        static const fmi2Byte patterns[] = {(fmi2Byte)0xFF, (fmi2Byte)0x80, (fmi2Byte)0x01};
        size_t p;
        for (p = 0; p < 3; ++p) {
            fmi2Status s;
            memcpy(work, blob, size);
            work[k] = (fmi2Byte)(work[k] ^ patterns[p]);
            dst = NULL;
            s = api->deSerializeFMUstate(in.c, work, size, &dst);
            check(s == fmi2OK || s == fmi2Error, "corrupt blob: OK or Error", statusName(s));
            if (s == fmi2OK && dst != NULL) {
                ++accepted;
                /* the format could not tell: using the state must still be safe */
                s = api->setFMUstate(in.c, dst);
                if (s == fmi2OK) {
                    double t = -1.0;
                    api->getRealStatus(in.c, fmi2LastSuccessfulTime, &t);
                    if (isfinite(t)) s = step(api, in.c, 1, 1e-4, out);
                    check(isValidStatus((int)s), "step from an accepted corrupt state", NULL);
                }
                api->reset(in.c);
                initialize(api, in.c, &defaults);
            }
            if (dst) api->freeFMUstate(in.c, &dst);
        }
    }
    printf("state blob: %lu bytes, %d of %lu single-byte corruptions accepted by the format\n",
           (unsigned long)size, accepted, (unsigned long)(3 * size));
    /* garbage */
    for (k = 0; k < size; ++k) work[k] = (fmi2Byte)(k * 131u + 7u);
    dst = NULL;
    check(api->deSerializeFMUstate(in.c, work, size, &dst) == fmi2Error, "garbage blob Error",
          NULL);
    if (dst) api->freeFMUstate(in.c, &dst);
    free(blob);
    free(work);
    freeInst(api, &in);
}

static void modelExchangeFunctions(const Api *api) {
    static const char *const names[] = {"fmi2EnterEventMode", "fmi2EnterContinuousTimeMode"};
    Inst in = readyInstance(api, "me");
    size_t k;
    for (k = 0; k < 2 && in.c != NULL; ++k) {
        fmi2EnterEventModeTYPE *f = NULL;
        void *p = dlsym(api->handle, names[k]);
        memcpy(&f, &p, sizeof p);
        if (f != NULL) check(isRefusal(f(in.c)), "model-exchange function refused", names[k]);
    }
    freeInst(api, &in);
}

/* ---------------------------------------------------------------------------------------------
 * leak mode: instantiate/free cycles and reset cycles, results identical every time */

static void leakCycles(const Api *api, long nInst, long nReset) {
    const int nSteps = 20;
    const double h = 1e-4;
    double ref[N_OUT], out[N_OUT];
    long i;
    int k, haveRef = 0;
    for (i = 0; i < nInst; ++i) {
        Inst in = newInstance(api, "leak", (fmi2Boolean)(i % 2));
        if (in.c == NULL) {
            check(0, "instantiate in a cycle", NULL);
            freeInst(api, &in);
            break;
        }
        if (initialize(api, in.c, &defaults) == fmi2OK) {
            fmi2FMUstate s = NULL;
            for (k = 0; k < nSteps; ++k)
                if (step(api, in.c, k, h, out) != fmi2OK) break;
            if (!haveRef) {
                memcpy(ref, out, sizeof ref);
                haveRef = 1;
            } else {
                check(memcmp(ref, out, sizeof ref) == 0, "same result in every instantiate cycle",
                      NULL);
            }
            api->getFMUstate(in.c, &s); /* left for fmi2FreeInstance to release */
        }
        freeInst(api, &in);
    }
    {
        Inst in = newInstance(api, "resetLeak", fmi2False);
        for (i = 0; i < nReset && in.c != NULL; ++i) {
            fmi2FMUstate s = NULL;
            size_t size = 0;
            if (api->reset(in.c) != fmi2OK || initialize(api, in.c, &defaults) != fmi2OK) {
                check(0, "reset + initialize in a cycle", NULL);
                break;
            }
            for (k = 0; k < nSteps; ++k)
                if (step(api, in.c, k, h, out) != fmi2OK) break;
            check(haveRef && memcmp(ref, out, sizeof ref) == 0, "same result in every reset cycle",
                  NULL);
            if (i % 10 == 0) { /* state handling leaks too */
                fmi2Byte *blob;
                api->getFMUstate(in.c, &s);
                api->serializedFMUstateSize(in.c, s, &size);
                blob = (fmi2Byte *)malloc(size);
                api->serializeFMUstate(in.c, s, blob, size);
                api->freeFMUstate(in.c, &s);
                api->deSerializeFMUstate(in.c, blob, size, &s);
                api->freeFMUstate(in.c, &s);
                free(blob);
            }
            if (i % 2 == 1) api->terminate(in.c);
        }
        freeInst(api, &in);
    }
    printf("leak cycles: %ld instantiate/free, %ld reset\n", nInst, nReset);
}

int main(int argc, char **argv) {
    Api api;
    const char *mode = argc > 2 ? argv[2] : "full";
    guid = getenv("SB_GUID") ? getenv("SB_GUID") : "{be1fc0de-d8b5-40e4-a0fb-399d8d12a40d}";
    if (getenv("SB_RESOURCES")) resourceUri = getenv("SB_RESOURCES");
    if (argc < 2) {
        fprintf(stderr, "usage: %s <binary.so> [full | leaks <nInst> <nReset>]\n", argv[0]);
        return 2;
    }
    if (!loadApi(argv[1], &api)) return 3;
    if (strcmp(mode, "full") == 0) {
        static const RunParams runs[] = {{1, 2, 3e-5, 1e-5}, {2, 1, 3e-5, 1e-5},
                                         {3, 2, 3e-5, 1e-5}, {1, 2, 0.0, 1e-3}};
        size_t r;
        for (r = 0; r < sizeof runs / sizeof runs[0]; ++r) fullRun(&api, &runs[r]);
        badInstantiation(&api);
        invalidParameters(&api);
        invalidInputs(&api);
        callOrder(&api);
        badSteps(&api);
        badReferencesAndPointers(&api);
        badBlobs(&api);
        modelExchangeFunctions(&api);
    } else if (strcmp(mode, "leaks") == 0 && argc > 4) {
        leakCycles(&api, atol(argv[3]), atol(argv[4]));
    } else {
        fprintf(stderr, "unknown mode %s\n", mode);
        return 2;
    }
    printf("sb_importer %s: %ld checks, %ld failures\n", mode, nChecks, nFailures);
    /* the library stays loaded so LeakSanitizer can symbolize FMU frames */
    return nFailures == 0 ? 0 : 1;
}
