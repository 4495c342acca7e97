/* Shroud contact (paper eq. 1-14, MODEL.md s.3, docs/model-notes.md s.2 and s.5).
 * Pure functions, no FMI types, no state beyond what the caller passes. */
#ifndef CONTACT_H
#define CONTACT_H

typedef enum { FrictionMacroslipDF = 1, FrictionCoulombDF = 2, FrictionMacroslipTD = 3 } FrictionModel;
typedef enum { ProjectionPaper = 1, ProjectionConsistent = 2 } Projection;
typedef enum { RegimeOpen = 0, RegimeStickSlip = 1, RegimeFullStick = 2 } Regime;
typedef enum { ContactOpen = 0, ContactStick = 1, ContactSlip = 2 } ContactState;

typedef struct {
    double kn;      /* normal contact stiffness [N/m] */
    double kdRatio; /* k_d / k_n [-] */
    double mu;      /* friction coefficient [-] */
    double gamma;   /* contact angle [rad], (0, pi/2) */
    double d;       /* gap [m], >= 0 */
} ContactParams;

typedef struct {
    Regime regime;
    double theta1, theta2, theta3; /* loop angles, eq. 5 [rad] (0 where not defined) */
    double fk;      /* friction stiffness per unit v [N/m] (eq. 7, MODEL.md) */
    double fcOmega; /* f_c * omega [N/m]: f_c = fcOmega / omega (eq. 8 with the fix) */
    double pk;      /* normal stiffness per unit v [N/m] (eq. 10) */
    double Keq;     /* equivalent stiffness [N/m] (eq. 12, projection applied) */
    double CeqOmega;/* C_eq * omega [N/m] (eq. 13, projection applied) */
} DescribingFunction;

/* Regime for amplitude B [m] (MODEL.md s.3). */
Regime contactRegime(const ContactParams *p, double B);

/* Describing function of the macroslip (model 1) or Coulomb (model 2) loop for amplitude B [m],
 * closed forms. Returns 0 on success, nonzero for an invalid model/projection/B. */
int contactDescribe(const ContactParams *p, FrictionModel model, Projection projection, double B,
                    DescribingFunction *out);

/* Normal force F_n(v) [N], eq. 3. */
double contactNormalForce(const ContactParams *p, double v);

/* Friction force of the loop F_f(theta) [N] at phase theta in [0, 2 pi), eq. 4 (model 1) or its
 * Coulomb limit (model 2), for amplitude B > d. Used by the quadrature tests. */
double contactLoopFriction(const ContactParams *p, FrictionModel model, double B, double theta);

/* Loop state (ContactState) at phase theta for amplitude B (docs/model-notes.md s.4). */
ContactState contactLoopState(const ContactParams *p, FrictionModel model, double B, double theta);

#endif
