// The `meter-convert --report` program listing: per program the features, the pipeline state, the
// attribute / uniform / sampler counts and what the shader optimizer did.
#include <sstream>

#include "meter/convert/converter.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::convert {

std::string program_report(const Scene& s) {
  std::ostringstream os;
  std::size_t total_instr = 0;
  os << "scene " << s.source_name << ": " << s.programs.size() << " program(s), " << s.draws.size() << " draw(s)\n";
  for (std::size_t i = 0; i < s.programs.size(); ++i) {
    const auto& e = s.programs[i];
    const auto& p = e.program;
    std::size_t draws = 0;
    for (const auto& d : s.draws) draws += d.program == static_cast<int>(i);
    os << "program " << i << ": " << shadergen::program_key(p.features) << "\n";
    os << "  shading " << shadergen::to_string(p.features.shading) << ", alpha " << shadergen::to_string(p.features.alpha)
       << ", blend " << (p.blend ? "on" : "off") << ", cull " << (p.cull_back_faces ? "back" : "none") << ", draws " << draws << "\n";
    os << "  attributes " << p.attributes.size() << ", uniforms " << p.uniforms.size() << ", samplers " << p.samplers.size()
       << ", source " << p.vertex_source.size() + p.fragment_source.size() << " bytes\n";
    if (p.optimized) {
      const auto& r = e.optimize_report;
      total_instr += r.spirv_instructions_after;
      os << "  optimized: SPIR-V instructions " << r.spirv_instructions_before << " -> " << r.spirv_instructions_after
         << ", uniforms " << r.uniforms_before << " -> " << r.uniforms_after << ", varyings " << r.varyings_before << " -> "
         << r.varyings_after << ", folded " << r.folded.size() << "\n";
    } else {
      total_instr += e.optimize_report.spirv_instructions_after;
      os << "  not optimized: SPIR-V instructions " << e.optimize_report.spirv_instructions_after << "\n";
    }
  }
  if (total_instr) os << "total SPIR-V instructions (vertex + fragment, all programs): " << total_instr << "\n";
  return os.str();
}

}  // namespace meter::convert
