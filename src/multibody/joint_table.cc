// The joint table and the parameters of mask joints.
#include <base/input_error.h>
#include <base/names.h>
#include <base/text.h>
#include <multibody/generic_joint.h>
#include <multibody/joint_table.h>
#include <multibody/track_joint.h>
#include <geometry/curve_library.h>

#include <sstream>

namespace flextrack::multibody
{
using namespace dealii;

namespace
{
Vector3 vector_entry(ParameterHandler &prm, const std::string &entry, const std::string &prefix, const std::string &unit)
{
  const auto v = base::parse_vector3(prm.get(entry), prefix + entry, unit);
  return Vector3({v[0], v[1], v[2]});
}

const Body &body_entry(ParameterHandler &prm, const std::string &entry, const std::string &prefix, const BodyLookup &bodies)
{
  const std::string name = base::trim(prm.get(entry));
  if (!base::is_valid_name(name)) throw InputError(prefix + entry, "'" + base::printable_excerpt(name) + "' is not a valid body name (" + base::name_rule() + ")");
  const Body *b = bodies(name);
  if (!b) throw InputError(prefix + entry, "there is no body '" + name + "'");
  return *b;
}

/// Global joint axes (columns x, y, z) from the z axis and an optional x reference.
/// The default of "Reference axis" (replaced by any perpendicular when Axis is along it).
const char *const default_reference_axis = "1, 0, 0";

Matrix3 joint_axes(const Vector3 &axis, const Vector3 &reference, const std::string &prefix, const bool reference_given)
{
  if (axis.norm() == 0) throw InputError(prefix + "Axis", "must not be zero");
  const Vector3 z = axis / axis.norm();
  Vector3 x = reference - (reference * z) * z;
  // A reference axis the scene gave sets the joint's zero angle (a driver's, a spring's): one
  // parallel to Axis cannot, and replacing it silently moved that zero.
  if (reference_given && !(x.norm() >= 1e-8 * reference.norm()))
    throw InputError(prefix + "Reference axis", "is parallel to Axis (or zero): it must have a part perpendicular to "
                                                "Axis, which becomes the joint's x axis");
  if (x.norm() < 1e-8) // the default reference along Axis: any perpendicular
    {
      const Vector3 trial = std::abs(z[0]) < 0.9 ? Vector3({1, 0, 0}) : Vector3({0, 1, 0});
      x = trial - (trial * z) * z;
    }
  x /= x.norm();
  const Vector3 y = cross_product_3d(z, x);
  Matrix3 A;
  for (unsigned int a = 0; a < 3; ++a)
    {
      A[a][0] = x[a];
      A[a][1] = y[a];
      A[a][2] = z[a];
    }
  return A;
}

std::unique_ptr<Joint> make_mask_joint(const std::string &name, ParameterHandler &prm, const BodyLookup &bodies,
                                        const geometry::TimeWindow &window,
                                       const JointMask &mask, const DriverKind drivable)
{
  const std::string prefix = "Joint " + name + "/";
  const Body &b1 = body_entry(prm, "Body 1", prefix, bodies), &b2 = body_entry(prm, "Body 2", prefix, bodies);
  if (&b1 == &b2) throw InputError(prefix + "Body 2", "joins body '" + b1.name() + "' to itself");
  const Vector3 position = vector_entry(prm, "Position", prefix, "m");
  const bool reference_given = base::trim(prm.get("Reference axis")) != default_reference_axis;
  const Matrix3 axes = joint_axes(vector_entry(prm, "Axis", prefix, "-"), vector_entry(prm, "Reference axis", prefix, "-"),
                                  prefix, reference_given);

  std::unique_ptr<Marker> m[2];
  const Body *b[2] = {&b1, &b2};
  for (unsigned int i = 0; i < 2; ++i)
    {
      std::vector<double> q(b[i]->n_q()), v(b[i]->n_v());
      b[i]->initial_coordinates(q.data(), v.data());
      try
        {
          m[i] = FixedMarker::at_global_pose(*b[i], name + "_" + std::to_string(i + 1), position, axes, q.data(),
                                             base::trim(prm.get("Interface " + std::to_string(i + 1))));
        }
      catch (const InputError &e)
        {
          throw InputError(prefix + "Interface " + std::to_string(i + 1), e.message());
        }
    }

  const std::string law_text = base::trim(prm.get("Driver"));
  DriverKind driver = DriverKind::none;
  std::shared_ptr<const geometry::Expression> law;
  if (!law_text.empty())
    {
      if (drivable == DriverKind::none) throw InputError(prefix + "Driver", "this joint kind cannot be driven (revolute: angle, prismatic: displacement)");
      try
        {
          law = std::make_shared<geometry::Expression>(law_text, "t");
          geometry::check_time_law(*law, window, 2); // an angle or a displacement: its rate and acceleration too
        }
      catch (const geometry::ExpressionError &e)
        {
          throw InputError(prefix + "Driver", e.what());
        }
      driver = drivable;
    }
  return std::make_unique<GenericJoint>(name, std::move(m[0]), std::move(m[1]), mask, driver, law);
}

using base::number_text;

/// The arm called @p arm of body @p b, with its geometry; InputError naming @p entry.
const reduction::ArmModeData &track_arm(const Body &b, const std::string &arm, const std::string &entry)
{
  const auto *floating = dynamic_cast<const FloatingBody *>(&b);
  const reduction::ReducedBody *reduced = floating ? floating->source() : nullptr;
  if (!reduced)
    throw InputError(entry, "body '" + b.name() + "' has no arms to slide along (only a flexible body, or one made "
                            "rigid, has arms)");
  std::string allowed;
  for (const auto &a : reduced->arms)
    {
      if (a.name == arm)
        {
          if (!a.curve || !a.frame)
            throw InputError(entry, "the reduced body of '" + b.name() + "' does not store the geometry of arm '" + arm +
                                      "' (an arm built in code): it cannot carry a track");
          return a;
        }
      allowed += (allowed.empty() ? "" : ", ") + a.name;
    }
  throw InputError(entry, "body '" + b.name() + "' has no arm '" + base::printable_excerpt(arm) + "'; allowed: " +
                            (allowed.empty() ? "none (it has no arms)" : allowed));
}

/// One contact of a track joint as the scene gives it: entries "Arm", "Sliding", "Driver",
/// "Friction", "Start arc length", "Start speed", each followed by @p suffix ("" for the track on
/// body 2, " 1" for a sleeve's track on body 1).
struct ContactInput
{
  const reduction::ArmModeData *arm;
  TrackSliding sliding;
  double s0 = 0, s0_rate = 0;
};

ContactInput parse_contact(ParameterHandler &prm, const std::string &prefix, const Body &carrier, const std::string &suffix,
                           const geometry::TimeWindow &window)
{
  ContactInput c;
  c.arm = &track_arm(carrier, base::trim(prm.get("Arm" + suffix)), prefix + "Arm" + suffix);
  const double L = c.arm->curve->length();
  const std::string drive = prm.get("Sliding" + suffix), driver_entry = prefix + "Driver" + suffix;
  c.sliding.drive = drive == "force" ? TrackDrive::force : drive == "motion" ? TrackDrive::motion : TrackDrive::free;
  c.sliding.friction = geometry::get_number(prm, "Friction" + suffix, prefix, {0, 1e12, true, "N s/m"});
  const std::string law_text = base::trim(prm.get("Driver" + suffix));
  if (c.sliding.drive != TrackDrive::free)
    {
      if (law_text.empty())
        throw InputError(driver_entry, "Sliding" + suffix + " = " + drive + " needs an expression of t: the " +
                                         (c.sliding.drive == TrackDrive::force ? "tangential force [N]" : "arc length [m]"));
      try
        {
          c.sliding.law = std::make_shared<geometry::Expression>(law_text, "t");
          // A force [N] is used as it is; an arc length s_d(t) [m] with its rate and acceleration.
          geometry::check_time_law(*c.sliding.law, window, c.sliding.drive == TrackDrive::motion ? 2 : 0);
        }
      catch (const geometry::ExpressionError &e)
        {
          throw InputError(driver_entry, e.what());
        }
    }
  else if (!law_text.empty())
    throw InputError(driver_entry, "a freely sliding contact takes no driver; set 'Sliding" + suffix + " = force' or 'motion'");

  const std::string ends = prm.get("End of track" + suffix);
  c.sliding.end_stops = ends == "stops";
  c.sliding.restitution = geometry::get_number(prm, "Restitution" + suffix, prefix, {0, 1, true, "-"});
  c.sliding.hold_speed = geometry::get_number(prm, "Hold speed" + suffix, prefix, {0, 1e6, true, "m/s"});
  if (c.sliding.end_stops && c.sliding.drive == TrackDrive::motion)
    throw InputError(prefix + "End of track" + suffix, "'stops' needs a contact that is not motion-driven (Sliding" +
                                                         suffix + " = free or force): a driven contact cannot bounce");
  c.s0 = geometry::get_number(prm, "Start arc length" + suffix, prefix, {0, 1e6, true, "m"});
  c.s0_rate = geometry::get_number(prm, "Start speed" + suffix, prefix, {-1e6, 1e6, true, "m/s"});
  if (c.sliding.drive == TrackDrive::motion) // the drive decides where the contact starts
    {
      const double t0 = window.start;
      const geometry::Jet start = c.sliding.law->jet(t0);
      // A start the scene gives as well must agree (issue 25, item 4: 'Start arc length 1'
      // contradicting 'Driver 1' was dropped silently). 0, the default, is taken as not given.
      const auto refuse_contradiction = [&](const std::string &entry, const double given, const double driven,
                                            const std::string &unit, const std::string &what) {
        if (given != 0 && !(std::abs(given - driven) <= 1e-9 * (1 + std::abs(driven) + L)))
          throw InputError(prefix + entry + suffix, number_text(given) + " " + unit + " contradicts 'Driver" + suffix +
                                                      "', which gives " + what + " " + number_text(driven) + " " + unit +
                                                      " at the start time t = " + number_text(t0) +
                                                      " s: a motion-driven contact starts where its driver puts it; "
                                                      "leave '" + entry + suffix + "' out, or make the two agree");
      };
      refuse_contradiction("Start arc length", c.s0, start.value(), "m", "the arc length");
      refuse_contradiction("Start speed", c.s0_rate, start.derivative(1), "m/s", "the speed");
      c.s0 = start.value();
      c.s0_rate = start.derivative(1);
      if (!(c.s0 >= 0 && c.s0 <= L))
        throw InputError(driver_entry, "puts the contact at s = " + number_text(c.s0) + " m at t = " + number_text(t0) +
                                         " s, off arm '" + c.arm->name + "' (0 to " + number_text(L) + " m)");
    }
  else if (c.s0 > L)
    throw InputError(prefix + "Start arc length" + suffix, number_text(c.s0) + " m is beyond the end of arm '" +
                                                             c.arm->name + "' (" + number_text(L) + " m)");
  return c;
}

/// Said when a contact slides on a flexible arm without track modes (issue 25, item 4): the
/// moving contact force then deforms the arm only through the normal and interface modes, which
/// miss the local deflection under the contact. Legitimate (a light slider, a stiff arm), so a
/// note, not a refusal.
std::string track_mode_note(const Body &carrier, const reduction::ArmModeData &arm)
{
  if (carrier.n_modes() == 0 || arm.track_stations > 0) return "";
  return "arm '" + arm.name + "' of body '" + carrier.name() +
         "' has no track modes (Reduction/Track arms of its body scene does not list it): the moving contact force "
         "deforms it only through the normal and interface modes, which miss the deflection under the contact; list "
         "the arm in Track arms";
}

std::unique_ptr<TrackMarker> make_track(const Body &carrier, const std::string &name, const ContactInput &c)
{
  auto field = carrier.n_modes() ? std::make_shared<reduction::ArmModeField>(*c.arm) : nullptr;
  return std::make_unique<TrackMarker>(carrier, name, c.arm->curve, c.arm->frame, field, c.s0, c.s0_rate);
}

/// Position and axes (columns, global) of @p track at the start.
MarkerKinematics initial_pose(const Marker &m, const double s0, Matrix3 &axes)
{
  std::vector<double> q(m.body().n_q()), v(m.body().n_v());
  m.body().initial_coordinates(q.data(), v.data());
  MarkerKinematics k;
  m.evaluate(q.data(), &s0, k);
  for (unsigned int a = 0; a < 3; ++a)
    for (unsigned int b = 0; b < 3; ++b) axes[b][a] = k.axes[a][b];
  return k;
}

std::unique_ptr<Joint> make_track_joint(const std::string &name, ParameterHandler &prm, const BodyLookup &bodies,
                                         const geometry::TimeWindow &window,
                                        const JointMask &mask)
{
  const std::string prefix = "Joint " + name + "/";
  const Body &slider = body_entry(prm, "Body 1", prefix, bodies), &carrier = body_entry(prm, "Body 2", prefix, bodies);
  if (&slider == &carrier) throw InputError(prefix + "Body 2", "joins body '" + slider.name() + "' to itself");
  const ContactInput contact = parse_contact(prm, prefix, carrier, "", window);
  auto track = make_track(carrier, name + "_on_" + contact.arm->name, contact);
  // The slider's marker: at the contact's initial place, with the contact's axes.
  Matrix3 axes;
  const MarkerKinematics k = initial_pose(*track, contact.s0, axes);
  std::vector<double> q1(slider.n_q()), v1(slider.n_v());
  slider.initial_coordinates(q1.data(), v1.data());
  std::unique_ptr<Marker> follower;
  try
    {
      follower = FixedMarker::at_global_pose(slider, name + "_slider", k.position, axes, q1.data(),
                                             base::trim(prm.get("Interface 1")));
    }
  catch (const InputError &e)
    {
      throw InputError(prefix + "Interface 1", e.message());
    }
  auto joint = std::make_unique<TrackJoint>(name, std::move(follower), std::move(track), mask, contact.sliding);
  // A slider placed away from its track rides on it at that offset, as on a rigid lever: that
  // may be meant (a carriage hanging below its rail), but it is said (issue 25, item 4: a body
  // 0.37 m off its track ran with its mass there, and the log said "moved 0 m").
  const double offset = q1.size() >= 3 ? (k.position - Vector3({q1[0], q1[1], q1[2]})).norm() : 0; // ground: none
  if (base::trim(prm.get("Interface 1")).empty() && offset > 1e-6 * (1 + contact.arm->curve->length()))
    joint->set_note("body '" + slider.name() + "' is held " + number_text(offset) + " m from its contact point on arm '" +
                    contact.arm->name + "' (s = " + number_text(contact.s0) + " m, at " + number_text(k.position[0]) + ", " +
                    number_text(k.position[1]) + ", " + number_text(k.position[2]) +
                    " m): it rides on the track at that offset, as on a rigid lever; place the body there to centre it "
                    "on the track");
  joint->add_note(track_mode_note(carrier, *contact.arm));
  return joint;
}

std::unique_ptr<Joint> make_sleeve(const std::string &name, ParameterHandler &prm, const BodyLookup &bodies,
                                    const geometry::TimeWindow &window,
                                   const JointMask &mask)
{
  const std::string prefix = "Joint " + name + "/";
  const Body &body_1 = body_entry(prm, "Body 1", prefix, bodies), &body_2 = body_entry(prm, "Body 2", prefix, bodies);
  const ContactInput c1 = parse_contact(prm, prefix, body_1, " 1", window), c2 = parse_contact(prm, prefix, body_2, "", window);
  if (&body_1 == &body_2 && c1.arm == c2.arm)
    throw InputError(prefix + "Arm 1", "a sleeve joins two different arms; both are arm '" + c1.arm->name + "' of body '" +
                                         body_1.name() + "'");
  auto track_1 = make_track(body_1, name + "_on_" + c1.arm->name, c1);
  auto track_2 = make_track(body_2, name + "_on_" + c2.arm->name, c2);
  Matrix3 axes_1, axes_2;
  const MarkerKinematics k1 = initial_pose(*track_1, c1.s0, axes_1), k2 = initial_pose(*track_2, c2.s0, axes_2);
  // The arms must meet at the two arc lengths (the initial-condition projection fixes round-off,
  // not a misplaced body).
  const double gap = (k1.position - k2.position).norm(),
               allowed = 1e-3 * (c1.arm->curve->length() + c2.arm->curve->length());
  if (!(gap <= allowed))
    throw InputError(prefix + "Start arc length 1",
                     "arm '" + c1.arm->name + "' at s = " + number_text(c1.s0) + " m and arm '" + c2.arm->name +
                       "' at s = " + number_text(c2.s0) + " m are " + number_text(gap) +
                       " m apart at the start; a sleeve needs them to meet (within " + number_text(allowed) +
                       " m): move a body or change the arc lengths");
  // Hold arm II at its initial angle to arm I: its marker axes are offset onto arm I's.
  track_1->set_axes_offset(transpose(axes_1) * axes_2);
  auto joint = std::make_unique<TrackJoint>(name, std::move(track_1), std::move(track_2), mask, c1.sliding, c2.sliding);
  joint->add_note(track_mode_note(body_1, *c1.arm));
  joint->add_note(track_mode_note(body_2, *c2.arm));
  return joint;
}

JointKind track_kind(const std::string &name, const std::string &doc, const JointMask mask)
{
  return {name, doc, [mask](const std::string &n, ParameterHandler &prm, const BodyLookup &b, const geometry::TimeWindow &w) {
            return make_track_joint(n, prm, b, w, mask);
          }};
}

JointKind mask_kind(const std::string &name, const std::string &doc, const JointMask mask,
                    const DriverKind drivable = DriverKind::none)
{
  return {name, doc, [mask, drivable](const std::string &n, ParameterHandler &prm, const BodyLookup &b, const geometry::TimeWindow &w) {
            return make_mask_joint(n, prm, b, w, mask, drivable);
          }};
}
} // namespace

const std::vector<JointKind> &joint_kinds()
{
  using M = JointMask;
  static const std::vector<JointKind> kinds = {
    mask_kind("fixed", "all six relative motions locked", M{{{true, true, true}}, {{true, true, true}}}),
    mask_kind("revolute", "rotation about z free; Driver: angle [rad]", M{{{true, true, true}}, {{true, true, false}}},
              DriverKind::angle),
    mask_kind("spherical", "all rotations free", M{{{true, true, true}}, {{false, false, false}}}),
    mask_kind("prismatic", "translation along z free; Driver: displacement [m]",
              M{{{true, true, false}}, {{true, true, true}}}, DriverKind::displacement),
    mask_kind("cylindrical", "translation along and rotation about z free", M{{{true, true, false}}, {{true, true, false}}}),
    mask_kind("universal", "rotations about x of body 1 and y of body 2 free (cross of pins)",
              M{{{true, true, true}}, {{false, false, true}}}),
    mask_kind("planar", "translations along x, y and rotation about z free", M{{{false, false, true}}, {{true, true, false}}}),
    mask_kind("point_in_plane", "the point of body 1 stays in the x-y plane of body 2",
              M{{{false, false, true}}, {{false, false, false}}}),
    track_kind("point_on_track", "a point of body 1 on arm 'Arm' of body 2 at arc length s (a bead): sliding and all "
                                 "rotations free", M{{{true, true, true}}, {{false, false, false}}}),
    track_kind("cylindrical_on_track", "body 1 slides along arm 'Arm' of body 2 and spins about its tangent (a sleeve)",
               M{{{true, true, true}}, {{true, true, false}}}),
    track_kind("prismatic_on_track", "body 1 slides along arm 'Arm' of body 2 with its frame locked to the arm's "
                                     "section frame (a slider)", M{{{true, true, true}}, {{true, true, true}}}),
    {"double_arm_sleeve",
     "a sleeve sliding along arm 'Arm' of body 2 (s_I) that holds arm 'Arm 1' of body 1 (s_II) at the angle the two "
     "arms make at the start (seed eqs. 41-43); entries ending in ' 1' set arm II's contact",
     [](const std::string &n, ParameterHandler &prm, const BodyLookup &b, const geometry::TimeWindow &w) {
       return make_sleeve(n, prm, b, w, JointMask{{{true, true, true}}, {{true, true, true}}});
     }},
  };
  return kinds;
}

std::string joint_kind_names()
{
  std::string s;
  for (const auto &k : joint_kinds()) s += (s.empty() ? "" : ", ") + k.name;
  return s;
}

void declare_joint_parameters(ParameterHandler &prm)
{
  std::string selection;
  for (const auto &k : joint_kinds()) selection += (selection.empty() ? "" : "|") + k.name;
  prm.declare_entry("Kind", "revolute", Patterns::Selection(selection), "Kind of joint [-]: " + joint_kind_names() + ".");
  prm.declare_entry("Body 1", "", Patterns::Anything(), "Name of the first body (the follower) [-].");
  prm.declare_entry("Body 2", "ground", Patterns::Anything(), "Name of the second body (the base, whose marker axes are the joint axes) [-].");
  prm.declare_entry("Position", "0, 0, 0", Patterns::Anything(), "Joint origin, global, at the initial configuration [m].");
  prm.declare_entry("Axis", "0, 0, 1", Patterns::Anything(), "Joint z axis, global, at the initial configuration [-].");
  prm.declare_entry("Reference axis", default_reference_axis, Patterns::Anything(),
                    "Joint x axis (made perpendicular to z), global, at the initial configuration [-].");
  prm.declare_entry("Interface 1", "", Patterns::Anything(),
                    "Interface of body 1 (flexible) the joint attaches to; empty: the joint position [-].");
  prm.declare_entry("Interface 2", "", Patterns::Anything(), "Interface of body 2 (flexible); empty: the joint position [-].");
  prm.declare_entry("Driver", "", Patterns::Anything(),
                    "Prescribed motion as an expression of t [s]: revolute angle about z [rad], prismatic "
                    "displacement along z [m], from the initial configuration; empty: free. Track joints: the "
                    "tangential force on body 1 [N] (Sliding = force) or the arc length s(t) [m] (Sliding = motion).");
  prm.declare_entry("Arm", "", Patterns::Anything(), "Track joints: the arm of body 2 that the contact slides along [-].");
  prm.declare_entry("Start arc length", "0", Patterns::Double(),
                    "Track joints: arc length s of the contact at the start [m], 0 to the arm's length (Sliding = "
                    "motion: taken from the driver at t = 0).");
  prm.declare_entry("Start speed", "0", Patterns::Double(),
                    "Track joints: sliding speed s' at the start [m/s], at most 1e6 in size (made consistent with "
                    "the bodies' velocities at the start).");
  prm.declare_entry("Sliding", "free", Patterns::Selection("free|force|motion"),
                    "Track joints: 'free' (only friction along the track), 'force' (a tangential force, Driver), "
                    "or 'motion' (s prescribed, Driver).");
  prm.declare_entry("Friction", "0", Patterns::Double(),
                    "Track joints: viscous friction along the track, force = -c s' [N s/m], 0 to 1e12.");
  prm.declare_entry("End of track", "ends run", Patterns::Selection("ends run|stops"),
                    "Track joints: what the ends of the arm (s = 0, s = L) do: 'ends run' (the run stops there with a "
                    "report, the default) or 'stops' (end stops: the contact bounces off with the coefficient "
                    "'Restitution' and is held at the end while the stop pushes; IDA only) [-].");
  prm.declare_entry("Restitution", "0", Patterns::Double(),
                    "Track joints with end stops: coefficient of restitution e, 0 (plastic) to 1 (elastic), s'+ = -e s'- "
                    "[-].");
  prm.declare_entry("Hold speed", "0.001", Patterns::Double(),
                    "Track joints with end stops: a rebound slower than this is held at the stop instead [m/s], 0 to "
                    "1e6.");
  // The second contact of a double-arm sleeve, on arm 'Arm 1' of body 1.
  prm.declare_entry("Arm 1", "", Patterns::Anything(), "Double-arm sleeve: the arm of body 1 (arm II) it holds [-].");
  prm.declare_entry("Start arc length 1", "0", Patterns::Double(),
                    "Double-arm sleeve: arc length s_II on arm 1 at the start [m], 0 to the arm's length.");
  prm.declare_entry("Start speed 1", "0", Patterns::Double(),
                    "Double-arm sleeve: s_II' at the start [m/s], at most 1e6 in size.");
  prm.declare_entry("Sliding 1", "free", Patterns::Selection("free|force|motion"),
                    "Double-arm sleeve: how arm 1 moves through the sleeve: 'free', 'force' or 'motion' (Driver 1).");
  prm.declare_entry("Driver 1", "", Patterns::Anything(),
                    "Double-arm sleeve: tangential force [N] (Sliding 1 = force) or s_II(t) [m] (Sliding 1 = motion) "
                    "as an expression of t [s].");
  prm.declare_entry("Friction 1", "0", Patterns::Double(),
                    "Double-arm sleeve: viscous friction along arm 1, force = -c s_II' [N s/m], 0 to 1e12.");
  prm.declare_entry("End of track 1", "ends run", Patterns::Selection("ends run|stops"),
                    "Double-arm sleeve: the ends of arm 1, as 'End of track' [-].");
  prm.declare_entry("Restitution 1", "0", Patterns::Double(),
                    "Double-arm sleeve: restitution at the end stops of arm 1, 0 to 1 [-].");
  prm.declare_entry("Hold speed 1", "0.001", Patterns::Double(),
                    "Double-arm sleeve: hold speed at the end stops of arm 1 [m/s], 0 to 1e6.");
}

std::unique_ptr<Joint> create_joint(const std::string &name, ParameterHandler &prm, const BodyLookup &bodies,
                                    const geometry::TimeWindow &window)
{
  if (!base::is_valid_name(name)) throw InputError("Joint " + base::printable_excerpt(name), "is not a valid joint name (" + base::name_rule() + ")");
  const std::string kind = prm.get("Kind");
  for (const auto &k : joint_kinds())
    if (k.name == kind) return k.create(name, prm, bodies, window);
  throw InputError("Joint " + name + "/Kind", "unknown joint kind '" + kind + "'; allowed: " + joint_kind_names());
}
} // namespace flextrack::multibody
