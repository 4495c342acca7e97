/* The ring's period map restarts every instance at t = 0 before each period
 * (harness/system/ring_orbits/restart.py): fmi2Reset, fmi2SetupExperiment at t = 0, its parameters
 * and start values (fmi2SetReal, fmi2SetInteger, fmi2SetBoolean), fmi2EnterInitializationMode and
 * fmi2ExitInitializationMode, in this order, per instance in turn; after the period it reads the
 * state back (fmi2GetReal of the same variables from every instance of a binary). The same calls as
 * the binding's, without ctypes between them (72 calls per period of the 6-blade ring to restart,
 * 12 to read). */
#include <stddef.h>

#include "fmi2Functions.h"

typedef struct {
    fmi2ResetTYPE *reset;
    fmi2SetupExperimentTYPE *setupExperiment;
    fmi2SetRealTYPE *setReal;
    fmi2SetIntegerTYPE *setInteger;
    fmi2SetBooleanTYPE *setBoolean;
    fmi2EnterInitializationModeTYPE *enterInitializationMode;
    fmi2ExitInitializationModeTYPE *exitInitializationMode;
} RestartApi; /* one binary's functions (pointers handed over by ctypes) */

typedef struct {
    void *c;                         /* fmi2Component */
    const unsigned int *realVr;      /* parameters, then start values */
    const double *real;
    size_t nReal;
    const unsigned int *intVr;
    const int *ints;
    size_t nInt;
    const unsigned int *boolVr;
    const int *bools;
    size_t nBool;
} RestartInstance;

enum { RESTART_RESET = 1, RESTART_SETUP, RESTART_REAL, RESTART_INTEGER, RESTART_BOOLEAN, RESTART_ENTER, RESTART_EXIT };

#define CALL(code, call) do { if ((*status = (int)(call)) > fmi2Warning) return (code); } while (0)

/* Restarts instances 0..count-1; 0, or the failed call (RESTART_*) with its instance in *failed and
 * its status in *status. */
int ringRestart(const RestartApi *api, const RestartInstance *in, int count, int *failed, int *status) {
    for (int i = 0; i < count; i++) {
        const RestartInstance *r = &in[i];
        *failed = i;
        CALL(RESTART_RESET, api->reset(r->c));
        CALL(RESTART_SETUP, api->setupExperiment(r->c, fmi2False, 0.0, 0.0, fmi2False, 0.0));
        if (r->nReal) CALL(RESTART_REAL, api->setReal(r->c, r->realVr, r->nReal, r->real));
        if (r->nInt) CALL(RESTART_INTEGER, api->setInteger(r->c, r->intVr, r->nInt, r->ints));
        if (r->nBool) CALL(RESTART_BOOLEAN, api->setBoolean(r->c, r->boolVr, r->nBool, r->bools));
        CALL(RESTART_ENTER, api->enterInitializationMode(r->c));
        CALL(RESTART_EXIT, api->exitInitializationMode(r->c));
    }
    return 0;
}

/* fmi2GetReal of the same k variables vr from instances c[0..count-1] into out (row i instance i's, k
 * values); 0, or 1 with the failed instance in *failed and its status in *status. */
int ringReads(fmi2GetRealTYPE *getReal, void *const *c, int count, const unsigned int *vr, size_t k, double *out,
              int *failed, int *status) {
    for (int i = 0; i < count; i++) {
        *failed = i;
        if ((*status = (int)getReal(c[i], vr, k, out + (size_t)i * k)) > fmi2Warning) return 1;
    }
    return 0;
}
