#include "meter/engine/evaluation/animation.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace meter::engine {
namespace {

void normalize_quat(std::span<float> q) {
  double n = std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
  if (n < 1e-12) {  // degenerate (cannot happen for validated data; keep it finite anyway)
    q[0] = q[1] = q[2] = 0.0f;
    q[3] = 1.0f;
    return;
  }
  for (int i = 0; i < 4; ++i) q[i] = static_cast<float>(q[i] / n);
}

// Shortest-path slerp of x,y,z,w quaternions.
void slerp(const float* a, const float* b, double u, std::span<float> out) {
  double dot = double(a[0]) * b[0] + double(a[1]) * b[1] + double(a[2]) * b[2] + double(a[3]) * b[3];
  double sign = 1.0;
  if (dot < 0.0) {  // q and -q: flip b so we go the short way
    dot = -dot;
    sign = -1.0;
  }
  double wa, wb;
  if (dot > 0.9995) {  // nearly parallel: lerp (then normalise) is exact enough and avoids 0/0
    wa = 1.0 - u;
    wb = u;
  } else {
    double theta = std::acos(std::min(1.0, dot));
    double st = std::sin(theta);
    wa = std::sin((1.0 - u) * theta) / st;
    wb = std::sin(u * theta) / st;
  }
  for (int i = 0; i < 4; ++i) out[i] = static_cast<float>(wa * a[i] + sign * wb * b[i]);
  normalize_quat(out);
}

}  // namespace

void sample(const AnimSampler& s, double t, std::span<float> out, bool rotation) {
  const int n = s.components;
  const std::size_t keys = s.input.size();
  const bool cubic = s.interpolation == Interpolation::CubicSpline;
  const int stride = cubic ? 3 * n : n;
  // Value of key k (for cubic splines the value sits between the in- and out-tangent).
  auto value = [&](std::size_t k) { return s.output.data() + k * stride + (cubic ? n : 0); };
  if (keys == 0 || out.size() < static_cast<std::size_t>(n) || s.output.size() < keys * stride) {
    std::fill(out.begin(), out.end(), 0.0f);
    return;
  }
  auto copy_key = [&](std::size_t k) {
    std::copy(value(k), value(k) + n, out.begin());
    if (rotation) normalize_quat(out);
  };
  if (keys == 1 || !(t > s.input.front())) return copy_key(0);  // also catches NaN t
  if (t >= s.input.back()) return copy_key(keys - 1);
  // First key with time > t; the interval is [k0, k1] with input[k0] <= t < input[k1].
  std::size_t k1 = static_cast<std::size_t>(std::upper_bound(s.input.begin(), s.input.end(), t) - s.input.begin());
  std::size_t k0 = k1 - 1;
  const double t0 = s.input[k0], t1 = s.input[k1];
  const double dt = t1 - t0;
  if (s.interpolation == Interpolation::Step) return copy_key(k0);
  if (!(dt > 0.0)) return copy_key(k1);  // duplicate key times: the later key wins
  const double u = (t - t0) / dt;
  if (s.interpolation == Interpolation::Linear) {
    const float* a = value(k0);
    const float* b = value(k1);
    if (rotation && n == 4) return slerp(a, b, u, out);
    for (int i = 0; i < n; ++i) out[i] = static_cast<float>(a[i] + (double(b[i]) - a[i]) * u);
    return;
  }
  // CUBICSPLINE: p(u) = h00 v0 + h10 dt b0 + h01 v1 + h11 dt a1, b0 = out-tangent of k0,
  // a1 = in-tangent of k1 (glTF spec, appendix C).
  const double u2 = u * u, u3 = u2 * u;
  const double h00 = 2 * u3 - 3 * u2 + 1, h10 = u3 - 2 * u2 + u, h01 = -2 * u3 + 3 * u2, h11 = u3 - u2;
  const float* v0 = value(k0);
  const float* b0 = s.output.data() + k0 * stride + 2 * n;
  const float* v1 = value(k1);
  const float* a1 = s.output.data() + k1 * stride;
  for (int i = 0; i < n; ++i) {
    out[i] = static_cast<float>(h00 * v0[i] + h10 * dt * b0[i] + h01 * v1[i] + h11 * dt * a1[i]);
  }
  if (rotation && n == 4) normalize_quat(out);
}

