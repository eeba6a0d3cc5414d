/* sym3.c: the least eigenvector of a 3 x 3 symmetric matrix (see sym3.h). */
#include <math.h>
#include "base/sym3.h"

void ws_sym3_least_eigenvector(const double m[6], double t[3]) {
    double a[3][3] = {{m[0], m[3], m[4]}, {m[3], m[1], m[5]}, {m[4], m[5], m[2]}};
    double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int sweep = 0; sweep < 8; sweep++)
        for (int p = 0; p < 2; p++)
            for (int q = p + 1; q < 3; q++) {
                if (!(fabs(a[p][q]) > 1e-15 * (fabs(a[p][p]) + fabs(a[q][q])))) continue;
                double theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
                double tt = (theta >= 0 ? 1 : -1) / (fabs(theta) + sqrt(theta * theta + 1));
                double c = 1 / sqrt(tt * tt + 1), s = tt * c;
                for (int k = 0; k < 3; k++) {
                    double akp = a[k][p], akq = a[k][q];
                    a[k][p] = c * akp - s * akq, a[k][q] = s * akp + c * akq;
                }
                for (int k = 0; k < 3; k++) {
                    double apk = a[p][k], aqk = a[q][k];
                    a[p][k] = c * apk - s * aqk, a[q][k] = s * apk + c * aqk;
                }
                for (int k = 0; k < 3; k++) {
                    double vkp = v[k][p], vkq = v[k][q];
                    v[k][p] = c * vkp - s * vkq, v[k][q] = s * vkp + c * vkq;
                }
            }
    int best = 0;
    for (int k = 1; k < 3; k++)
        if (a[k][k] < a[best][best]) best = k;
    for (int k = 0; k < 3; k++) t[k] = v[k][best];
}
