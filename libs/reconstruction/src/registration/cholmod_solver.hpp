#pragma once
/// \file
/// A small RAII wrapper of CHOLMOD for repeated solves with one sparsity
/// pattern: the symbolic analysis (fill-reducing ordering, supernodes) is
/// done once, each iteration only refactorises numerically.

#include <cholmod.h>

#include <vector>

namespace icrkit::reconstruction {

class CholmodSolver {
 public:
  CholmodSolver();
  ~CholmodSolver();
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  /// Sets the pattern of a symmetric n x n matrix by its upper triangle in
  /// compressed columns (rows sorted within each column, diagonal present)
  /// and analyses it. Values start at zero.
  void analyse(int n, const std::vector<int>& column_start, const std::vector<int>& row_index);

  /// The value array matching `row_index`, to fill before `factorise`.
  double* values();
  std::size_t nonzeros() const;
  /// Whether CHOLMOD chose a supernodal factor (large, dense-ish fill) over
  /// a simplicial one (CHOLMOD_AUTO decides from the analysis).
  bool supernodal() const { return factor_ && factor_->is_super; }
  /// Non-zeros of the factor L after the analysis.
  double factorNonzeros() const { return common_.lnz; }

  /// Numeric factorisation of the current values (LDL^T when simplicial,
  /// LL^T when supernodal); false when the matrix is not positive definite.
  bool factorise();

  /// Solves A x = rhs with the last factorisation; `x` is resized to n.
  void solve(const std::vector<double>& rhs, std::vector<double>& x);

 private:
  void release();

  cholmod_common common_;
  cholmod_sparse* matrix_ = nullptr;
  cholmod_factor* factor_ = nullptr;
  cholmod_dense* rhs_ = nullptr;
};

}  // namespace icrkit::reconstruction
