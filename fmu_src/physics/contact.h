/* Shroud contact (paper eq. 1-14, docs/model.md s.3, docs/model-notes.md s.2 and s.5).
 * Pure functions, no FMI types, no state beyond what the caller passes. */
#ifndef CONTACT_H
#define CONTACT_H

/* FrictionNone: no built-in contact (the blade whose contact force is an input, BladeExternalContact);
 * only physics/dynamics accepts it, contactDescribe refuses it. */
typedef enum { FrictionNone = 0, FrictionMacroslipDF = 1, FrictionCoulombDF = 2, FrictionMacroslipTD = 3 } FrictionModel;
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
    double fk;      /* friction stiffness per unit v [N/m] (eq. 7, docs/model.md) */
    double fcOmega; /* f_c * omega [N/m]: f_c = fcOmega / omega (eq. 8 with the fix) */
    double pk;      /* normal stiffness per unit v [N/m] (eq. 10) */
    double Keq;     /* equivalent stiffness [N/m] (eq. 12, projection applied) */
    double CeqOmega;/* C_eq * omega [N/m] (eq. 13, projection applied) */
} DescribingFunction;

/* 1 if every field is finite and kn >= 0, kdRatio >= 0, mu >= 0, d >= 0, 0 <= gamma <= pi/2;
 * else 0. contactDescribe refuses (nonzero return) what this refuses. */
int contactParamsValid(const ContactParams *p);

/* Regime of the macroslip loop for amplitude B [m] (docs/model.md s.3): open if B <= d, stick-slip if
 * k_d tan(gamma) >= mu k_n, else full stick. Invalid p or non-finite B give RegimeOpen. */
Regime contactRegime(const ContactParams *p, double B);

/* Regime for a given friction model: as contactRegime, except that the Coulomb DF (model 2) is
 * never in full stick (docs/model-notes.md s.5). This is what contactDescribe reports. */
Regime contactModelRegime(const ContactParams *p, FrictionModel model, double B);

/* Describing function of the macroslip (model 1) or Coulomb (model 2) loop for amplitude B [m],
 * closed forms. Model 3 (time-domain element) is accepted and gives the macroslip DF values
 * (information outputs, docs/model-notes.md s.4). B <= d: regime open, everything 0.
 * Returns 0 on success; nonzero (out zeroed) for: 1 out NULL, 2 invalid params, 3 invalid model,
 * 4 invalid projection, 5 B negative or non-finite, 6 non-finite result (overflow). */
int contactDescribe(const ContactParams *p, FrictionModel model, Projection projection, double B,
                    DescribingFunction *out);

/* Normal force F_n(v) [N], eq. 3. NaN for invalid params or non-finite v. */
double contactNormalForce(const ContactParams *p, double v);

/* Friction force of the loop F_f(theta) [N] at phase theta in [0, 2 pi), eq. 4 (model 1) or its
 * Coulomb limit (model 2), for amplitude B > d. Used by the quadrature tests. theta is reduced
 * modulo 2 pi; B <= d gives 0; in full stick F_f = (k_d tan g / k_n) F_n(B cos theta) (model 1
 * and 3); NaN for invalid params/model, negative or non-finite B or theta. */
double contactLoopFriction(const ContactParams *p, FrictionModel model, double B, double theta);

/* Loop state (ContactState) at phase theta for amplitude B (docs/model-notes.md s.4): stick on
 * intervals 1, 4, 6, 9 of eq. 4, slip on 2, 5, 7, 10, open on 3, 8; always stick in full stick;
 * open for B <= d or invalid input. */
ContactState contactLoopState(const ContactParams *p, FrictionModel model, double B, double theta);

/* The phases t in [0, pi) where contactLoopState changes (each again at t + pi: interval k + 5
 * mirrors interval k), for model exchange's event indicators: writes 5 angles [rad] and returns 5
 * in the stick-slip regime; returns 0 (no phase dependence) when open, in full stick or for
 * invalid input. Angles may coincide (Coulomb: th1 = 0, th3 = pi - th2). */
int contactLoopSwitchAngles(const ContactParams *p, FrictionModel model, double B, double angle[5]);

#endif
