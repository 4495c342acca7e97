/* ShroudContact FMU: identity (see modelDescription.xml next to this file). */
#ifndef SHROUD_CONTACT_CONFIG_H
#define SHROUD_CONTACT_CONFIG_H

#define MODEL_IDENTIFIER ShroudContact
#define MODEL_NAME "ShroudContact"
/* Must equal the guid attribute of modelDescription.xml (checked by CMake at configure time). */
#define MODEL_GUID "{9d41c7e3-25ab-4f0e-8a63-c1b7e2f50d94}"
#define MAX_ORDER 8             /* highest input derivative order, as the blades' (model-notes s.1) */
#define ROTOR_SPEED_MAX 30000.0 /* rotorSpeed range [0, max] rpm, as the blades' (model-notes s.1) */

#endif
