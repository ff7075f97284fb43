// A steel solid on a mesh, clamped at one node set: the body of the solid tests.
#pragma once

#include <fem/solid.h>

#include <memory>
#include <string>

namespace test_support
{
/// E = 2.1e11 Pa, nu = 0.3, rho = 7850 kg/m^3; the nodes of @p clamped_set held in x, y, z.
inline flextrack::fem::Solid steel_solid(std::shared_ptr<const flextrack::fem::SolidMesh> mesh, const std::string &clamped_set = "FIX")
{
  flextrack::fem::Solid s;
  s.mesh = std::move(mesh);
  s.material.youngs_modulus = 2.1e11;
  s.material.poisson_ratio = 0.3;
  s.material.shear_modulus = 2.1e11 / 2.6;
  s.material.density = 7850;
  flextrack::fem::SolidSupport clamp;
  clamp.node_set = clamped_set;
  s.supports = {clamp};
  return s;
}
} // namespace test_support
