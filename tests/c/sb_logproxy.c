/* Test-only helper library for the Python FMI tests (tests/fmi2raw.py), not part of the FMU.
 *
 * The FMI 2.0 logger is variadic (printf style); ctypes cannot implement a variadic C function,
 * so sbLogProxy formats the message with vsnprintf, exactly as a conforming importer does, and
 * hands the finished text to a plain callback. The callback and a cookie travel inside the
 * componentEnvironment the importer passes to fmi2Instantiate (struct SbLogEnv), so one process
 * can hold many instances with different loggers. A logger call whose componentEnvironment is not
 * an SbLogEnv (the FMU lost or replaced it) is counted in sbOrphanLogs instead; calls with a NULL
 * componentEnvironment (legal when the importer passed NULL) are counted in sbNullEnvLogs.
 *
 * sbCalloc/sbFree are counting memory callbacks: the FMU declares
 * canNotUseMemoryManagementFunctions="true", so the tests check they are never called. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>

#define SB_LOG_MAGIC 0x5B10C0DEu

typedef void (*SbPlainLogger)(void *cookie, const char *instanceName, int status,
                              const char *category, const char *message);

typedef struct {
    unsigned magic;         /* SB_LOG_MAGIC */
    SbPlainLogger callback; /* receives the formatted message */
    void *cookie;           /* passed back unchanged */
} SbLogEnv;

/* Test-side counters (this library is test code, not the FMU: globals are fine here). */
static volatile long sbOrphanLogCount = 0;
static volatile long sbNullEnvLogCount = 0;
static volatile long sbAllocCount = 0;
static volatile long sbFreeCount = 0;

long sbOrphanLogs(void) { return __atomic_load_n(&sbOrphanLogCount, __ATOMIC_SEQ_CST); }
long sbNullEnvLogs(void) { return __atomic_load_n(&sbNullEnvLogCount, __ATOMIC_SEQ_CST); }
long sbAllocs(void) { return __atomic_load_n(&sbAllocCount, __ATOMIC_SEQ_CST); }
long sbFrees(void) { return __atomic_load_n(&sbFreeCount, __ATOMIC_SEQ_CST); }

void sbLogProxy(void *componentEnvironment, const char *instanceName, int status,
                const char *category, const char *message, ...) {
    SbLogEnv *env = (SbLogEnv *)componentEnvironment;
    char small[1024];
    char *text = small;
    char *big = NULL;
    va_list args;
    int n;
    if (env == NULL) {
        __atomic_add_fetch(&sbNullEnvLogCount, 1, __ATOMIC_SEQ_CST);
        return;
    }
    if (env->magic != SB_LOG_MAGIC || env->callback == NULL) {
        __atomic_add_fetch(&sbOrphanLogCount, 1, __ATOMIC_SEQ_CST);
        return;
    }
    if (message == NULL) {
        env->callback(env->cookie, instanceName, status, category, NULL);
        return;
    }
    va_start(args, message);
    n = vsnprintf(small, sizeof small, message, args);
    va_end(args);
    if (n < 0) {
        text = NULL;
    } else if ((size_t)n >= sizeof small) {
        big = (char *)malloc((size_t)n + 1);
        if (big != NULL) {
            va_start(args, message);
            vsnprintf(big, (size_t)n + 1, message, args);
            va_end(args);
            text = big;
        }
    }
    env->callback(env->cookie, instanceName, status, category, text);
    free(big);
}

void *sbCalloc(size_t nobj, size_t size) {
    __atomic_add_fetch(&sbAllocCount, 1, __ATOMIC_SEQ_CST);
    return calloc(nobj, size);
}

void sbFree(void *obj) {
    __atomic_add_fetch(&sbFreeCount, 1, __ATOMIC_SEQ_CST);
    free(obj);
}
