#include "meter/runner/script_log.hpp"

#include "meter/engine/logic/scripts.hpp"
#include "meter/protocol/log/logger.hpp"

namespace meter::runner {

void log_script_messages(engine::BindingEvaluator& evaluator, std::ostream& log) {
  if (auto* scripts = evaluator.scripts())
    for (const auto& m : scripts->take_messages()) protocol::LogLine(log, protocol::LogLevel::Warning, "script") << "meter-view: script " << m;
}

void log_script_stats(const engine::BindingEvaluator& evaluator, std::ostream& log) {
  if (const auto* scripts = evaluator.scripts())
    for (const auto& st : scripts->stats()) log << "meter-view: script " << engine::describe(st) << "\n";
}

}  // namespace meter::runner
