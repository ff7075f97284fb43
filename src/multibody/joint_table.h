// The central table of joint kinds: name -> documentation, parameters, factory.
// flextrack_lib is a static library, so kinds are listed here explicitly (a self-registering
// static in a file nobody references would be dropped by the linker). Adding a kind: one file
// with its class (or just a mask), one row in joint_table.cc.
//
// A joint's subsection (the scene reader enters `subsection Joint NAME`):
//   set Kind = revolute
//   set Body 1 = crank            # the follower; the reaction output acts on it
//   set Body 2 = ground           # the base: its marker's axes are the joint axes
//   set Position = 0, 0, 0        # [m] global, at the initial configuration
//   set Axis = 0, 0, 1            # joint z axis, global
//   set Driver = 2*pi*t           # revolute: angle [rad]; prismatic: displacement [m]
#pragma once

#include <geometry/time_law.h>
#include <multibody/joint.h>

#include <deal.II/base/parameter_handler.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace flextrack::multibody
{
/// Finds a body by name; returns nullptr if there is none.
using BodyLookup = std::function<const Body *(const std::string &)>;

struct JointKind
{
  std::string name, documentation;
  std::function<std::unique_ptr<Joint>(const std::string &name, dealii::ParameterHandler &prm, const BodyLookup &,
                                       const geometry::TimeWindow &)>
    create;
};

/// Every joint kind.
const std::vector<JointKind> &joint_kinds();
/// "fixed, revolute, ..." (for messages and the Kind pattern).
std::string joint_kind_names();

/// The entries of a joint subsection (Kind and the entries of every kind; same names are shared).
void declare_joint_parameters(dealii::ParameterHandler &prm);
/// The joint of the current subsection; InputError (entry "Joint NAME/...") for bad input. Its
/// drivers are checked over the run's @p window (geometry/time_law.h; an empty window: not checked).
std::unique_ptr<Joint> create_joint(const std::string &name, dealii::ParameterHandler &prm, const BodyLookup &bodies,
                                    const geometry::TimeWindow &window = {});
} // namespace flextrack::multibody
