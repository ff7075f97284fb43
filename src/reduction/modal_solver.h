// Lowest natural modes of K phi = w^2 M phi by shift-invert Lanczos: ARPACK's implicitly
// restarted Lanczos (dsaupd, mode 3) on (K - sigma M)^{-1} M, with K - sigma M factorised
// once by a sparse direct solver (SuiteSparse CHOLMOD by default; MUMPS under MPI, or where
// K - sigma M is not positive definite; KLU on request). The default shift is negative, so free
// structures (singular K) are factorised safely and their rigid-body modes come out as
// near-zero frequencies.
#pragma once

#include <base/solver_error.h> // thrown when the eigen solver fails

#include <fem/curved_beam_model.h>
#include <fem/solid_model.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/trilinos_sparse_matrix.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

namespace flextrack::reduction
{
struct ModalSettings
{
  unsigned int n_modes = 10;
  /// Shift sigma [rad^2/s^2]; NaN = automatic (minus a bending-frequency estimate squared).
  double shift = std::numeric_limits<double>::quiet_NaN();
  double tolerance = 1e-12; ///< ARPACK's relative accuracy of the Ritz values
  unsigned int max_iterations = 1000;
  /// Sparse direct solver for K - sigma M: "auto" (= "cholmod"), "cholmod", "mumps", "klu".
  std::string direct_solver = "auto";
  /// Point [m] through which the rotation axes of the modal participation pass (modes only).
  std::array<double, 3> participation_reference{};

  static void declare_parameters(dealii::ParameterHandler &prm);
  static ModalSettings parse_parameters(dealii::ParameterHandler &prm);
};

/// Frequency [Hz] of an eigenvalue w^2 [rad^2/s^2]: sign(w^2) sqrt(|w^2|) / (2 pi), so that a
/// (round-off) negative eigenvalue stays visible.
double frequency_hz(double eigenvalue);

struct Modes
{
  std::vector<double> eigenvalues;            ///< w^2 [rad^2/s^2], ascending
  std::vector<dealii::Vector<double>> shapes; ///< mass-normalised: phi^T M phi = 1
  std::vector<double> frequencies_hz() const; ///< sign(w^2) sqrt(|w^2|) / (2 pi)
  unsigned int iterations = 0;                ///< ARPACK: Lanczos restarts; block Lanczos: block steps
};

/// @p n_free: number of unconstrained dofs (at most that many finite modes exist);
/// @p shift: sigma, must not be an eigenvalue; @p direct_solver: "cholmod",
/// "mumps" or "klu".
Modes lowest_modes(const dealii::TrilinosWrappers::SparseMatrix &K,
                   const dealii::TrilinosWrappers::SparseMatrix &M, unsigned int n_free,
                   const ModalSettings &settings, double shift, const std::string &direct_solver);

class SparseFactorization;
/// The same with a factorisation of K - shift M that the caller keeps (e.g. for static solves
/// with the same matrix when shift = 0).
Modes lowest_modes(const dealii::TrilinosWrappers::SparseMatrix &K,
                   const dealii::TrilinosWrappers::SparseMatrix &M, unsigned int n_free,
                   const ModalSettings &settings, double shift, const SparseFactorization &factorization);

/// Automatic shift for an arm: minus the squared first clamped-free bending frequency of a
/// straight beam with the arm's length and section, the scale of the lowest modes [rad^2/s^2].
double automatic_shift(const fem::Arm &arm);

/// Lowest modes of an arm's FE model, with the settings' shift or the automatic one.
Modes lowest_modes(const fem::CurvedBeamModel &model, const ModalSettings &settings);

/// Automatic shift for any structure: -1e-6 max_i K_ii / M_ii, a small fraction of the
/// spectrum's upper end, negative so that free bodies are factorisable [rad^2/s^2].
double automatic_shift(const dealii::TrilinosWrappers::SparseMatrix &K,
                       const dealii::TrilinosWrappers::SparseMatrix &M);

/// Lowest modes of any K, M with the settings' shift (or the automatic one for K, M) and direct
/// solver ("auto" = CHOLMOD).
Modes lowest_modes(const dealii::TrilinosWrappers::SparseMatrix &K,
                   const dealii::TrilinosWrappers::SparseMatrix &M, unsigned int n_free,
                   const ModalSettings &settings);

/// Lowest modes of a solid body's FE model.
Modes lowest_modes(const fem::SolidModel &model, const ModalSettings &settings);

/// The same in the least memory (one process, the Cholesky factor, a negative shift: the
/// default): K and M are released once the factorisation has its copy of K - sigma M, so that
/// they are not held beside the factor, and the Lanczos iteration applies M cell by cell
/// (model.mass_operator()). The model's matrices are empty afterwards. Otherwise (MPI, another
/// solver, a shift of 0 or more) as lowest_modes(model, settings), keeping them.
Modes lowest_modes_releasing_matrices(fem::SolidModel &model, const ModalSettings &settings);
} // namespace flextrack::reduction
