/* Gauss-Legendre nodes and weights (see gauss_legendre.h). */
#include "physics/gauss_legendre.h"

#include <math.h>

void gaussLegendre16(double x[GAUSS_LEGENDRE_NODES], double w[GAUSS_LEGENDRE_NODES])
{
    const int n = GAUSS_LEGENDRE_NODES;
    const double pi = 3.14159265358979323846;
    int i, it, j;
    for (i = 0; i < n; ++i) {
        double z = cos(pi * ((double)i + 0.75) / ((double)n + 0.5));
        double dp = 1.0;
        for (it = 0; it < 100; ++it) {
            double p0 = 1.0, p1 = z, dz;
            for (j = 2; j <= n; ++j) {
                double p2 = ((2.0 * j - 1.0) * z * p1 - (j - 1.0) * p0) / (double)j;
                p0 = p1;
                p1 = p2;
            }
            dp = (double)n * (z * p1 - p0) / (z * z - 1.0);
            dz = p1 / dp;
            z -= dz;
            if (fabs(dz) <= 1e-17) break;
        }
        x[i] = z;
        w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
}