Pose Pose::rest(const Scene& scene) {
  Pose p;
  for (const auto& n : scene.nodes) {
    p.translation.push_back(n.translation);
    p.rotation.push_back(n.rotation);
    p.scale.push_back(n.scale);
    p.weights.push_back(n.weights);
  }
  return p;
}

void apply_animation(const Scene& scene, int index, double t, Pose& pose, std::vector<int>* touched) {
  if (index < 0 || index >= static_cast<int>(scene.animations.size())) return;
  const Animation& a = scene.animations[static_cast<std::size_t>(index)];
  float buf[4];
  for (const auto& ch : a.channels) {
    const AnimSampler& s = a.samplers[static_cast<std::size_t>(ch.sampler)];
    const auto node = static_cast<std::size_t>(ch.node);
    switch (ch.path) {
      case TargetPath::Translation:
        sample(s, t, std::span<float>(buf, 3));
        pose.translation[node] = {buf[0], buf[1], buf[2]};
        break;
      case TargetPath::Scale:
        sample(s, t, std::span<float>(buf, 3));
        pose.scale[node] = {buf[0], buf[1], buf[2]};
        break;
      case TargetPath::Rotation:
        sample(s, t, std::span<float>(buf, 4), true);
        pose.rotation[node] = glm::quat(buf[3], buf[0], buf[1], buf[2]);
        break;
      case TargetPath::Weights: {
        auto& w = pose.weights[node];
        w.resize(static_cast<std::size_t>(s.components));
        sample(s, t, std::span<float>(w));
        break;
      }
    }
    if (touched) touched->push_back(ch.node);
  }
}

glm::mat4 local_matrix(const glm::vec3& t, const glm::quat& r, const glm::vec3& s) {
  glm::mat4 m = glm::mat4_cast(r);
  m[0] *= s.x;
  m[1] *= s.y;
  m[2] *= s.z;
  m[3] = glm::vec4(t, 1.0f);
  return m;
}

glm::mat3 normal_matrix(const glm::mat4& model) {
  // In double: the products of 1e-20 or 1e20 scales would under/overflow in float.
  const glm::dvec3 a{glm::vec3{model[0]}}, b{glm::vec3{model[1]}}, c{glm::vec3{model[2]}};
  // Columns of the cofactor matrix: cross products of the other two columns.
  glm::dmat3 n(glm::cross(b, c), glm::cross(c, a), glm::cross(a, b));
  if (glm::dot(a, n[0]) < 0.0) n = -n;  // dot(a, b x c) = det
  // Scale so the largest entry is 1: a positive factor changes no direction, and the shader's
  // normalize() then never sees a vector whose squared length underflows (tiny scales).
  double big = 0.0;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) big = std::max(big, std::abs(n[i][j]));
  if (big > 0.0 && std::isfinite(big)) n /= big;
  else if (!(big == 0.0)) return glm::mat3(1.0f);  // non-finite model matrix: nothing sensible to do
  return glm::mat3(n);
}

double loop_time(double uptime, double start, double end) {
  const double len = end - start;
  if (!std::isfinite(uptime) || !(len > 0) || !std::isfinite(len)) return start;
  double r = std::fmod(uptime - start, len);  // exact; sign of (uptime - start)
  if (r < 0) r += len;
  if (r >= len) r = 0;  // r + len may round up to len for a tiny negative r
  return start + r;
}

NodeOrder NodeOrder::of(const Scene& scene) {
  NodeOrder o;
  o.preorder = node_preorder(scene);
  o.parent.assign(scene.nodes.size(), -1);
  for (int n : o.preorder)
    for (int c : scene.nodes[static_cast<std::size_t>(n)].children) o.parent[static_cast<std::size_t>(c)] = n;
  return o;
}

void world_matrices(const Scene& scene, const Pose& pose, std::vector<glm::mat4>& world) {
  world_matrices(scene, NodeOrder::of(scene), pose, world);
}

void world_matrices(const Scene& scene, const NodeOrder& order, const Pose& pose, std::vector<glm::mat4>& world) {
  world.assign(scene.nodes.size(), glm::mat4(1.0f));
  // The converter guarantees a forest (no loops, one parent each): every parent is done first.
  for (int n : order.preorder) {
    const auto i = static_cast<std::size_t>(n);
    const int p = order.parent[i];
    const glm::mat4 local = local_matrix(pose.translation[i], pose.rotation[i], pose.scale[i]);
    world[i] = p >= 0 ? world[static_cast<std::size_t>(p)] * local : glm::mat4(1.0f) * local;
  }
}

}  // namespace meter::engine
