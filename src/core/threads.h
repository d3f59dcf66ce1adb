/* Threads a run may use (OpenMP when the build has it). */
#ifndef HSBD_CORE_THREADS_H
#define HSBD_CORE_THREADS_H

/* The cores this process may use (OMP_NUM_THREADS, else the CPU affinity mask); 1 in a
 * build without OpenMP. */
int hsbd_threads_available(void);

#endif
