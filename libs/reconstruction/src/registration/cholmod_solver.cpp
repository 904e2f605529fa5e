#include "cholmod_solver.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace icrkit::reconstruction {
namespace {

// Unknowns up to which the factor is simplicial: a thousand poses.
constexpr int kSimplicialUpTo = 6000;

[[noreturn]] void fail(const char* what, const cholmod_common& common) {
  throw std::runtime_error(std::string("CHOLMOD ") + what + " failed (status " + std::to_string(common.status) + ")");
}

}  // namespace

CholmodSolver::CholmodSolver() {
  cholmod_start(&common_);
  // Failures are turned into exceptions or return values here; CHOLMOD's
  // own messages on stderr would only duplicate them.
  common_.print = 0;
  common_.error_handler = nullptr;
}

CholmodSolver::~CholmodSolver() {
  release();
  cholmod_finish(&common_);
}

void CholmodSolver::release() {
  if (rhs_) cholmod_free_dense(&rhs_, &common_);
  if (factor_) cholmod_free_factor(&factor_, &common_);
  if (matrix_) cholmod_free_sparse(&matrix_, &common_);
}

void CholmodSolver::analyse(int n, const std::vector<int>& column_start, const std::vector<int>& row_index) {
  release();
  const std::size_t nnz = row_index.size();
  // stype = 1: only the upper triangle is stored and read.
  matrix_ = cholmod_allocate_sparse(static_cast<std::size_t>(n), static_cast<std::size_t>(n), nnz, 1, 1, 1,
                                    CHOLMOD_REAL, &common_);
  if (!matrix_) fail("allocate_sparse", common_);
  std::copy(column_start.begin(), column_start.end(), static_cast<int*>(matrix_->p));
  std::copy(row_index.begin(), row_index.end(), static_cast<int*>(matrix_->i));
  std::fill_n(static_cast<double*>(matrix_->x), nnz, 0.0);
  // CHOLMOD's supernodal factor is made of dense BLAS blocks; with
  // Debian's reference BLAS it took twice the simplicial factor's time on
  // the graphs of 36 views (216 unknowns, 11k factor entries), and a
  // registration's graph is rarely larger than a few hundred views.
  common_.supernodal = n <= kSimplicialUpTo ? CHOLMOD_SIMPLICIAL : CHOLMOD_AUTO;
  factor_ = cholmod_analyze(matrix_, &common_);
  if (!factor_) fail("analyze", common_);
  rhs_ = cholmod_allocate_dense(static_cast<std::size_t>(n), 1, static_cast<std::size_t>(n), CHOLMOD_REAL, &common_);
  if (!rhs_) fail("allocate_dense", common_);
}

double* CholmodSolver::values() {
  return static_cast<double*>(matrix_->x);
}

std::size_t CholmodSolver::nonzeros() const {
  return matrix_ ? cholmod_nnz(matrix_, const_cast<cholmod_common*>(&common_)) : 0;
}

bool CholmodSolver::factorise() {
  // A failed (not positive definite) factorisation leaves the factor in a
  // state the next call overwrites; the symbolic part stays valid.
  const int ok = cholmod_factorize(matrix_, factor_, &common_);
  if (common_.status == CHOLMOD_NOT_POSDEF) return false;
  if (!ok || common_.status < CHOLMOD_OK) fail("factorize", common_);
  return factor_->minor == factor_->n;
}

void CholmodSolver::solve(const std::vector<double>& rhs, std::vector<double>& x) {
  std::copy(rhs.begin(), rhs.end(), static_cast<double*>(rhs_->x));
  cholmod_dense* solution = cholmod_solve(CHOLMOD_A, factor_, rhs_, &common_);
  if (!solution) fail("solve", common_);
  const double* s = static_cast<const double*>(solution->x);
  x.assign(s, s + rhs.size());
  cholmod_free_dense(&solution, &common_);
}

}  // namespace icrkit::reconstruction
