// glTF accessors: checked against their buffer views and buffers, then decoded once to doubles
// (normalised integers mapped to 0..1 / -1..1, sparse substitutions applied) so every later check
// and every conversion stage reads the same values.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "convert_context.hpp"

namespace meter::convert {

std::string idx(const char* what, std::size_t i) { return std::string(what) + "[" + std::to_string(i) + "]"; }

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}


int component_size(int type) {
  switch (type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

int type_components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

const char* type_name(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "?";
  }
}


void check_accessor(ConvertContext& ctx, std::size_t i) {
  const auto& a = ctx.m.accessors[i];
  const std::string p = idx("accessors", i);
  const int cs = component_size(a.componentType);
  const int nc = type_components(a.type);
  bool ok = true;
  if (!cs) ctx.error(p + ".componentType", "unsupported component type " + std::to_string(a.componentType)), ok = false;
  if (!nc) ctx.error(p + ".type", "unsupported accessor type"), ok = false;
  if (a.count == 0) ctx.error(p + ".count", "must be at least 1"), ok = false;
  if (ok && a.bufferView >= 0) {
    if (static_cast<std::size_t>(a.bufferView) >= ctx.m.bufferViews.size()) {
      ctx.error(p + ".bufferView", "index " + std::to_string(a.bufferView) + " out of range"), ok = false;
    } else {
      const auto& bv = ctx.m.bufferViews[static_cast<std::size_t>(a.bufferView)];
      const std::string bvp = idx("bufferViews", static_cast<std::size_t>(a.bufferView));
      if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= ctx.m.buffers.size()) {
        ctx.error(bvp + ".buffer", "index out of range"), ok = false;
      } else if (bv.byteOffset + bv.byteLength > ctx.m.buffers[static_cast<std::size_t>(bv.buffer)].data.size()) {
        ctx.error(bvp + ".byteLength", "buffer view (offset " + std::to_string(bv.byteOffset) + ", length " +
                                       std::to_string(bv.byteLength) + ") does not fit buffer " +
                                       std::to_string(bv.buffer) + " (" +
                                       std::to_string(ctx.m.buffers[static_cast<std::size_t>(bv.buffer)].data.size()) + " bytes)");
        ok = false;
      } else {
        const std::size_t elem = std::size_t(cs) * std::size_t(nc);
        const std::size_t stride = bv.byteStride ? bv.byteStride : elem;
        if (bv.byteStride && (bv.byteStride < elem || bv.byteStride % std::size_t(cs))) {
          ctx.error(bvp + ".byteStride", "stride " + std::to_string(bv.byteStride) + " is invalid for " + type_name(a.type)), ok = false;
        } else if (a.byteOffset + stride * (a.count - 1) + elem > bv.byteLength) {
          ctx.error(p, "accessor data (offset " + std::to_string(a.byteOffset) + ", " + std::to_string(a.count) +
                       " elements) does not fit bufferViews[" + std::to_string(a.bufferView) + "] (" +
                       std::to_string(bv.byteLength) + " bytes)");
          ok = false;
        }
      }
    }
  }
  if (ok && a.sparse.isSparse) {
    auto check_view = [&](int v, std::size_t off, std::size_t bytes, const std::string& sp) {
      if (v < 0 || static_cast<std::size_t>(v) >= ctx.m.bufferViews.size()) {
        ctx.error(sp + ".bufferView", "index out of range"), ok = false;
        return;
      }
      const auto& bv = ctx.m.bufferViews[static_cast<std::size_t>(v)];
      if (bv.buffer < 0 || static_cast<std::size_t>(bv.buffer) >= ctx.m.buffers.size() ||
          bv.byteOffset + bv.byteLength > ctx.m.buffers[static_cast<std::size_t>(bv.buffer)].data.size() ||
          off + bytes > bv.byteLength) {
        ctx.error(sp, "sparse data does not fit its buffer view"), ok = false;
      }
    };
    const int ics = component_size(a.sparse.indices.componentType);
    if (a.sparse.count <= 0 || static_cast<std::size_t>(a.sparse.count) > a.count || !ics ||
        a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
        a.sparse.indices.componentType == TINYGLTF_COMPONENT_TYPE_SHORT) {
      ctx.error(p + ".sparse", "invalid sparse count or index component type"), ok = false;
    } else {
      check_view(a.sparse.indices.bufferView, std::size_t(a.sparse.indices.byteOffset),
                 std::size_t(a.sparse.count) * std::size_t(ics), p + ".sparse.indices");
      check_view(a.sparse.values.bufferView, std::size_t(a.sparse.values.byteOffset),
                 std::size_t(a.sparse.count) * std::size_t(cs) * std::size_t(nc), p + ".sparse.values");
    }
  }
  ctx.accessor_ok[i] = ok;
  if (!ok) return;
  // Decode now: every later check and the conversion read the decoded doubles.
  auto& out = ctx.accessor_values[i];
  out.assign(a.count * std::size_t(nc), 0.0);
  auto decode = [&](const unsigned char* src, int ct, bool normalized) -> double {
    switch (ct) {
      case TINYGLTF_COMPONENT_TYPE_FLOAT: { float f; std::memcpy(&f, src, 4); return f; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { std::uint32_t v; std::memcpy(&v, src, 4); return v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { std::uint16_t v; std::memcpy(&v, src, 2); return normalized ? v / 65535.0 : v; }
      case TINYGLTF_COMPONENT_TYPE_SHORT: { std::int16_t v; std::memcpy(&v, src, 2); return normalized ? std::max(v / 32767.0, -1.0) : v; }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalized ? *src / 255.0 : *src;
      case TINYGLTF_COMPONENT_TYPE_BYTE: { auto v = static_cast<std::int8_t>(*src); return normalized ? std::max(v / 127.0, -1.0) : v; }
      default: return 0.0;
    }
  };
  if (a.bufferView >= 0) {
    const auto& bv = ctx.m.bufferViews[static_cast<std::size_t>(a.bufferView)];
    const auto& buf = ctx.m.buffers[static_cast<std::size_t>(bv.buffer)].data;
    const std::size_t stride = bv.byteStride ? bv.byteStride : std::size_t(cs) * std::size_t(nc);
    for (std::size_t e = 0; e < a.count; ++e) {
      const unsigned char* base = buf.data() + bv.byteOffset + a.byteOffset + e * stride;
      for (int c = 0; c < nc; ++c) out[e * std::size_t(nc) + std::size_t(c)] = decode(base + c * cs, a.componentType, a.normalized);
    }
  }
  if (a.sparse.isSparse) {
    const auto& ibv = ctx.m.bufferViews[static_cast<std::size_t>(a.sparse.indices.bufferView)];
    const auto& vbv = ctx.m.bufferViews[static_cast<std::size_t>(a.sparse.values.bufferView)];
    const auto* ib = ctx.m.buffers[static_cast<std::size_t>(ibv.buffer)].data.data() + ibv.byteOffset + std::size_t(a.sparse.indices.byteOffset);
    const auto* vb = ctx.m.buffers[static_cast<std::size_t>(vbv.buffer)].data.data() + vbv.byteOffset + std::size_t(a.sparse.values.byteOffset);
    const int ics = component_size(a.sparse.indices.componentType);
    for (int s = 0; s < a.sparse.count; ++s) {
      auto target = static_cast<std::size_t>(decode(ib + s * ics, a.sparse.indices.componentType, false));
      if (target >= a.count) {
        ctx.error(p + ".sparse.indices", "sparse index " + std::to_string(target) + " >= count " + std::to_string(a.count));
        ctx.accessor_ok[i] = false;
        return;
      }
      for (int c = 0; c < nc; ++c) out[target * std::size_t(nc) + std::size_t(c)] = decode(vb + (s * nc + c) * cs, a.componentType, a.normalized);
    }
  }
  if (a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
    for (std::size_t e = 0; e < out.size(); ++e) {
      if (!std::isfinite(out[e])) {
        ctx.error(p, "element " + std::to_string(e / std::size_t(nc)) + " (component " + std::to_string(e % std::size_t(nc)) +
                     ") is " + (std::isnan(out[e]) ? "NaN" : (out[e] > 0 ? "Infinity" : "-Infinity")));
        ctx.accessor_ok[i] = false;
      }
    }
  }
}


const std::vector<double>* ConvertContext::use_accessor(int a, const std::string& path, std::initializer_list<int> types,
                                        std::initializer_list<int> component_types) {
  if (a < 0 || static_cast<std::size_t>(a) >= m.accessors.size()) {
    error(path, "accessor index " + std::to_string(a) + " out of range");
    return nullptr;
  }
  const auto& acc = m.accessors[static_cast<std::size_t>(a)];
  if (std::find(types.begin(), types.end(), acc.type) == types.end()) {
    std::string list;
    for (int t : types) list += std::string(list.empty() ? "" : " or ") + type_name(t);
    error(path, std::string("accessor type ") + type_name(acc.type) + " where " + list + " is required");
    return nullptr;
  }
  if (component_types.size() &&
      std::find(component_types.begin(), component_types.end(), acc.componentType) == component_types.end()) {
    error(path, "component type " + std::to_string(acc.componentType) + " is not allowed here");
    return nullptr;
  }
  if (!accessor_ok[static_cast<std::size_t>(a)]) return nullptr;  // already reported at accessors[a]
  return &accessor_values[static_cast<std::size_t>(a)];
}

std::vector<float> ConvertContext::attribute(int acc, int comps_out, bool clamp01) const {
  const auto& a = m.accessors[static_cast<std::size_t>(acc)];
  const auto& d = accessor_values[static_cast<std::size_t>(acc)];
  const int nc = type_components(a.type);
  std::vector<float> out(a.count * std::size_t(comps_out), 1.0f);
  for (std::size_t e = 0; e < a.count; ++e) {
    for (int c = 0; c < std::min(nc, comps_out); ++c) {
      double v = d[e * std::size_t(nc) + std::size_t(c)];
      if (clamp01) v = std::clamp(v, 0.0, 1.0);
      out[e * std::size_t(comps_out) + std::size_t(c)] = static_cast<float>(v);
    }
  }
  return out;
}

}  // namespace meter::convert
