// Basic numeric types shared by the whole engine. SI units everywhere.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

namespace granulab {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

/// Index of a rigid grain (body) in the world: a position in the SoA arrays of Bodies, which may change
/// from one build of a sample to another (e.g. when grains are knocked out).
using BodyId = std::uint32_t;
/// Index of a sphere inside its grain's template (body-frame clump).
using LocalSphereId = std::uint16_t;

/// The stable id of a crystal grain: the number of its lattice site in the full box (layer-major, then
/// row, then column), unchanged by knock-outs. What users see in snapshots and give in `crystal.knockout`.
/// A distinct type so that a body index cannot be passed where a grain id is meant, or the reverse.
enum class GrainId : std::uint32_t {};
constexpr std::uint32_t value(GrainId id) { return static_cast<std::uint32_t>(id); }

/// Two bodies (world indices), a < b: an interface between neighbouring grains during a run.
struct BodyPair {
  BodyId a, b;
  friend bool operator==(const BodyPair& p, const BodyPair& q) { return p.a == q.a && p.b == q.b; }
  friend bool operator<(const BodyPair& p, const BodyPair& q) { return p.a != q.a ? p.a < q.a : p.b < q.b; }
};
/// The same interface named by stable grain ids, for output.
struct GrainPair {
  GrainId a, b;
  friend bool operator==(const GrainPair& p, const GrainPair& q) { return p.a == q.a && p.b == q.b; }
};

}  // namespace granulab
