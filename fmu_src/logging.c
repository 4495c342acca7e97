/* Logging of the ShroudedBlade FMU through the FMI logger callback: only enabled categories reach
 * the logger (logAll enables all); '%' is escaped since the logger treats the message as a printf
 * format. */
#include <stdarg.h>
#include <stdio.h>

#include "instance.h"

static const char *const CATEGORY_NAMES[LOG_NUM_CATEGORIES] = {
    "logEvents", "logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal",
    "logAll", "logCalls"};

const char *logCategoryName(int category)
{
    return (category >= 0 && category < LOG_NUM_CATEGORIES) ? CATEGORY_NAMES[category] : "logAll";
}

int instanceLogEnabled(const Instance *inst, int category)
{
    if (inst == NULL || inst->logger == NULL) return 0;
    if (category < 0 || category >= LOG_NUM_CATEGORIES) return 0;
    return inst->logOn[category] || inst->logOn[LogAll];
}

static void emit(Instance *inst, fmi2Status status, int category, const char *fmt, va_list ap)
{
    size_t j = 0;
    vsnprintf(inst->message, sizeof inst->message, fmt, ap);
    /* the logger's message is a printf format: escape '%' */
    for (size_t i = 0; inst->message[i] != '\0' && j + 2 < sizeof inst->escaped; ++i) {
        if (inst->message[i] == '%') inst->escaped[j++] = '%';
        inst->escaped[j++] = inst->message[i];
    }
    inst->escaped[j] = '\0';
    inst->logger(inst->componentEnvironment, inst->instanceName, status, logCategoryName(category),
                 inst->escaped);
}

void instanceLog(Instance *inst, fmi2Status status, int category, const char *fmt, ...)
{
    va_list ap;
    if (!instanceLogEnabled(inst, category)) return;
    va_start(ap, fmt);
    emit(inst, status, category, fmt, ap);
    va_end(ap);
}

static int statusCategory(fmi2Status status)
{
    switch (status) {
    case fmi2Warning: return LogStatusWarning;
    case fmi2Discard: return LogStatusDiscard;
    case fmi2Error: return LogStatusError;
    case fmi2Fatal: return LogStatusFatal;
    default: return LogEvents;
    }
}

void instanceLogStatus(Instance *inst, fmi2Status status, const char *fmt, ...)
{
    va_list ap;
    const int category = statusCategory(status);
    if (!instanceLogEnabled(inst, category)) return;
    va_start(ap, fmt);
    emit(inst, status, category, fmt, ap);
    va_end(ap);
}
