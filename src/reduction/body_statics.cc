#include <base/input_error.h>
#include <reduction/body_statics.h>
#include <reduction/static_solver.h>

#include <deal.II/lac/lapack_full_matrix.h>

#include <algorithm>
#include <cmath>

namespace flextrack::reduction
{
using dealii::Tensor;
using dealii::Vector;

namespace
{
double difference(const PlaceValues &full, const PlaceValues &reduced, const unsigned int c0)
{
  double diff = 0, size = 0;
  for (unsigned int c = c0; c < c0 + 3; ++c)
    {
      diff += (reduced[c] - full[c]) * (reduced[c] - full[c]);
      size += full[c] * full[c];
    }
  return size > 0 ? std::sqrt(diff / size) : std::sqrt(diff);
}
} // namespace

double BodyStaticCase::displacement_difference(const unsigned int k) const { return difference(full[k], reduced[k], 0); }
double BodyStaticCase::rotation_difference(const unsigned int k) const { return difference(full[k], reduced[k], 3); }

BodyStatics::BodyStatics(const fem::BodyModel &model, const ReducedBasis &basis, const ReductionSettings &settings)
  : model(model), basis(basis)
{
  if (!model.is_supported())
    {
      if (!reduction_method(settings.method).fixed_interface || model.interfaces().empty())
        throw InputError("Reduction/Method", "a free body has a static solution only when it is held: use "
                                             "'craig bampton' with an interface (the first interface, the body "
                                             "frame, is held) or add supports");
      // The body frame: every vector of the Craig-Bampton basis is zero there (component_modes.h).
      for (const auto d : model.interfaces()[0].dofs) held.add_line(d);
    }
  held.close();
  full_solver = std::make_unique<StaticSolver>(model.stiffness_matrix(), held);
}

BodyStatics::~BodyStatics() = default;

Vector<double> BodyStatics::load_vector(const fem::LoadCase &load_case) const
{
  Vector<double> f_full(model.n_full_dofs());
  // Arms: the consistent nodal loads of each arm's share.
  for (unsigned int a = 0; a < model.n_arms(); ++a)
    {
      const auto &arm = model.arm_model(a);
      Vector<double> f_arm(arm.n_dofs());
      for (const auto &p : load_case.point_forces)
        if (p.point.empty() && p.arm == a) arm.add_point_load(p.s, p.value, Tensor<1, 3>(), f_arm);
      for (const auto &p : load_case.point_moments)
        if (p.point.empty() && p.arm == a) arm.add_point_load(p.s, Tensor<1, 3>(), p.value, f_arm);
      for (const auto &l : load_case.line_loads)
        if (l.arm == a) arm.add_line_load(l.s0, l.s1, l.q, f_arm);
      for (unsigned int i = 0; i < f_arm.size(); ++i) f_full[model.arm_offset(a) + i] += f_arm[i];
    }
  // The solid: node set forces (its dofs come first in the full numbering, body_model.h).
  if (model.solid_model() &&
      (!load_case.node_set_forces.empty() || !load_case.node_set_moments.empty() || !load_case.pressures.empty() ||
       !load_case.node_forces.empty()))
    {
      fem::LoadCase sets;
      sets.name = load_case.name;
      sets.node_set_forces = load_case.node_set_forces;
      sets.node_set_moments = load_case.node_set_moments;
      sets.pressures = load_case.pressures;
      sets.node_forces = load_case.node_forces;
      const Vector<double> f_solid = model.solid_model()->load_vector(sets);
      for (unsigned int i = 0; i < f_solid.size(); ++i) f_full[i] += f_solid[i];
    }
  // Gravity: M_full times the rigid translation g (consistent masses and point masses).
  if (load_case.gravity.norm() > 0)
    {
      Vector<double> g(model.n_full_dofs()), weight;
      for (const auto &n : model.full_nodes())
        for (unsigned int d = 0; d < 3; ++d) g[n.u[d]] = load_case.gravity[d];
      model.full_mass_vmult(weight, g);
      f_full += weight;
    }
  // Interfaces and output points: forces and moments on their six dofs.
  const auto at_point = [&](const fem::ArmPointLoad &p, const unsigned int c0) {
    for (const auto &o : model.output_points())
      if (o.name == p.point)
        for (unsigned int c = 0; c < 3; ++c) f_full[o.full_dofs[c0 + c]] += p.value[c];
  };
  for (const auto &p : load_case.point_forces) at_point(p, 0);
  for (const auto &p : load_case.point_moments) at_point(p, 3);
  Vector<double> f = model.condense(f_full);
  const auto at_interface = [&](const fem::ArmPointLoad &p, const unsigned int c0) {
    for (const auto &i : model.interfaces())
      if (i.name == p.point)
        for (unsigned int c = 0; c < 3; ++c) f[i.dofs[c0 + c]] += p.value[c];
  };
  for (const auto &p : load_case.point_forces) at_interface(p, 0);
  for (const auto &p : load_case.point_moments) at_interface(p, 3);
  return f;
}

PlaceValues BodyStatics::values_at(const fem::LoadPoint &place, const Vector<double> &y, const Vector<double> &x) const
{
  PlaceValues v{};
  if (place.point.empty())
    {
      const auto &arm = model.arm_model(place.arm);
      Vector<double> u(arm.n_dofs());
      for (unsigned int i = 0; i < u.size(); ++i) u[i] = x[model.arm_offset(place.arm) + i];
      const auto d = arm.displacement_at(place.s, u), theta = arm.rotation_at(place.s, u);
      for (unsigned int c = 0; c < 3; ++c)
        {
          v[c] = d[c];
          v[3 + c] = theta[c];
        }
      return v;
    }
  for (const auto &i : model.interfaces())
    if (i.name == place.point)
      {
        for (unsigned int c = 0; c < 6; ++c) v[c] = y[i.dofs[c]];
        return v;
      }
  for (const auto &o : model.output_points())
    if (o.name == place.point)
      for (unsigned int c = 0; c < 6; ++c) v[c] = x[o.full_dofs[c]];
  return v;
}

Vector<double> BodyStatics::reduced_solution(const Vector<double> &f, double &strain_energy) const
{
  const unsigned int n = basis.modes.size();
  Vector<double> q(n);
  for (unsigned int a = 0; a < n; ++a) q[a] = basis.modes[a] * f;
  dealii::LAPACKFullMatrix<double> K(n);
  K = basis.stiffness;
  // The reduced stiffness is symmetric positive definite; deal.II's debug build checks that the
  // property is declared before a Cholesky factorisation (the release build does not).
  K.set_property(dealii::LAPACKSupport::symmetric);
  K.compute_cholesky_factorization();
  Vector<double> eta = q;
  K.solve(eta);
  strain_energy = 0.5 * (eta * q);
  Vector<double> u(f.size());
  for (unsigned int a = 0; a < n; ++a) u.add(eta[a], basis.modes[a]);
  return u;
}

std::vector<BodyStaticCase> BodyStatics::solve(const std::vector<fem::LoadCase> &cases,
                                               const std::vector<fem::LoadPoint> &places) const
{
  std::vector<Vector<double>> loads;
  for (const auto &c : cases) loads.push_back(load_vector(c));
  const auto full = full_solver->solve(loads);
  std::vector<BodyStaticCase> results(cases.size());
  for (std::size_t i = 0; i < cases.size(); ++i)
    {
      auto &r = results[i];
      r.name = cases[i].name;
      r.strain_energy_full = full[i].strain_energy;
      r.residual = full[i].residual;
      const Vector<double> y_r = reduced_solution(loads[i], r.strain_energy_reduced);
      const Vector<double> x = model.expand(full[i].u), x_r = model.expand(y_r);
      for (const auto &p : places)
        {
          r.full.push_back(values_at(p, full[i].u, x));
          r.reduced.push_back(values_at(p, y_r, x_r));
        }
    }
  return results;
}

std::vector<fem::LoadPoint> default_body_places(const fem::Body &body, const std::vector<fem::LoadCase> &cases)
{
  std::vector<fem::LoadPoint> places;
  const auto add = [&](const fem::LoadPoint &p) {
    const bool seen = std::any_of(places.begin(), places.end(), [&](const fem::LoadPoint &q) {
      return q.point == p.point && (!p.point.empty() || (q.arm == p.arm && q.s == p.s));
    });
    if (!seen) places.push_back(p);
  };
  for (const auto &i : body.interfaces)
    {
      fem::LoadPoint p;
      p.point = p.label = i.name;
      add(p);
    }
  for (const auto &o : body.output_points)
    {
      fem::LoadPoint p;
      p.point = p.label = o.name;
      add(p);
    }
  for (const auto &c : cases)
    {
      for (const auto &p : c.point_forces) add(p);
      for (const auto &p : c.point_moments) add(p);
    }
  return places;
}
} // namespace flextrack::reduction
