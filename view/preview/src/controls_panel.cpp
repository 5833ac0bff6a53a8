#include "meter/preview/controls_panel.hpp"

#include <imgui.h>

#include <cstring>

namespace meter::preview {
namespace {

const ImVec4 kErrorColor{1.0f, 0.4f, 0.35f, 1.0f};

void draw_status(const PanelStatus& s) {
  ImGui::TextWrapped("%s", s.files.c_str());
  if (s.generation > 0) {
    ImGui::Text("scene %llu: converted in %.0f ms", static_cast<unsigned long long>(s.generation), s.convert_ms);
  } else {
    ImGui::TextUnformatted("no scene yet: waiting for a save that converts");
  }
  if (s.reload_ms > 0) ImGui::Text("on screen %.0f ms after the save", s.reload_ms);
  if (!s.error.empty()) {
    ImGui::PushStyleColor(ImGuiCol_Text, kErrorColor);
    if (s.generation > 0) {
      ImGui::TextWrapped("The last save does not convert; still showing scene %llu:",
                         static_cast<unsigned long long>(s.generation));
    } else {
      ImGui::TextWrapped("The scene does not convert:");
    }
    ImGui::TextWrapped("%s", s.error.c_str());
    ImGui::PopStyleColor();
  }
  ImGui::Text("frame %.1f ms (engine %.1f ms)", s.frame_ms, s.render_ms);
  ImGui::Separator();
}

bool draw_source(const PanelStatus& s, PanelInput& input) {
  switch (s.source) {
    case PanelStatus::Source::Controls:
      return ImGui::Checkbox("link lost (failsafe look)", &input.link_lost);
    case PanelStatus::Source::Playback:
      ImGui::Text("playing values: %.2f / %.2f s", s.play_t, s.play_duration);
      ImGui::SameLine();
      if (ImGui::Button("restart")) input.restart_playback = true;
      return false;
    case PanelStatus::Source::Link:
      ImGui::Text("link %s: %s", s.link.c_str(), s.link_up ? "up" : "DOWN (failsafe look)");
      return false;
  }
  return false;
}

// One signal's control; true when the artist changed it.
bool draw_control(const SignalControl& c, protocol::SignalTable& values) {
  const auto& state = values.get(c.id);
  double v = state.value;
  bool changed = false;
  ImGui::PushID(c.id);
  switch (c.kind) {
    case ControlKind::Slider: {
      const std::string label = c.name + (c.unit.empty() ? "" : " (" + c.unit + ")");
      ImGui::TextUnformatted(label.c_str());
      changed = ImGui::SliderScalar("##v", ImGuiDataType_Double, &v, &c.min, &c.max, "%.2f");
      break;
    }
    case ControlKind::Toggle: {
      bool on = v >= 0.5;
      changed = ImGui::Checkbox(c.name.c_str(), &on);
      v = on ? 1.0 : 0.0;
      break;
    }
    case ControlKind::Choice: {
      ImGui::TextUnformatted(c.name.c_str());
      std::string current = std::to_string(static_cast<long long>(v));
      for (const auto& item : c.choices)
        if (static_cast<double>(item.value) == v) current = item.label;
      if (ImGui::BeginCombo("##v", current.c_str())) {
        for (const auto& item : c.choices) {
          if (ImGui::Selectable(item.label.c_str(), static_cast<double>(item.value) == v)) {
            v = static_cast<double>(item.value);
            changed = true;
          }
        }
        ImGui::EndCombo();
      }
      break;
    }
    case ControlKind::Text: {
      ImGui::TextUnformatted(c.name.c_str());
      char buffer[128] = {};
      std::strncpy(buffer, state.text.c_str(), sizeof buffer - 1);
      if (ImGui::InputText("##v", buffer, sizeof buffer)) {
        values.set_text(c.id, buffer, protocol::SignalStatus::Valid);
        ImGui::PopID();
        return true;
      }
      break;
    }
  }
  if (changed) values.set(c.id, v, protocol::SignalStatus::Valid);
  ImGui::SameLine();
  ImGui::TextDisabled("%s", std::string(protocol::to_string(values.get(c.id).status)).c_str());
  ImGui::PopID();
  return changed;
}

}  // namespace

bool draw_controls_panel(int x, int width, int height, const PanelStatus& status,
                         const std::vector<SignalControl>& controls, protocol::SignalTable& values, PanelInput& input) {
  ImGui::SetNextWindowPos(ImVec2(static_cast<float>(x), 0.0f));
  ImGui::SetNextWindowSize(ImVec2(static_cast<float>(width), static_cast<float>(height)));
  ImGui::Begin("meter-preview", nullptr,
               ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
  draw_status(status);
  bool changed = draw_source(status, input);
  const bool editable = status.source == PanelStatus::Source::Controls;
  if (!editable) ImGui::BeginDisabled();
  for (const auto& c : controls) changed = draw_control(c, values) || changed;
  if (!editable) ImGui::EndDisabled();
  ImGui::End();
  return changed;
}

}  // namespace meter::preview
