/* bench_step: cost of one internal RK4 step of the ShroudedBlade FMU, in ns, through the raw FMI 2.0
 * API (the FMU sources are linked in; no dlopen). For each configuration the master loop of a real
 * run is timed: per communication step fmi2SetReal of both inputs, fmi2SetRealInputDerivatives of
 * aeroLoad = 100 sin(omega t) (orders 1..8), fmi2DoStep, fmi2GetReal of two outputs. maxStep =
 * 1e-5 s, 5000 rpm, 1 s of simulated time = 1e5 internal steps; best of 3 repetitions. Two tables:
 * communication step 1e-4 s (10 internal steps per fmi2DoStep, a sweep's loop) and 1e-3 s (100,
 * mostly the integrator).
 *
 *   cmake --build build --target bench_step && build/bench_step
 *
 * Prints one line per configuration: ns per internal step, right-hand-side calls and located
 * switching events per internal step (from the instance's work counters). */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "fmi/instance.h"
#include "fmi2Functions.h"
#include "models/ShroudedBlade/blade_data.h"
#include "models/ShroudedBlade/variables.h"

static void quietLogger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                        fmi2String message, ...)
{
    (void)env; (void)name; (void)category;
    if (status >= fmi2Warning) fprintf(stderr, "[%d] %s\n", (int)status, message);
}

typedef struct {
    const char *name;
    int frictionModel;
    int amplitudeMode;
    int gating;
    double d; /* gap [m] */
    int modes;       /* m bending modes (docs/model.md s.2a) */
    int formulation; /* 1 printed, 2 consistent */
} Config;

