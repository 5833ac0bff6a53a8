// Keyframe sampling (glTF 2.0 semantics) and pose evaluation. Pure functions on plain data.
#pragma once

#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

// Samples `s` at time t (seconds) into out[0 .. s.components). Rules:
//  - t before the first key / after the last key: clamped to that key's value;
//  - a single key: that value for every t;
//  - duplicate key times (zero-length interval): the later key wins, no division by zero;
//  - LINEAR: lerp; for rotations (rotation = true) shortest-path slerp (q and -q are the same
//    orientation, so the interpolation never takes the long way round), result normalised;
//  - STEP: the value of the key at or before t;
//  - CUBICSPLINE: Hermite with the stored tangents scaled by the key interval (glTF spec), rotation
//    result normalised.
// Time is double so long-running loops keep sub-millisecond resolution.
void sample(const AnimSampler& s, double t, std::span<float> out, bool rotation = false);

// Local TRS + morph weights of every node, the state animations write into.
struct Pose {
  std::vector<glm::vec3> translation;
  std::vector<glm::quat> rotation;
  std::vector<glm::vec3> scale;
  std::vector<std::vector<float>> weights;
  static Pose rest(const Scene& scene);
};

// Writes every channel of animation `index` sampled at time t into the pose. Returns the set of
// nodes it touched (their world matrices need recomputing).
void apply_animation(const Scene& scene, int index, double t, Pose& pose, std::vector<int>* touched = nullptr);

glm::mat4 local_matrix(const glm::vec3& t, const glm::quat& r, const glm::vec3& s);

// Normal matrix of a model matrix: the cofactor matrix of its upper 3x3, signed by the determinant
// and scaled so its largest entry is 1. It is inverse-transpose times a positive factor (the
// shaders normalise, so the factor does not matter) but never divides by the determinant: a zero
// or 1e-20 scale gives a finite matrix instead of Inf/NaN normals, and a mirroring
// (negative-determinant) transform still turns normals the right way.
glm::mat3 normal_matrix(const glm::mat4& model);

// Time inside a looping animation [start, end] after `uptime` seconds: start + (uptime - start)
// mod (end - start), in double with std::fmod (exact: no rounding however long the uptime). A
// non-finite uptime or an empty loop gives start. The result is in [start, end).
double loop_time(double uptime, double start, double end);

// The scene's one traversal order (bridge::node_preorder) with each node's parent (-1 for a
// root and for nodes no root reaches): parents come before their children.
struct NodeOrder {
  std::vector<int> preorder;
  std::vector<int> parent;  // per node
  static NodeOrder of(const Scene& scene);
};

// World matrices of all nodes (parents before children, in node_preorder); a node no root reaches
// keeps the identity.
void world_matrices(const Scene& scene, const Pose& pose, std::vector<glm::mat4>& world);
void world_matrices(const Scene& scene, const NodeOrder& order, const Pose& pose, std::vector<glm::mat4>& world);

}  // namespace meter::engine
