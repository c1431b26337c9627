// Basic numeric types shared by the whole engine. SI units everywhere.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace granulab {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Index of a rigid grain (body) in the world.
using BodyId = std::uint32_t;
/// Index of a sphere inside its grain's template (body-frame clump).
using LocalSphereId = std::uint16_t;

}  // namespace granulab
