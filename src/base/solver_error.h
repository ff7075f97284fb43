// Failures of a numerical method on valid input: an eigen solver that does not converge, a
// singular factorisation, an integrator whose step size collapses. what() says where it failed
// and what to change; `main` prints it as one line and exits with status 3 (input errors: 2).
#pragma once

#include <stdexcept>

namespace flextrack
{
class SolverError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};
} // namespace flextrack
