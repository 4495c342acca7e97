/* Excitation FMU: identity (see modelDescription.xml next to this file). */
#ifndef EXCITATION_CONFIG_H
#define EXCITATION_CONFIG_H

#define MODEL_IDENTIFIER Excitation
#define MODEL_NAME "Excitation"
/* Must equal the guid attribute of modelDescription.xml (checked by CMake at configure time). */
#define MODEL_GUID "{6a0c7e52-3f1d-4b8e-9c27-5d4e1f0a9b13}"

#endif
