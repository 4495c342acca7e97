/* The co-simulation state machine (FMI 2.0 s.4.2.4): its states and their phases. A face holds one
 * allowed-states mask per function (fmi2_cs.c; fmi3_cs.c maps FMI 3.0's states onto these). */
#ifndef FMI_FSM_H
#define FMI_FSM_H

#include <stdint.h>

/* States of the co-simulation state machine (FMI 2.0 s.4.2.4) and the two model-exchange states
 * after initialization (s.3.2.3), one bit each for allowed-state
 * masks. Not serialized: a deserialized FMU state derives it from FmiRun.initialized. */
typedef enum {
    FsmStartEnd = 1 << 0,
    FsmInstantiated = 1 << 1,
    FsmInitializationMode = 1 << 2,
    FsmStepComplete = 1 << 3,
    FsmStepInProgress = 1 << 4,
    FsmStepFailed = 1 << 5,
    FsmStepCanceled = 1 << 6,
    FsmTerminated = 1 << 7,
    FsmError = 1 << 8,
    FsmFatal = 1 << 9,
    /* FMI 2.0 model exchange (s.3.2.3): after initialization an instance alternates between these */
    FsmEventMode = 1 << 10,
    FsmContinuousTimeMode = 1 << 11
} FsmState;

const char *fsmStateName(int32_t state);

/* 1 before the end of initialization (instantiated or initializationMode): parameters may still
 * change and the model follows them. */
int fsmPreInit(int32_t state);

#endif
