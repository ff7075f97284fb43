// The generic joint between two markers: constrained-axis masks in the frame of the second
// marker (the base, axes e_j) acting on the first (the follower, axes e_i, origin r_i):
//   translation along a:   e_j,a . (r_i - r_j) - s(t) = 0        (s = 0 unless driven along z)
//   rotations locked:      all three  e_i,z.e_j,x, e_i,z.e_j,y, e_i,x.e_j,y   (= th_y, -th_x, th_z)
//                          two (a, b; c free)  e_i,c.e_j,a, e_i,c.e_j,b       (axis c stays aligned)
//                          one (c)  e_i,a.e_j,b                              (the cross of a universal)
//   driven angle about z:  e_i,x . (-sin th(t) e_j,x + cos th(t) e_j,y) = 0   (= sin(angle - th))
//   driven own coordinate: s - s(t) = 0                  (a track contact's arc length)
// Each row is a function of the 24 marker quantities x = (r_i, e_i,1..3, r_j, e_j,1..3); its
// gradient times the markers' Jacobians gives B, and the same gradient gives the reactions.
// Fixed, revolute, spherical, prismatic, cylindrical, universal, planar and point-in-plane are
// masks (joint_table.cc). Markers may own coordinates (a track contact owns its arc length s,
// multibody/track_marker.h): the joint carries them, marker 1's first, and their Jacobian
// columns form B_own.
#pragma once

#include <geometry/expression.h>
#include <multibody/joint.h>

#include <array>
#include <memory>

namespace flextrack::multibody
{
struct JointMask
{
  std::array<bool, 3> translation{{true, true, true}}; ///< constrained translations (base axes)
  std::array<bool, 3> rotation{{true, true, true}};    ///< locked rotations (base axes)
};

enum class DriverKind { none, angle, displacement, own_coordinate };

class GenericJoint : public Joint
{
public:
  /// @p follower on the first body, @p base on the second. A driver prescribes the angle [rad]
  /// about z (rotation about z must then be free) or the displacement [m] along z (translation
  /// along z free) as @p driver(t), measured from the initial coincidence of the markers.
  GenericJoint(std::string name, std::unique_ptr<Marker> follower, std::unique_ptr<Marker> base, const JointMask &mask,
               DriverKind driver = DriverKind::none, std::shared_ptr<const geometry::Expression> law = nullptr);

  unsigned int n_equations() const override { return rows.size(); }
  unsigned int n_own_coordinates() const override;
  void initial_own_coordinates(double *q, double *v) const override;
  std::vector<const Body *> bodies() const override { return {&markers[0]->body(), &markers[1]->body()}; }
  void evaluate(const std::vector<const double *> &q, const double *own_q, double t, JointEvaluation &e) const override;
  /// From the markers' Jacobians J directly: B v = sum of the row gradients times J v, and
  /// B^T w = J^T (sum_r w_r times the row gradients), with no equations x velocities product.
  void residual_terms(const std::vector<const double *> &q, const double *own_q, double t,
                      const std::vector<const double *> &v, const double *own_v, const double *lambda,
                      const double *mu, JointResidualTerms &r) const override;
  /// Analytic where a marker has a body-fixed form (a point and frame on a body or at an
  /// interface); a track contact's own second derivatives by differences of that marker alone.
  /// False for two markers on one body.
  bool derivatives(const std::vector<const double *> &q, const double *own_q, double t, const double *lambda,
                   const double *mu, const std::vector<const double *> &v, const double *own_v,
                   JointDerivatives &d) const override;
  /// Phi_t from the laws alone; the markers are evaluated only for a driven angle (whose Phi_t
  /// depends on the axes). A track contact's marker (curve, section frame, mode fields at s) is
  /// the costly one, and its driver, s = s(t), needs none of it.
  void driver_rates(const std::vector<const double *> &q, const double *own_q, double t,
                    dealii::Vector<double> &phi_t) const override;
  std::string equation_name(unsigned int k) const override { return rows[k].name; }
  bool is_driver_equation(unsigned int k) const override
  {
    return rows[k].kind == RowKind::angle || rows[k].kind == RowKind::own || rows[k].driven;
  }
  void reaction(const std::vector<const double *> &q, const double *own_q, double t, const double *lambda, Vector3 &force,
                Vector3 &torque) const override;
  /// The same, and the unit axes (global) of the base marker, the second, at the state: of a
  /// track contact the track's section y axis d2, d3 = t x d2 and the tangent t (track_marker.h).
  void reaction(const std::vector<const double *> &q, const double *own_q, double t, const double *lambda, Vector3 &force,
                Vector3 &torque, std::array<Vector3, 3> &base_axes) const;

  const Marker &marker(unsigned int i) const { return *markers[i]; }

protected:
  /// Adds the driver row  own coordinate @p index = @p law(t)  (a track's arc length).
  void add_own_driver(unsigned int index, std::shared_ptr<const geometry::Expression> law, const std::string &name);

private:
  enum class RowKind { translation, rotation, angle, own };
  struct Row
  {
    RowKind kind;
    unsigned int a = 0, b = 0; // translation: axis a; rotation: e_i,a . e_j,b
    bool driven = false;       // translation with s(t)
    std::string name;
    std::shared_ptr<const geometry::Expression> own_law; // own: coordinate a = own_law(t)
  };
  /// Gradient of row values w.r.t. x = (r_i, e_i[3], r_j, e_j[3]): 8 vectors per row.
  using Gradient = std::array<Vector3, 8>;
  struct Local
  {
    MarkerKinematics k[2];
    std::vector<Gradient> grad;
  };
  /// This joint's workspace on this thread (a cache of a few joints per thread). One workspace
  /// shared by all joints had each joint resize the other joints' marker Jacobians: a ground
  /// marker's 3 x 0 Jacobian frees the storage, and the next joint's marker allocates it again
  /// (186 000 allocations in the laser robot's run, 3 % of its instructions).
  Local &workspace() const;
  void evaluate_rows(const std::vector<const double *> &q, const double *own_q, double t, Local &l,
                     dealii::Vector<double> &phi, dealii::Vector<double> &phi_t) const;
  /// Each row's value is a quadratic form in the 8 marker quantities x = (r_i, e_i[3], r_j,
  /// e_j[3]): its gradient w.r.t. x_a is sum_b C_ab x_b. The non-zero C_ab of row @p r (a, b,
  /// C_ab; symmetric), for the drive angle @p angle [rad] at the time.
  struct HessianTerm
  {
    unsigned int a, b;
    double c;
  };
  void row_hessian(unsigned int r, double angle, std::vector<HessianTerm> &terms) const;
  /// Own coordinates of marker @p m within the joint's (nullptr if it has none).
  const double *own_of(unsigned int m, const double *own_q) const;

  std::unique_ptr<Marker> markers[2];
  std::vector<Row> rows;
  DriverKind driver;
  std::shared_ptr<const geometry::Expression> law;
  /// Tells joints apart in workspace() (an address can be reused).
  unsigned long long id;
};
} // namespace flextrack::multibody
