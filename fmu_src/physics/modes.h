/* The blade as m bending modes (paper eq. 19-21 with m terms, docs/model.md s.2a): the first m
 * exact modes of the non-rotating cantilever with the tip mass, each scaled to phi_i(l) = 1, and
 * the consistent (energy) Galerkin matrices in these modal coordinates. Pure functions, no FMI
 * types, no allocation. */
#ifndef MODES_H
#define MODES_H

#include "physics/blade.h"

#define MODES_MAX 6 /* largest number of modes */

typedef struct {
    int m;                                  /* number of modes */
    double lambdaL[MODES_MAX];              /* lambda_i l, the first m roots of eq. 21 [-] */
    double M[MODES_MAX][MODES_MAX];         /* rho A int phi_i phi_j + m0 [kg] */
    double C[MODES_MAX][MODES_MAX];         /* c int phi_i phi_j [N s/m] */
    double Kstatic[MODES_MAX][MODES_MAX];   /* EI int phi_i'' phi_j'' [N/m] */
    double Komega2[MODES_MAX][MODES_MAX];   /* int (rho A (l^2 - x^2)/2 + m0 l) phi_i' phi_j' [kg] (eq. 16) */
    double load[MODES_MAX];                 /* int phi_i dx: generalized load per unit f_w [m] */
    double curvature0[MODES_MAX];           /* phi_i''(0): root curvature per unit q_i [1/m^2] */
} ModalReduction;

/* Fills *out for m in [1, MODES_MAX] modes. Returns 0 on success, nonzero for invalid parameters
 * or a failed root search (out is then unspecified). */
int modesReduce(const BladeParams *p, int m, ModalReduction *out);

/* phi''(0) / phi(l) of the eq. 20 shape with root lambda l = lambdaL on a blade of length l:
 * the root curvature per unit tip displacement [1/m^2]. */
double modesRootCurvature(double lambdaL, double l);

/* The m eigenvalues (ascending) of the symmetric generalized problem K x = w^2 M x (M positive
 * definite), by Cholesky and cyclic Jacobi. Returns 0, or nonzero if M is not positive definite. */
int modesEigenvalues(int m, const double *M, const double *K,
                     double lambda[MODES_MAX]);

/* Matrices are passed as &A[0][0] of a double[MODES_MAX][MODES_MAX] (row stride MODES_MAX).
 * inv = M^-1 for a symmetric positive definite M (Cholesky). Returns 0, or nonzero. */
int modesInverse(int m, const double *M, double inv[MODES_MAX][MODES_MAX]);

#endif
