// Probes (probe.h).
#include <base/input_error.h>
#include <base/names.h>
#include <base/text.h>
#include <multibody/probe.h>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
/// Index of @p body in @p system (bodies are few; a probe is evaluated once per output row).
unsigned int index_of(const System &system, const Body &body)
{
  for (unsigned int b = 0; b < system.n_bodies(); ++b)
    if (&system.body(b) == &body) return b;
  AssertThrow(false, ExcMessage("a probe's body is not in the system"));
  return 0;
}

Matrix3 identity()
{
  Matrix3 I;
  for (unsigned int a = 0; a < 3; ++a) I[a][a] = 1;
  return I;
}
} // namespace

Probe::Probe(std::string name, std::unique_ptr<Marker> m, const FloatingBody *f)
  : probe_name(std::move(name)), marker(std::move(m)), frame(f)
{}

std::string Probe::frame_name() const { return frame ? frame->name() : "global"; }

ProbeValues Probe::evaluate(const System &system, const Vector<double> &y) const
{
  const unsigned int b = index_of(system, marker->body());
  MarkerKinematics k;
  marker->evaluate(system.q_of(b, y), nullptr, k);
  ProbeValues values;
  values.position = k.position;
  if (const unsigned int nv = marker->body().n_v(); nv > 0)
    {
      const double *v = system.v_of(b, y);
      for (unsigned int a = 0; a < 3; ++a)
        for (unsigned int j = 0; j < nv; ++j) values.velocity[a] += k.J_position(a, j) * v[j];
    }
  if (!frame) return values;
  const unsigned int f = index_of(system, *frame);
  const FrameState F = frame->frame(system.q_of(f, y), system.v_of(f, y));
  const Matrix3 At = transpose(F.A);
  const Vector3 x = At * (values.position - F.R);
  values.velocity = At * (values.velocity - F.R_dot) - cross_product_3d(F.omega, x);
  values.position = x;
  return values;
}

void Probe::declare_parameters(ParameterHandler &prm)
{
  prm.declare_entry("Body", "", Patterns::Anything(), "Name of the body the probe sits on (or 'ground') [-].");
  prm.declare_entry("Position", "0, 0, 0", Patterns::Anything(),
                    "The probed point, global, at the initial configuration [m] (ignored at an interface).");
  prm.declare_entry("Interface", "", Patterns::Anything(),
                    "Interface or output point of a flexible body the probe sits on (it moves with that "
                    "point's mode shapes); empty: the point 'Position' fixed in the body frame [-].");
  prm.declare_entry("Frame", "global", Patterns::Anything(),
                    "Axes of the output: 'global', or the name of a body: position [m] and velocity [m/s] "
                    "relative to that body's floating frame, in its axes [-].");
}

std::unique_ptr<Probe> Probe::create(const std::string &name, ParameterHandler &prm, const BodyLookup &bodies)
{
  const std::string prefix = "Probe " + name + "/";
  if (!base::is_valid_name(name))
    throw InputError("Probe " + base::printable_excerpt(name), "is not a valid probe name (" + base::name_rule() + ")");
  const std::string body_name = base::trim(prm.get("Body"));
  const Body *body = base::is_valid_name(body_name) ? bodies(body_name) : nullptr;
  if (!body) throw InputError(prefix + "Body", "there is no body '" + base::printable_excerpt(body_name) + "'");
  const auto p = base::parse_vector3(prm.get("Position"), prefix + "Position", "m");
  std::vector<double> q(body->n_q()), v(body->n_v());
  body->initial_coordinates(q.data(), v.data());
  std::unique_ptr<Marker> marker;
  try
    {
      marker = FixedMarker::at_global_pose(*body, name, Vector3({p[0], p[1], p[2]}), identity(), q.data(),
                                           base::trim(prm.get("Interface")));
    }
  catch (const InputError &e)
    {
      throw InputError(prefix + "Interface", e.message());
    }

  const std::string frame_name = base::trim(prm.get("Frame"));
  const FloatingBody *frame = nullptr;
  if (frame_name != "global")
    {
      const Body *f = base::is_valid_name(frame_name) ? bodies(frame_name) : nullptr;
      if (!f) throw InputError(prefix + "Frame", "there is no body '" + base::printable_excerpt(frame_name) + "'; give 'global' or a body name");
      frame = dynamic_cast<const FloatingBody *>(f); // the ground's frame is the global one
    }
  return std::make_unique<Probe>(name, std::move(marker), frame);
}
} // namespace flextrack::multibody
