// Text the link can always encode.
#pragma once

#include <string>
#include <string_view>

namespace meter::protocol::detail {

// Cuts text to kMaxTextBytes at a character boundary and replaces invalid UTF-8 bytes with '?',
// so whatever the caller passes can always be encoded.
std::string sanitize_text(std::string_view text);

}  // namespace meter::protocol::detail
