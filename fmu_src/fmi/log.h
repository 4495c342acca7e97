/* Logging through the face's sink. Warnings, discards, errors and fatal errors always reach the
 * importer's logger, whatever loggingOn says (the convention of the FMI SDKs: a refusal must be
 * explained); the debug categories (logEvents, logCalls) reach it only when enabled by loggingOn or
 * SetDebugLogging (logAll enables all). */
#ifndef FMI_LOG_H
#define FMI_LOG_H

#include "fmi/instance.h"

const char *logCategoryName(int category);
/* Category index of a name, or -1. */
int logCategoryIndex(const char *name);

/* 1 if a message of this category reaches the logger now. */
int fmiLogEnabled(const FmiInstance *inst, int category);

/* The categories switched by a face's SetDebugLogging (FMI 2.0 s.2.1.5, FMI 3.0 s.2.3.1): with
 * nCategories = 0 all of them follow loggingOn; with a list and loggingOn only the listed ones are
 * on, with loggingOn = 0 the listed ones are switched off. An unknown name (or NULL array) logs and
 * returns FmiError, nothing changed. */
FmiStatus fmiSetDebugLogging(FmiInstance *inst, const char *fn, int loggingOn, size_t nCategories,
                             const char *const categories[]);

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
