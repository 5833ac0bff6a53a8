#include "recording/recording_text.hpp"

#include <algorithm>
#include <cstdio>

namespace meter::protocol::detail {

namespace {

int hex_digit(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

}  // namespace

void append_quoted(std::string& out, std::string_view text) {
  out += '"';
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (byte < 0x20 || byte == 0x7f) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\x%02x", byte);
      out += buffer;
    } else {
      out += c;
    }
  }
  out += '"';
}

std::optional<std::string> unquote(std::string_view token, std::string& why) {
  if (token.size() < 2 || token.front() != '"' || token.back() != '"') {
    why = "expected a quoted text \"...\", got '" + std::string(token) + "'";
    return std::nullopt;
  }
  std::string out;
  for (std::size_t i = 1; i + 1 < token.size(); ++i) {
    const char c = token[i];
    if (c == '"') {
      why = "unescaped '\"' inside a quoted text (write \\\")";
      return std::nullopt;
    }
    if (c != '\\') {
      out += c;
      continue;
    }
    if (i + 2 >= token.size()) {
      why = "a quoted text ends in a lone backslash";
      return std::nullopt;
    }
    const char e = token[++i];
    if (e == '"' || e == '\\') {
      out += e;
    } else if (e == 'x' && i + 3 < token.size() && hex_digit(token[i + 1]) >= 0 && hex_digit(token[i + 2]) >= 0) {
      out += static_cast<char>(hex_digit(token[i + 1]) * 16 + hex_digit(token[i + 2]));
      i += 2;
    } else {
      why = std::string("unknown escape '\\") + e + "' in a quoted text (known: \\\\, \\\", \\xHH)";
      return std::nullopt;
    }
  }
  return out;
}

std::string close_reason_token(CloseReason reason) {
  std::string text(to_string(reason));
  for (char& c : text)
    if (c == ' ') c = '-';
  return text;
}

std::optional<CloseReason> close_reason_from_token(std::string_view token) {
  for (int r = 0; r <= static_cast<int>(CloseReason::Authentication); ++r) {
    const auto reason = static_cast<CloseReason>(r);
    if (close_reason_token(reason) == token) return reason;
  }
  return std::nullopt;
}

std::optional<std::vector<std::string_view>> split_tokens(std::string_view line) {
  std::vector<std::string_view> tokens;
  std::size_t i = 0;
  while (i < line.size()) {
    if (line[i] == ' ') {
      ++i;
      continue;
    }
    const std::size_t start = i;
    bool quoted = false;
    for (; i < line.size(); ++i) {
      const char c = line[i];
      if (quoted && c == '\\') {
        ++i;
      } else if (c == '"') {
        quoted = !quoted;
      } else if (c == ' ' && !quoted) {
        break;
      }
    }
    if (quoted) return std::nullopt;
    tokens.push_back(line.substr(start, std::min(i, line.size()) - start));
  }
  return tokens;
}

}  // namespace meter::protocol::detail
