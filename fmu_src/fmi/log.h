/* Logging through the face's sink: only enabled categories reach it (logAll enables all). */
#ifndef FMI_LOG_H
#define FMI_LOG_H

#include "fmi/instance.h"

const char *logCategoryName(int category);
/* Category index of a name, or -1. */
int logCategoryIndex(const char *name);

int fmiLogEnabled(const FmiInstance *inst, int category);

#if defined(__GNUC__)
__attribute__((format(printf, 4, 5)))
#endif
void fmiLog(FmiInstance *inst, FmiStatus status, int category, const char *fmt, ...);

/* Logs with the category of the status (logStatusWarning/Discard/Error/Fatal). */
#if defined(__GNUC__)
__attribute__((format(printf, 3, 4)))
#endif
void fmiLogStatus(FmiInstance *inst, FmiStatus status, const char *fmt, ...);

#endif
