// Cameras and KHR_lights_punctual lights: checked against the spec's ranges and copied into the
// scene model (names defaulted so the scene config can refer to them).
#include "convert_context.hpp"

namespace meter::convert {

void validate_cameras(ConvertContext& ctx) {
  for (std::size_t i = 0; i < ctx.m.cameras.size(); ++i) {
    const auto& c = ctx.m.cameras[i];
    const std::string p = idx("cameras", i);
    if (c.type == "perspective") {
      if (!(c.perspective.yfov > 0 && c.perspective.yfov < 3.14159)) ctx.error(p + ".perspective.yfov", "must be in (0, pi), got " + fmt(c.perspective.yfov));
      if (!(c.perspective.znear > 0)) ctx.error(p + ".perspective.znear", "must be > 0");
      if (c.perspective.zfar != 0 && !(c.perspective.zfar > c.perspective.znear)) ctx.error(p + ".perspective.zfar", "must be > znear");
    } else if (c.type == "orthographic") {
      if (c.orthographic.xmag == 0 || c.orthographic.ymag == 0) ctx.error(p + ".orthographic", "xmag and ymag must be non-zero");
      if (!(c.orthographic.zfar > c.orthographic.znear) || c.orthographic.znear < 0) ctx.error(p + ".orthographic.zfar", "must be > znear >= 0");
    } else {
      ctx.error(p + ".type", "expected \"perspective\" or \"orthographic\"");
    }
  }
}

void validate_lights(ConvertContext& ctx) {
  int casting = 0;
  for (std::size_t i = 0; i < ctx.m.lights.size(); ++i) {
    const auto& l = ctx.m.lights[i];
    const std::string p = "extensions.KHR_lights_punctual.lights[" + std::to_string(i) + "]";
    if (l.type != "directional" && l.type != "point" && l.type != "spot") ctx.error(p + ".type", "unknown light type \"" + l.type + "\"");
    if (!(l.intensity >= 0) || !std::isfinite(l.intensity)) ctx.error(p + ".intensity", "must be a finite number >= 0");
    if (l.range < 0 || !std::isfinite(l.range)) ctx.error(p + ".range", "must be > 0 when present");
    if (l.type == "spot" && !(l.spot.innerConeAngle >= 0 && l.spot.innerConeAngle < l.spot.outerConeAngle &&
                              l.spot.outerConeAngle <= 1.5707964)) {
      ctx.error(p + ".spot", "need 0 <= innerConeAngle < outerConeAngle <= pi/2");
    }
    if (l.extras.IsObject() && l.extras.Has("meter_cast_shadow")) {
      const auto& v = l.extras.Get("meter_cast_shadow");
      if (!v.IsBool() && !v.IsInt())
        ctx.error(p + ".extras.meter_cast_shadow", "expected true / false or 1 / 0 (Blender's use_shadow of the light)");
      else if (casts_shadow(l) && l.type == "point")
        ctx.repair(p + ".extras.meter_cast_shadow", "light \"" + l.name + "\" casts shadows in the scene; point-light shadows "
                   "(cube maps) are not drawn: it lights without a shadow");
      else if (casts_shadow(l) && ++casting > bridge::kMaxShadowMaps)
        ctx.repair(p + ".extras.meter_cast_shadow", "light \"" + l.name + "\": more than " + std::to_string(bridge::kMaxShadowMaps) +
                   " lights cast shadows; only the first " + std::to_string(bridge::kMaxShadowMaps) + " in light order get a shadow map");
    }
  }
}

bool casts_shadow(const tinygltf::Light& l) {
  if (!l.extras.IsObject() || !l.extras.Has("meter_cast_shadow")) return false;
  const auto& v = l.extras.Get("meter_cast_shadow");
  return v.IsBool() ? v.Get<bool>() : v.IsInt() && v.Get<int>() != 0;
}

void convert_cameras(const ConvertContext& ctx, Scene& s) {
  for (std::size_t i = 0; i < ctx.m.cameras.size(); ++i) {
    const auto& c = ctx.m.cameras[i];
    Camera out;
    out.name = c.name.empty() ? "camera" + std::to_string(i) : c.name;
    out.perspective = c.type == "perspective";
    if (out.perspective) {
      out.yfov = static_cast<float>(c.perspective.yfov), out.znear = static_cast<float>(c.perspective.znear), out.zfar = static_cast<float>(c.perspective.zfar);
    } else {
      out.xmag = static_cast<float>(c.orthographic.xmag), out.ymag = static_cast<float>(c.orthographic.ymag);
      out.znear = static_cast<float>(c.orthographic.znear), out.zfar = static_cast<float>(c.orthographic.zfar);
    }
    s.cameras.push_back(out);
  }
}

void convert_lights(const ConvertContext& ctx, Scene& s) {
  for (std::size_t i = 0; i < ctx.m.lights.size(); ++i) {
    const auto& l = ctx.m.lights[i];
    Light out;
    out.name = l.name.empty() ? "light" + std::to_string(i) : l.name;
    out.type = l.type == "point" ? LightType::Point : l.type == "spot" ? LightType::Spot : LightType::Directional;
    if (l.color.size() == 3) out.color = glm::vec3(l.color[0], l.color[1], l.color[2]);
    out.intensity = static_cast<float>(l.intensity);
    out.range = static_cast<float>(l.range);
    out.inner_cone = static_cast<float>(l.spot.innerConeAngle);
    out.outer_cone = static_cast<float>(l.spot.outerConeAngle);
    // Shadow maps for directional and spot lights (a point light's would be a cube map).
    out.cast_shadow = casts_shadow(l) && out.type != LightType::Point;
    s.lights.push_back(out);
  }
}

}  // namespace meter::convert
