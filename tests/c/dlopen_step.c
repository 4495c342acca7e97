/* dlopen_step: load an FMI 2.0 co-simulation binary the way a C master does and take one step.
 *
 *   dlopen_step <binary.so> <guid> <resourceUri> <outputVr>
 *
 * This program is built WITHOUT -lm (tests/test_fmu_links.py checks that), so the process holds
 * no libm: a binary that uses sin/cos/sqrt without linking libm itself fails here, with
 * RTLD_NOW, as it fails in any C or C++ master. Python masters hide that fault because
 * the interpreter has libm loaded.
 * Prints "OK <value of outputVr after one step>" and exits 0, or prints the failing call and
 * exits 1. */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#include "fmi2Functions.h"

static void logger(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status, fmi2String category,
                   fmi2String message, ...) {
    (void)env;
    fprintf(stderr, "[%s] status %d %s: %s\n", name ? name : "?", (int)status, category ? category : "?",
            message ? message : "");
}

/* dlsym's void * to a function pointer goes through memcpy-free union punning (ISO C forbids the cast) */
static void *symbol(void *lib, const char *name) {
    void *p = dlsym(lib, name);
    if (p == NULL) fprintf(stderr, "FAIL: missing symbol %s\n", name);
    return p;
}

#define LOAD(type, var, name)                 \
    union { void *p; type f; } var##U;        \
    var##U.p = symbol(lib, name);             \
    if (var##U.p == NULL) return 1;           \
    type var = var##U.f

#define CHECK(call)                                               \
    do {                                                          \
        fmi2Status s_ = (call);                                   \
        if (s_ != fmi2OK) {                                       \
            fprintf(stderr, "FAIL: %s returned %d\n", #call, s_); \
            return 1;                                             \
        }                                                         \
    } while (0)

int main(int argc, char **argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: %s <binary.so> <guid> <resourceUri> <outputVr>\n", argv[0]);
        return 2;
    }
    void *lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
    if (lib == NULL) {
        fprintf(stderr, "FAIL: dlopen: %s\n", dlerror());
        return 1;
    }
    LOAD(fmi2InstantiateTYPE *, instantiate, "fmi2Instantiate");
    LOAD(fmi2SetupExperimentTYPE *, setup, "fmi2SetupExperiment");
    LOAD(fmi2EnterInitializationModeTYPE *, enterInit, "fmi2EnterInitializationMode");
    LOAD(fmi2ExitInitializationModeTYPE *, exitInit, "fmi2ExitInitializationMode");
    LOAD(fmi2DoStepTYPE *, doStep, "fmi2DoStep");
    LOAD(fmi2GetRealTYPE *, getReal, "fmi2GetReal");
    LOAD(fmi2TerminateTYPE *, terminate, "fmi2Terminate");
    LOAD(fmi2FreeInstanceTYPE *, freeInstance, "fmi2FreeInstance");

    fmi2CallbackFunctions cb = {logger, calloc, free, NULL, NULL};
    fmi2Component c = instantiate("dlopen_step", fmi2CoSimulation, argv[2], argv[3], &cb, fmi2False, fmi2False);
    if (c == NULL) {
        fprintf(stderr, "FAIL: fmi2Instantiate returned NULL\n");
        return 1;
    }
    fmi2ValueReference vr = (fmi2ValueReference)strtoul(argv[4], NULL, 10);
    fmi2Real value = 0.0;
    CHECK(setup(c, fmi2False, 0.0, 0.0, fmi2True, 1.0));
    CHECK(enterInit(c));
    CHECK(exitInit(c));
    CHECK(doStep(c, 0.0, 1e-4, fmi2True));
    CHECK(getReal(c, &vr, 1, &value));
    CHECK(terminate(c));
    freeInstance(c);
    dlclose(lib);
    printf("OK %.17g\n", value);
    return 0;
}