static double now(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Returns the wall time [s] of the stepping loop; fills the counters. */
static double runOnce(const Config *cfg, double duration, double hComm, double maxStep, SolverCounters *counters)
{
    fmi2CallbackFunctions cb;
    fmi2Component c;
    const double Fw0 = 100.0, rpm = 5000.0;
    const double omega = 3.0 * 2.0 * 3.14159265358979323846 * rpm / 60.0;
    const long n = (long)floor(duration / hComm + 0.5);
    fmi2ValueReference vrIn[2] = {vr_aeroLoad, vr_rotorSpeed}, vrDer[8], vrOut[2] = {vr_tipDisplacement, vr_Keq};
    fmi2ValueReference vrReal[3] = {vr_d, vr_maxStep, vr_Fw0};
    fmi2ValueReference vrInt[4] = {vr_frictionModel, vr_amplitudeMode, vr_modes, vr_formulation};
    fmi2ValueReference vrBool[1] = {vr_gating};
    fmi2Real rv[3]; /* rv[2] = Fw0 = 0: the bench feeds aeroLoad, the built-in load is off */
    fmi2Integer iv[4];
    fmi2Boolean bv[1];
    fmi2Integer order[8];
    fmi2Real der[8], out[2], x[2];
    double t0, t1, sink = 0.0;
    long k;
    int j;
    memset(&cb, 0, sizeof cb);
    cb.logger = quietLogger;
    c = fmi2Instantiate("bench", fmi2CoSimulation, MODEL_GUID, NULL, &cb, fmi2False, fmi2False);
    if (c == NULL) return -1.0;
    rv[0] = cfg->d;
    rv[1] = maxStep;
    rv[2] = 0.0;
    iv[0] = cfg->frictionModel;
    iv[1] = cfg->amplitudeMode;
    iv[2] = cfg->modes;
    iv[3] = cfg->formulation;
    bv[0] = cfg->gating;
    fmi2SetupExperiment(c, fmi2False, 0.0, 0.0, fmi2False, 0.0);
    fmi2SetReal(c, vrReal, 3, rv);
    fmi2SetInteger(c, vrInt, 4, iv);
    fmi2SetBoolean(c, vrBool, 1, bv);
    fmi2EnterInitializationMode(c);
    if (fmi2ExitInitializationMode(c) > fmi2Warning) return -1.0;
    for (j = 0; j < 8; ++j) {
        vrDer[j] = vr_aeroLoad;
        order[j] = j + 1;
    }
    t0 = now();
    for (k = 0; k < n; ++k) {
        const double t = (double)k * hComm;
        x[0] = Fw0 * sin(omega * t);
        x[1] = rpm;
        for (j = 0; j < 8; ++j) der[j] = Fw0 * pow(omega, j + 1) * sin(omega * t + (j + 1) * 1.5707963267948966);
        fmi2SetReal(c, vrIn, 2, x);
        fmi2SetRealInputDerivatives(c, vrDer, 8, order, der);
        if (fmi2DoStep(c, t, hComm, fmi2True) != fmi2OK) {
            fprintf(stderr, "%s: fmi2DoStep failed at t = %g\n", cfg->name, t);
            break;
        }
        fmi2GetReal(c, vrOut, 2, out);
        sink += out[0];
    }
    t1 = now();
    *counters = ((BladeMemory *)((FmiInstance *)c)->memory)->counters;
    fmi2FreeInstance(c);
    if (!isfinite(sink)) fprintf(stderr, "non-finite output\n");
    return t1 - t0;
}

static void table(const Config *configs, size_t nConfigs, double duration, double hComm, double maxStep)
{
    printf("\ncommunication step %g s (%g internal steps each), maxStep %g s, %g s simulated\n", hComm,
           floor(hComm / maxStep + 0.5), maxStep, duration);
    printf("%-38s %12s %12s %14s\n", "configuration", "ns/step", "rhs/step", "events/step");
    for (size_t i = 0; i < nConfigs; ++i) {
        double best = 1e300;
        SolverCounters cnt;
        memset(&cnt, 0, sizeof cnt);
        for (int rep = 0; rep < 3; ++rep) {
            SolverCounters c1;
            double wall;
            memset(&c1, 0, sizeof c1);
            wall = runOnce(&configs[i], duration, hComm, maxStep, &c1);
            if (wall < 0.0) {
                printf("%-38s failed\n", configs[i].name);
                break;
            }
            if (wall < best) best = wall;
            cnt = c1;
        }
        if (cnt.internalSteps > 0)
            printf("%-38s %12.1f %12.2f %14.5f\n", configs[i].name, 1e9 * best / (double)cnt.internalSteps,
                   (double)cnt.rhsCalls / (double)cnt.internalSteps, (double)cnt.events / (double)cnt.internalSteps);
    }
}

/* `bench_step modes`: the Jenkins element (tracked B, consistent formulation) with m = 1..6 modes
 * (docs/model.md s.2a), and the one-mode default (printed) as the first row */
static int modesTable(double duration)
{
    static const Config configs[] = {
        {"m = 1, printed (default)", 3, 2, 1, 3e-5, 1, 1},
        {"m = 1, consistent", 3, 2, 1, 3e-5, 1, 2},
        {"m = 2, consistent", 3, 2, 1, 3e-5, 2, 2},
        {"m = 3, consistent", 3, 2, 1, 3e-5, 3, 2},
        {"m = 4, consistent", 3, 2, 1, 3e-5, 4, 2},
        {"m = 5, consistent", 3, 2, 1, 3e-5, 5, 2},
        {"m = 6, consistent", 3, 2, 1, 3e-5, 6, 2},
    };
    printf("bench_step modes: ns per internal RK4 step through the FMI API (best of 3), Jenkins element\n");
    table(configs, sizeof configs / sizeof configs[0], duration, 1e-3, 1e-5);
    return 0;
}

int main(int argc, char **argv)
{
    static const Config configs[] = {
        {"linear (d = 1 m, no contact)", 1, 1, 1, 1.0, 1, 1},
        {"macroslip DF, gating, fixed B", 1, 1, 1, 3e-5, 1, 1},
        {"macroslip DF, gating, tracked B", 1, 2, 1, 3e-5, 1, 1},
        {"macroslip DF, no gating, tracked B", 1, 2, 0, 3e-5, 1, 1},
        {"Coulomb DF, gating, tracked B", 2, 2, 1, 3e-5, 1, 1},
        {"Jenkins element, tracked B", 3, 2, 1, 3e-5, 1, 1},
    };
    const size_t n = sizeof configs / sizeof configs[0];
    /* a last argument "quick": 10 ms simulated per row instead of 1 s (a check that every row runs) */
    const double duration = argc > 1 && strcmp(argv[argc - 1], "quick") == 0 ? 0.01 : 1.0;
    if (argc > 1 && strcmp(argv[1], "modes") == 0) return modesTable(duration);
    printf("bench_step: ns per internal RK4 step through the FMI API (best of 3)\n");
    /* the master loop of a sweep: the FMI calls of every communication step are included */
    table(configs, n, duration, 1e-4, 1e-5);
    /* long communication steps: the integrator itself (the 8th-order Taylor load is then only
     * approximately a sine, which does not matter for the cost) */
    table(configs, n, duration, 1e-3, 1e-5);
    return 0;
}
