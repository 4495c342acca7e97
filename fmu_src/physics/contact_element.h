/* The macroslip contact between two neighbouring shrouds, driven by their relative displacement
 * u = q_A - q_B (docs/model.md s.8): the time-domain Jenkins element of the blade (model-notes
 * s.2) or the describing function at a fixed amplitude B (docs/model.md s.3), with u(tau) given as
 * a polynomial over a communication step. The element has no inertia: its state (slider, mode,
 * dissipated energy) follows u exactly, with every open/close/stick/slip event located as a root
 * of a polynomial and the friction energy integrated in closed form (Jenkins element) or by
 * Gauss-Legendre quadrature (describing function). Pure C: no FMI types, no allocation, no
 * logging. */
#ifndef CONTACT_ELEMENT_H
#define CONTACT_ELEMENT_H

#include <stdint.h>

#include "physics/contact.h"

#define CE_MAX_DEG 9                 /* u(tau): a displacement of order 8 built from a velocity of order 8 */
#define CE_MAX_EVENTS_PER_STEP 1000  /* more is chattering */

/* A polynomial sum_j c[j] tau^j, tau [s] from the step start. */
typedef struct {
    double c[CE_MAX_DEG + 1];
    int deg; /* highest j used (c[j] = 0 above) */
} CePoly;

double cePolyAt(const CePoly *p, double tau);
/* dp/dtau at tau */
double cePolySlopeAt(const CePoly *p, double tau);

typedef enum { CeOk = 0, CeChattering = 1, CeOmegaZero = 2, CeNonFinite = 3 } CeStatus;

/* Constants, built once per run. */
typedef struct {
    FrictionModel friction;  /* 1 macroslip DF, 2 Coulomb DF, 3 Jenkins element */
    int gating;              /* DF: forces only while |u| > d (eq. 12-13) */
    ContactParams contact;
    double sinG, cosG;       /* [-] */
    double kd;               /* kdRatio kn [N/m] */
    double knCos;            /* kn cos(gamma) [N/m] */
    double muKnCos;          /* mu kn cos(gamma) [N/m] */
    int stickAtEntry;        /* 1 if kd tan(gamma) <= mu kn: an arriving contact sticks */
    double B;                /* DF amplitude [m] */
    DescribingFunction df;   /* DF at B (all zero for the Jenkins element) */
    double omegaPerRpm;      /* engineOrder 2 pi / 60 [rad/s per rpm] */
} CeModel;

/* State: consistent with the relative displacement uRef. Plain data. */
typedef struct {
    double w;        /* slider position in the Delta_u coordinate [m] (Jenkins element) */
    double E;        /* dissipated friction energy [J] */
    double uRef;     /* relative displacement the state belongs to [m] */
    int32_t mode;    /* Jenkins element: ContactState; DF: 1 gate on, 0 off */
    int32_t side;    /* sigma = +1 (u > d) or -1 (u < -d) */
    int32_t slipDir; /* s = sign(F_f) in slip */
} CeState;

/* Returns 0 on success, nonzero if the parameters are unusable (contactDescribe refused B for a
 * DF model, kd = 0, engineOrder < 1). */
int ceBuild(CeModel *m, const ContactParams *cp, FrictionModel friction, Projection projection, int gating,
            double B, int engineOrder);

/* State at u0 [m] with the spring unloaded (stick in contact), energy E0 [J]. */
void ceInit(const CeModel *m, CeState *s, double u0, double E0);

/* Advances s along u(tau), tau in [0, h] (s consistent with u(0)); nRpm(tau): rotor speed [rpm]
 * (DF only). *events receives the number of located events (may be NULL). On failure s is
 * partially advanced: the caller restores its copy. */
CeStatus ceAdvance(const CeModel *m, CeState *s, const CePoly *u, const CePoly *nRpm, double h, long *events);

/* Makes s consistent with u0 [m]: the Jenkins element follows the straight path from s->uRef to
 * u0 (slip and its dissipation included); a jump of rounding size (<= 1e-12 (|u0| + d)) keeps the
 * mode (the master rebuilds u from its values); the DF gate is set from |u0|. */
CeStatus ceProject(const CeModel *m, CeState *s, double u0);

typedef struct {
    double contactForce;  /* F_c on the contact coordinate, resisting u [N]: side A gets -F_c, B +F_c */
    double normalForce;   /* F_n (eq. 3), or p_k u (DF) [N] */
    double frictionForce; /* F_f, or f_k u + f_c u' (DF) [N] */
    int contactState;     /* ContactState */
} CeOutputs;

/* Outputs of a state consistent with u [m], at relative velocity du [m/s] and rotor speed nRpm
 * (DF; f_c and C_eq read 0 at omega = 0). */
void ceOutputs(const CeModel *m, const CeState *s, double u, double du, double nRpm, CeOutputs *o);

#endif
