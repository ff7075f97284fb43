// Joints on a track: a contact (multibody/track_marker.h) at arc length s on an arm of body 2,
// and a marker of body 1 (the slider) held to it by the generic joint's rows:
//   point_on_track        the slider's point stays on the deformed centre line (a bead): 3 rows;
//   cylindrical_on_track  also its z axis along the deformed tangent (spin about it free): 5 rows;
//   prismatic_on_track    its frame locked to the deformed section frame: 6 rows.
// s is the joint's own coordinate. It has no inertia and needs none (the slider carries the
// mass; the saddle-point matrix stays regular because M is positive on the null space of the
// constraints): its velocity row reads  B_s^T lambda = Q_s, i.e. the tangential contact force on
// the slider equals Q_s, the force the scene puts between slider and track:
//   free    Q_s = -c s'            (viscous friction c [N s/m], 0 by default)
//   force   Q_s = F(t) - c s'      (a tangential drive force F [N], an expression of t)
//   motion  s = s_d(t)             (a driver row; s_d an expression of t [m])
// The ends of the track are limits (s = 0, s = L): the integrator stops there and the run
// reports the time, the joint, s and the speed; or, with end stops, the contact hits them with a
// restitution coefficient and is held at an end while the stop pushes (app/multibody_runs.cc). A sleeve between two arms has two contacts, each
// with its own s, sliding law and limits.
#pragma once

#include <geometry/expression.h>
#include <multibody/generic_joint.h>
#include <multibody/track_marker.h>

#include <memory>

namespace flextrack::multibody
{
enum class TrackDrive { free, force, motion };

struct TrackSliding
{
  TrackDrive drive = TrackDrive::free;
  std::shared_ptr<const geometry::Expression> law; ///< F(t) [N] or s_d(t) [m]
  double friction = 0;                             ///< viscous coefficient c [N s/m]
  bool end_stops = false;     ///< the track's ends hold the contact (else the run stops there)
  double restitution = 0;     ///< e at the end stops [-], 0..1
  double hold_speed = 1e-3;   ///< rebounds slower than this are held at the stop [m/s]
};

class TrackJoint : public GenericJoint
{
public:
  /// A contact on a track of body 2 holding a marker of body 1.
  TrackJoint(std::string name, std::unique_ptr<Marker> slider, std::unique_ptr<TrackMarker> track,
             const JointMask &mask, const TrackSliding &sliding);
  /// The double flexible arm sleeve (seed eqs. 41-43): contacts on an arm of body 1 (arm II,
  /// @p track_1, own coordinate s_II) and on an arm of body 2 (arm I, @p track_2, s_I) held together
  /// by the mask's rows, @p track_1's axes offset to coincide with @p track_2's at the start.
  TrackJoint(std::string name, std::unique_ptr<TrackMarker> track_1, std::unique_ptr<TrackMarker> track_2,
             const JointMask &mask, const TrackSliding &sliding_1, const TrackSliding &sliding_2);

  void own_forces(const double *own_q, const double *own_v, double t, double *applied,
                  double *dissipative) const override;
  unsigned int n_limits() const override { return 2 * contacts.size(); }
  void limits(const double *own_q, double *g) const override;
  std::string limit_report(unsigned int k, const double *own_q, const double *own_v) const override;
  EndStop end_stop(unsigned int k) const override;

private:
  struct Contact
  {
    unsigned int own;         ///< index among the joint's own coordinates
    const TrackMarker *track;
    TrackSliding sliding;
  };
  void add_contact(unsigned int own, const TrackSliding &sliding);
  std::vector<Contact> contacts;
};
} // namespace flextrack::multibody
