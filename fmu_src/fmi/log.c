/* Logging of the generic layer: messages are formatted here and handed to the face's sink. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "fmi/log.h"

static const char *const CATEGORY_NAMES[LOG_NUM_CATEGORIES] = {
    "logEvents", "logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
    "logAll", "logCalls"};

const char *logCategoryName(int category)
{
    return (category >= 0 && category < LOG_NUM_CATEGORIES) ? CATEGORY_NAMES[category] : "logAll";
}

int logCategoryIndex(const char *name)
{
    for (int k = 0; name != NULL && k < LOG_NUM_CATEGORIES; ++k)
        if (strcmp(name, CATEGORY_NAMES[k]) == 0) return k;
    return -1;
}

int fmiLogEnabled(const FmiInstance *inst, int category)
{
    if (inst == NULL || inst->sink == NULL) return 0;
    if (category < 0 || category >= LOG_NUM_CATEGORIES) return 0;
    if (category >= LogStatusWarning && category <= LogStatusFatal) return 1; /* always reported */
    return inst->logOn[category] || inst->logOn[LogAll];
}

FmiStatus fmiSetDebugLogging(FmiInstance *inst, const char *fn, int loggingOn, size_t nCategories,
                             const char *const categories[])
{
    size_t i;
    int k;
    if (nCategories > 0 && categories == NULL) {
        fmiLogStatus(inst, FmiError, "%s: categories is NULL with nCategories = %lu", fn,
                          (unsigned long)nCategories);
        return FmiError;
    }
    for (i = 0; i < nCategories; ++i) {
        int found = 0;
        if (categories[i] != NULL)
            for (k = 0; k < LOG_NUM_CATEGORIES; ++k)
                if (strcmp(categories[i], logCategoryName(k)) == 0) found = 1;
        if (!found) {
            fmiLogStatus(inst, FmiError,
                              "%s: unknown log category '%s'; known: logEvents, logStatusWarning, "
                              "logStatusDiscard, logStatusError, logStatusFatal, logAll, logCalls", fn,
                              categories[i] ? categories[i] : "(NULL)");
            return FmiError;
        }
    }
    if (nCategories == 0 || loggingOn) {
        for (k = 0; k < LOG_NUM_CATEGORIES; ++k) inst->logOn[k] = (loggingOn && nCategories == 0) ? 1 : 0;
    }
    if (nCategories > 0) {
        for (i = 0; i < nCategories; ++i)
            for (k = 0; k < LOG_NUM_CATEGORIES; ++k)
                if (strcmp(categories[i], logCategoryName(k)) == 0) inst->logOn[k] = loggingOn ? 1 : 0;
    }
    return FmiOK;
}

static void emit(FmiInstance *inst, FmiStatus status, int category, const char *fmt, va_list ap)
{
    vsnprintf(inst->message, sizeof inst->message, fmt, ap);
    inst->sink(inst->sinkCtx, inst->instanceName, status, logCategoryName(category), inst->message);
}

void fmiLog(FmiInstance *inst, FmiStatus status, int category, const char *fmt, ...)
{
    va_list ap;
    if (!fmiLogEnabled(inst, category)) return;
    va_start(ap, fmt);
    emit(inst, status, category, fmt, ap);
    va_end(ap);
}

static int statusCategory(FmiStatus status)
{
    switch (status) {
    case FmiWarning: return LogStatusWarning;
    case FmiDiscard: return LogStatusDiscard;
    case FmiError: return LogStatusError;
    case FmiFatal: return LogStatusFatal;
    default: return LogEvents;
    }
}

void fmiLogStatus(FmiInstance *inst, FmiStatus status, const char *fmt, ...)
{
    va_list ap;
    const int category = statusCategory(status);
    if (!fmiLogEnabled(inst, category)) return;
    va_start(ap, fmt);
    emit(inst, status, category, fmt, ap);
    va_end(ap);
}
