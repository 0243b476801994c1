/* LAPACK opened when a command first solves a system (core.h,
 * jnd_lazy_symbol): the LAPACKE functions linalg.c and csf_fit.c call, with
 * LAPACKE's prototypes, each forwarding to the library's own. Built where
 * CMake read LAPACKE's soname (JND_LAPACKE_SONAME); elsewhere jnd links
 * LAPACKE as before and this file is empty. Where the library cannot be
 * opened, a call fails as LAPACKE reports running out of memory
 * (LAPACK_WORK_MEMORY_ERROR), which every caller treats as a failure. */
#ifdef JND_LAPACKE_SONAME
#include <lapacke.h>

#include "core/core.h"

static jnd_lazy_lib lapacke = {JND_LAPACKE_SONAME, NULL};

lapack_int LAPACKE_dposv(int matrix_layout, char uplo, lapack_int n, lapack_int nrhs, double *a, lapack_int lda,
                         double *b, lapack_int ldb) {
  JND_LAZY_FN(&lapacke, lapack_int (*)(int, char, lapack_int, lapack_int, double *, lapack_int, double *, lapack_int),
             LAPACKE_dposv);
  return f ? f(matrix_layout, uplo, n, nrhs, a, lda, b, ldb) : LAPACK_WORK_MEMORY_ERROR;
}

lapack_int LAPACKE_dpotrf(int matrix_layout, char uplo, lapack_int n, double *a, lapack_int lda) {
  JND_LAZY_FN(&lapacke, lapack_int (*)(int, char, lapack_int, double *, lapack_int), LAPACKE_dpotrf);
  return f ? f(matrix_layout, uplo, n, a, lda) : LAPACK_WORK_MEMORY_ERROR;
}

lapack_int LAPACKE_dpotri(int matrix_layout, char uplo, lapack_int n, double *a, lapack_int lda) {
  JND_LAZY_FN(&lapacke, lapack_int (*)(int, char, lapack_int, double *, lapack_int), LAPACKE_dpotri);
  return f ? f(matrix_layout, uplo, n, a, lda) : LAPACK_WORK_MEMORY_ERROR;
}

lapack_int LAPACKE_dsyev(int matrix_layout, char jobz, char uplo, lapack_int n, double *a, lapack_int lda,
                         double *w) {
  JND_LAZY_FN(&lapacke, lapack_int (*)(int, char, char, lapack_int, double *, lapack_int, double *), LAPACKE_dsyev);
  return f ? f(matrix_layout, jobz, uplo, n, a, lda, w) : LAPACK_WORK_MEMORY_ERROR;
}
#else
typedef int jnd_lapacke_linked; /* ISO C wants a declaration in every file */
#endif
