// Joints on tracks: sliding forces, drivers and the ends of the tracks (see track_joint.h).
#include <multibody/track_joint.h>

#include <sstream>

namespace flextrack::multibody
{
TrackJoint::TrackJoint(std::string name, std::unique_ptr<Marker> slider, std::unique_ptr<TrackMarker> track,
                       const JointMask &mask, const TrackSliding &sliding)
  : GenericJoint(std::move(name), std::move(slider), std::move(track), mask)
{
  add_contact(0, sliding);
}

TrackJoint::TrackJoint(std::string name, std::unique_ptr<TrackMarker> track_1, std::unique_ptr<TrackMarker> track_2,
                       const JointMask &mask, const TrackSliding &sliding_1, const TrackSliding &sliding_2)
  : GenericJoint(std::move(name), std::move(track_1), std::move(track_2), mask)
{
  add_contact(0, sliding_1);
  add_contact(1, sliding_2);
}

void TrackJoint::add_contact(const unsigned int own, const TrackSliding &sliding)
{
  // The contact of own coordinate 0 is marker 1's when marker 1 is on a track (a sleeve).
  const Marker &m = marker(own == 0 && marker(0).n_own_coordinates() ? 0 : 1);
  contacts.push_back({own, &static_cast<const TrackMarker &>(m), sliding});
  if (sliding.drive == TrackDrive::motion)
    add_own_driver(own, sliding.law, "driven arc length s on " + m.name());
}

void TrackJoint::own_forces(const double *, const double *own_v, const double t, double *applied,
                            double *dissipative) const
{
  for (const Contact &c : contacts)
    {
      if (c.sliding.drive == TrackDrive::force) applied[c.own] = c.sliding.law->value(t);
      if (c.sliding.drive != TrackDrive::motion) dissipative[c.own] = -c.sliding.friction * own_v[c.own];
    }
}

void TrackJoint::limits(const double *own_q, double *g) const
{
  for (unsigned int i = 0; i < contacts.size(); ++i)
    {
      g[2 * i] = own_q[contacts[i].own];
      g[2 * i + 1] = contacts[i].track->length() - own_q[contacts[i].own];
    }
}

Joint::EndStop TrackJoint::end_stop(const unsigned int k) const
{
  const Contact &c = contacts[k / 2];
  EndStop e;
  e.stop_run = !c.sliding.end_stops;
  e.coordinate = c.own;
  e.upper = k % 2 == 1;
  e.restitution = c.sliding.restitution;
  e.hold_speed = c.sliding.hold_speed;
  return e;
}

std::string TrackJoint::limit_report(const unsigned int k, const double *own_q, const double *own_v) const
{
  const Contact &c = contacts[k / 2];
  std::ostringstream m;
  m.precision(6);
  m << "the contact " << c.track->name() << " of joint '" << name() << "' reached the " << (k % 2 == 0 ? "start" : "end")
    << " of its track (s = " << own_q[c.own] << " m of L = " << c.track->length() << " m, sliding at " << own_v[c.own]
    << " m/s); give the track a longer arm, a drive that stays on it, or a shorter end time";
  return m.str();
}
} // namespace flextrack::multibody
