// The generic joint: constraint rows, their gradients w.r.t. the markers' positions and axes,
// and the chain rule through the marker Jacobians (see generic_joint.h).
#include <base/input_error.h>
#include <multibody/generic_joint.h>

#include <algorithm>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
const char *axis_name[] = {"x", "y", "z"};
}

GenericJoint::GenericJoint(std::string name, std::unique_ptr<Marker> follower, std::unique_ptr<Marker> base,
                           const JointMask &mask, const DriverKind driver_kind,
                           std::shared_ptr<const geometry::Expression> driver_law)
  : Joint(std::move(name)), driver(driver_kind), law(std::move(driver_law))
{
  markers[0] = std::move(follower);
  markers[1] = std::move(base);
  if (driver == DriverKind::angle && mask.rotation[2])
    throw InputError("Joint " + this->name() + "/Driver", "an angle driver needs the rotation about z to be free");
  if (driver == DriverKind::displacement && mask.translation[2])
    throw InputError("Joint " + this->name() + "/Driver", "a displacement driver needs the translation along z to be free");
  if (driver != DriverKind::none && !law) throw InputError("Joint " + this->name() + "/Driver", "needs an expression of t");
  if (driver == DriverKind::own_coordinate && markers[1]->n_own_coordinates() != 1)
    throw InputError("Joint " + this->name() + "/Driver", "only a joint on a track can drive the arc length");
  for (unsigned int a = 0; a < 3; ++a)
    if (mask.translation[a]) rows.push_back({RowKind::translation, a, 0, false, std::string("translation along ") + axis_name[a], nullptr});
  if (driver == DriverKind::displacement)
    rows.push_back({RowKind::translation, 2, 0, true, "driven displacement along z", nullptr});

  const unsigned int n_locked = mask.rotation[0] + mask.rotation[1] + mask.rotation[2];
  if (n_locked == 3)
    {
      rows.push_back({RowKind::rotation, 2, 0, false, "rotation about y (e1_z . e2_x)", nullptr});
      rows.push_back({RowKind::rotation, 2, 1, false, "rotation about x (e1_z . e2_y)", nullptr});
      rows.push_back({RowKind::rotation, 0, 1, false, "rotation about z (e1_x . e2_y)", nullptr});
    }
  else if (n_locked == 2)
    {
      const unsigned int c = !mask.rotation[0] ? 0 : !mask.rotation[1] ? 1 : 2, a = (c + 1) % 3, b = (c + 2) % 3;
      rows.push_back({RowKind::rotation, c, a, false,
                      std::string("rotation about ") + axis_name[b] + " (e1_" + axis_name[c] + " . e2_" + axis_name[a] + ")", nullptr});
      rows.push_back({RowKind::rotation, c, b, false,
                      std::string("rotation about ") + axis_name[a] + " (e1_" + axis_name[c] + " . e2_" + axis_name[b] + ")", nullptr});
    }
  else if (n_locked == 1)
    {
      const unsigned int c = mask.rotation[0] ? 0 : mask.rotation[1] ? 1 : 2, a = (c + 1) % 3, b = (c + 2) % 3;
      rows.push_back({RowKind::rotation, a, b, false,
                      std::string("rotation about ") + axis_name[c] + " (e1_" + axis_name[a] + " . e2_" + axis_name[b] + ")", nullptr});
    }
  if (driver == DriverKind::angle) rows.push_back({RowKind::angle, 0, 0, false, "driven angle about z", nullptr});
  if (driver == DriverKind::own_coordinate) add_own_driver(markers[0]->n_own_coordinates(), law, "driven arc length s");
}

void GenericJoint::add_own_driver(const unsigned int index, std::shared_ptr<const geometry::Expression> own_law,
                                  const std::string &row_name)
{
  Assert(index < n_own_coordinates() && own_law, ExcMessage("no such own coordinate, or no law"));
  rows.push_back({RowKind::own, index, 0, true, row_name, std::move(own_law)});
}

unsigned int GenericJoint::n_own_coordinates() const
{
  return markers[0]->n_own_coordinates() + markers[1]->n_own_coordinates();
}

void GenericJoint::initial_own_coordinates(double *q, double *v) const
{
  const unsigned int n0 = markers[0]->n_own_coordinates();
  if (n0) markers[0]->initial_own_coordinates(q, v);
  if (markers[1]->n_own_coordinates()) markers[1]->initial_own_coordinates(q + n0, v + n0);
}

const double *GenericJoint::own_of(const unsigned int m, const double *own_q) const
{
  if (!markers[m]->n_own_coordinates()) return nullptr;
  return own_q + (m == 0 ? 0 : markers[0]->n_own_coordinates());
}

