/* sym3.h: the eigenvector of a 3 x 3 symmetric matrix's smallest
 * eigenvalue: the direction most nearly perpendicular to the vectors whose
 * outer products it sums (an edge's direction from the planes of its
 * views, a plane's normal from points on it). */
#ifndef WS_BASE_SYM3_H
#define WS_BASE_SYM3_H

/* t: the unit eigenvector of the smallest eigenvalue of the symmetric m
 * given as (xx, yy, zz, xy, xz, yz), by cyclic Jacobi rotations. */
void ws_sym3_least_eigenvector(const double m[6], double t[3]);

#endif
