/* Galerkin reduction of the rotating cantilever with a tip mass (paper eq. 19-27, docs/model.md s.2).
 * Pure functions, no FMI types. */
#ifndef BLADE_H
#define BLADE_H

typedef enum { FormulationPrinted = 1, FormulationConsistent = 2 } Formulation;

typedef struct {
    double EI;  /* flexural stiffness [N m^2] */
    double rho; /* density [kg/m^3] */
    double A;   /* cross-section area [m^2] */
    double l;   /* blade length [m] */
    double c;   /* distributed viscous damping [N s/m^2] */
    double m0;  /* tip (shroud) mass [kg] */
} BladeParams;

/* BladeParams from six values in the order EI, rho, A, l, c, m0 (the models' parameter slots). */
BladeParams bladeParamsOf(const double v[6]);

typedef struct {
    double lambdaL;   /* lambda_1 l, first root of eq. 21 [-] */
    double U1;        /* int phi^2 dx [m] (eq. 24) */
    double U2;        /* int phi phi'''' dx = lambda^4 U1 [1/m^3] (docs/model.md fixes eq. 24) */
    double U3;        /* int x phi phi' dx [-] */
    double U4;        /* int phi'' phi (l^2 - x^2) dx [m^2] */
    double U5;        /* int phi phi'' dx [1/m] */
    double intPhi;    /* int phi dx [m] (u1 = F_w0 intPhi) */
    double u2;        /* phi(l) [-] */
    double M;         /* generalized mass [kg] */
    double C0;        /* generalized viscous damping [N s/m] */
    double K0static;  /* K0 at Omega = 0 [N/m] */
    double K0omega2;  /* dK0/d(Omega^2) [kg]: K0(Omega) = K0static + K0omega2 Omega^2 */
    double loadGain;  /* G: generalized load per unit f_w, intPhi/u2 [m] */
} BladeReduction;

/* Fills *out for the given formulation. Returns 0 on success, nonzero if the parameters are
 * invalid or the root/quadrature fails (out is then unspecified). */
int bladeReduce(const BladeParams *p, Formulation formulation, BladeReduction *out);

/* The last reduction and what it was made from (zeroed: empty). */
typedef struct {
    int valid;
    Formulation formulation;
    BladeParams params;
    BladeReduction reduction;
} BladeReductionCache;

/* bladeReduce, or the cache's reduction if p and the formulation are bit-identical to its own (a
 * master that resets and re-initialises an instance with the same blade, e.g. shooting, skips
 * eq. 19-26: ~90 us); the cache is refilled on success, emptied on failure. */
int bladeReduceReusing(BladeReductionCache *c, const BladeParams *p, Formulation formulation, BladeReduction *out);

/* K0(Omega) [N/m] for Omega [rad/s]. */
double bladeK0(const BladeReduction *r, double Omega);

#endif