void GenericJoint::evaluate_rows(const std::vector<const double *> &q, const double *own_q, const double t, Local &l,
                                 Vector<double> &phi, Vector<double> &phi_t) const
{
  for (unsigned int m = 0; m < 2; ++m) markers[m]->evaluate(q[m], own_of(m, own_q), l.k[m]);
  const MarkerKinematics &ki = l.k[0], &kj = l.k[1];
  const Vector3 d = ki.position - kj.position;
  phi.reinit(rows.size());
  phi_t.reinit(rows.size());
  l.grad.assign(rows.size(), Gradient());
  geometry::Dual s; // a drive law's value and rate (Phi and Phi_t need no more)
  if (law) s = law->dual(t);
  for (unsigned int r = 0; r < rows.size(); ++r)
    {
      const Row &row = rows[r];
      Gradient &g = l.grad[r];
      switch (row.kind)
        {
          case RowKind::translation:
            phi[r] = kj.axes[row.a] * d - (row.driven ? s.value() : 0.0);
            phi_t[r] = row.driven ? -s.derivative(1) : 0.0;
            g[0] = kj.axes[row.a];
            g[4] = -kj.axes[row.a];
            g[5 + row.a] = d;
            break;
          case RowKind::rotation:
            phi[r] = ki.axes[row.a] * kj.axes[row.b];
            g[1 + row.a] = kj.axes[row.b];
            g[5 + row.b] = ki.axes[row.a];
            break;
          case RowKind::angle:
            {
              const double c = std::cos(s.value()), sn = std::sin(s.value());
              const Vector3 target = -sn * kj.axes[0] + c * kj.axes[1];
              phi[r] = ki.axes[0] * target;
              phi_t[r] = -(ki.axes[0] * (c * kj.axes[0] + sn * kj.axes[1])) * s.derivative(1);
              g[1] = target;
              g[5] = -sn * ki.axes[0];
              g[6] = c * ki.axes[0];
              break;
            }
          case RowKind::own: // s - s(t): no marker gradient; its B_own entry is set in evaluate()
            {
              const geometry::Dual s_d = row.own_law->dual(t);
              phi[r] = own_q[row.a] - s_d.value();
              phi_t[r] = -s_d.derivative(1);
              break;
            }
        }
    }
}

void GenericJoint::driver_rates(const std::vector<const double *> &q, const double *own_q, const double t,
                                Vector<double> &phi_t) const
{
  const bool angle = std::any_of(rows.begin(), rows.end(), [](const Row &r) { return r.kind == RowKind::angle; });
  if (angle)
    {
      // The angle row's Phi_t needs both markers' axes: evaluate the rows as a whole.
      thread_local Local l;
      thread_local Vector<double> phi;
      evaluate_rows(q, own_q, t, l, phi, phi_t);
      return;
    }
  phi_t.reinit(rows.size());
  for (unsigned int r = 0; r < rows.size(); ++r)
    {
      const Row &row = rows[r];
      if (row.kind == RowKind::translation && row.driven) phi_t[r] = -law->dual(t).derivative(1);
      else if (row.kind == RowKind::own) phi_t[r] = -row.own_law->dual(t).derivative(1);
    }
}

void GenericJoint::evaluate(const std::vector<const double *> &q, const double *own_q, const double t,
                            JointEvaluation &e) const
{
  // Reused between calls (the residual evaluates every joint several times per step): its
  // matrices keep their storage, which saves about 10 heap allocations per call. Nothing
  // evaluated from here evaluates a joint again, and each thread has its own.
  thread_local Local l;
  evaluate_rows(q, own_q, t, l, e.phi, e.phi_t);
  e.B.resize(2);
  e.B_own.reinit(rows.size(), n_own_coordinates());
  unsigned int own_column = 0;
  for (unsigned int m = 0; m < 2; ++m)
    {
      // The marker's columns: its body's velocities, then its own coordinates (into B_own).
      const MarkerKinematics &k = l.k[m];
      const unsigned int nv = markers[m]->body().n_v(), n_own = markers[m]->n_own_coordinates();
      e.B[m].reinit(rows.size(), nv);
      for (unsigned int r = 0; r < rows.size(); ++r)
        {
          // A row depends on few of the marker's four vectors (a rotation row on one axis of
          // each marker, a translation row on no axis of the first): zero gradients are skipped,
          // the sums over the others are taken in the same order as before.
          const Gradient &g = l.grad[r];
          const auto nonzero = [](const Vector3 &w) { return w[0] != 0 || w[1] != 0 || w[2] != 0; };
          const bool position = nonzero(g[4 * m]);
          std::array<bool, 3> axis;
          for (unsigned int x = 0; x < 3; ++x) axis[x] = nonzero(g[4 * m + 1 + x]);
          for (unsigned int c = 0; c < nv + n_own; ++c)
            {
              double v = 0;
              for (unsigned int a = 0; a < 3; ++a)
                {
                  if (position) v += g[4 * m][a] * k.J_position(a, c);
                  for (unsigned int x = 0; x < 3; ++x)
                    if (axis[x]) v += g[4 * m + 1 + x][a] * k.J_axes[x](a, c);
                }
              (c < nv ? e.B[m](r, c) : e.B_own(r, own_column + c - nv)) = v;
            }
        }
      own_column += n_own;
    }
  for (unsigned int r = 0; r < rows.size(); ++r)
    if (rows[r].kind == RowKind::own) e.B_own(r, rows[r].a) = 1;
}

void GenericJoint::reaction(const std::vector<const double *> &q, const double *own_q, const double t,
                            const double *lambda, Vector3 &force, Vector3 &torque) const
{
  std::array<Vector3, 3> unused;
  reaction(q, own_q, t, lambda, force, torque, unused);
}

void GenericJoint::reaction(const std::vector<const double *> &q, const double *own_q, const double t,
                            const double *lambda, Vector3 &force, Vector3 &torque, std::array<Vector3, 3> &base_axes) const
{
  // Generalised constraint force -B^T lambda = J_r^T F + J_w^T T at the follower marker, with
  // F = -sum lambda dPhi/dr_i and T = -sum lambda sum_a e_a x dPhi/de_a (e_a' = omega x e_a).
  Local l;
  Vector<double> phi, phi_t;
  evaluate_rows(q, own_q, t, l, phi, phi_t);
  force = torque = Vector3();
  for (unsigned int r = 0; r < rows.size(); ++r)
    {
      force -= lambda[r] * l.grad[r][0];
      for (unsigned int a = 0; a < 3; ++a) torque -= lambda[r] * cross_product_3d(l.k[0].axes[a], l.grad[r][1 + a]);
    }
  base_axes = l.k[1].axes;
}
} // namespace flextrack::multibody
