/* BladeExternalContact FMU: identity (see modelDescription.xml next to this file). */
#ifndef BLADE_EXTERNAL_CONFIG_H
#define BLADE_EXTERNAL_CONFIG_H

#define MODEL_IDENTIFIER BladeExternalContact
#define MODEL_NAME "BladeExternalContact"
/* Must equal the guid attribute of modelDescription.xml (checked by CMake at configure time). */
#define MODEL_GUID "{3f6b2a14-8c0e-4d57-b1a9-7e20c5d4f861}"
#define ROTOR_SPEED_MAX 30000.0 /* [rpm], as ShroudedBlade (model-notes s.1) */

#endif
