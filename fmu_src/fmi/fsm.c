/* Names and phases of the state machine states (see fsm.h). */
#include "fmi/fsm.h"

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
    case FsmEventMode: return "eventMode";
    case FsmContinuousTimeMode: return "continuousTimeMode";
    default: return "unknown";
    }
}

int fsmPreInit(int32_t state) { return state == FsmInstantiated || state == FsmInitializationMode; }
