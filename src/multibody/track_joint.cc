// Joints on a track: sliding forces and the ends of the track (see track_joint.h).
#include <multibody/track_joint.h>

#include <sstream>

namespace flextrack::multibody
{
TrackJoint::TrackJoint(std::string name, std::unique_ptr<Marker> slider, std::unique_ptr<TrackMarker> track,
                       const JointMask &mask, const TrackSliding &sliding_)
  : GenericJoint(std::move(name), std::move(slider), std::move(track), mask,
                 sliding_.drive == TrackDrive::motion ? DriverKind::own_coordinate : DriverKind::none,
                 sliding_.drive == TrackDrive::motion ? sliding_.law : nullptr),
    sliding(sliding_)
{}

void TrackJoint::own_forces(const double *, const double *own_v, const double t, double *applied,
                            double *dissipative) const
{
  if (sliding.drive == TrackDrive::force) applied[0] = sliding.law->value(t);
  if (sliding.drive != TrackDrive::motion) dissipative[0] = -sliding.friction * own_v[0];
}

void TrackJoint::limits(const double *own_q, double *g) const
{
  g[0] = own_q[0];
  g[1] = track().length() - own_q[0];
}

std::string TrackJoint::limit_report(const unsigned int k, const double *own_q, const double *own_v) const
{
  std::ostringstream m;
  m.precision(6);
  m << "the contact of joint '" << name() << "' reached the " << (k == 0 ? "start" : "end")
    << " of its track (s = " << own_q[0] << " m of L = " << track().length() << " m, sliding at " << own_v[0]
    << " m/s); give the track a longer arm, a drive that stays on it, or a shorter end time";
  return m.str();
}
} // namespace flextrack::multibody
