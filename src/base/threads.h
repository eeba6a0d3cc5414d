/* threads.h: one thread count for everything that runs in parallel
 * (OpenMP loops and OpenBLAS's GEMMs), so that a run is reproducible: the
 * same seed and thread count give the same bits. */
#ifndef WS_THREADS_H
#define WS_THREADS_H

/* n = 0: one thread per core. */
void ws_threads_set(int n);
int ws_threads_get(void);

#endif
