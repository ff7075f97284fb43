// LAPACK's LU with partial pivoting and its solve, real and complex, and BLAS' gemv and gemm (Debian's
// liblapack and libblas, which deal.II links): the dense factorisations of the Newton matrices
// of IDA, generalised-alpha and Radau IIA (NewtonLU, condensed_lu.cc); the joints' second
// derivatives (generic_joint.cc).
#pragma once

#include <complex>

extern "C"
{
  void dgetrf_(const int *m, const int *n, double *a, const int *lda, int *ipiv, int *info);
  void dgetrs_(const char *trans, const int *n, const int *nrhs, const double *a, const int *lda, const int *ipiv,
               double *b, const int *ldb, int *info);
  void dgemm_(const char *transa, const char *transb, const int *m, const int *n, const int *k, const double *alpha,
              const double *a, const int *lda, const double *b, const int *ldb, const double *beta, double *c,
              const int *ldc);
  void dgemv_(const char *trans, const int *m, const int *n, const double *alpha, const double *a, const int *lda,
              const double *x, const int *incx, const double *beta, double *y, const int *incy);
  void zgemv_(const char *trans, const int *m, const int *n, const std::complex<double> *alpha,
              const std::complex<double> *a, const int *lda, const std::complex<double> *x, const int *incx,
              const std::complex<double> *beta, std::complex<double> *y, const int *incy);
  void zgetrf_(const int *m, const int *n, std::complex<double> *a, const int *lda, int *ipiv, int *info);
  void zgetrs_(const char *trans, const int *n, const int *nrhs, const std::complex<double> *a, const int *lda,
               const int *ipiv, std::complex<double> *b, const int *ldb, int *info);
}
