/* Gauss-Legendre quadrature nodes and weights on [-1, 1] (the blade's Galerkin integrals, eq. 24
 * and docs/model.md s.2a). */
#ifndef GAUSS_LEGENDRE_H
#define GAUSS_LEGENDRE_H

#define GAUSS_LEGENDRE_NODES 16

/* The 16 nodes x and weights w by Newton on the Legendre recurrence (stack only). */
void gaussLegendre16(double x[GAUSS_LEGENDRE_NODES], double w[GAUSS_LEGENDRE_NODES]);

#endif
