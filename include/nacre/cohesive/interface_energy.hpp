#pragma once
/// \file
/// \brief Transitional: the rigid-brick kinematics moved to nacre/kinematics/rigid.hpp and the
/// segment integral to nacre/cohesive/segment.hpp. These names keep code that still spells them
/// in nacre::cohesive (src/io, until it becomes solver-neutral on branch rel) compiling; new code
/// uses the new headers. Remove once nothing includes this file.
#include <nacre/cohesive/segment.hpp>
#include <nacre/kinematics/rigid.hpp>

namespace nacre::cohesive {
using kinematics::Frame;
using kinematics::interface_energy;
using kinematics::make_frame;
using kinematics::point_displacement;
using kinematics::Pose;
using kinematics::Segment;
}  // namespace nacre::cohesive
