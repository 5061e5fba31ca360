#include "jointhb/io/input_error.hpp"

#include <algorithm>
#include <utility>

namespace jointhb::io {
namespace {

// The length of the UTF-8 sequence at text[i] that encodes a printable code point, or 0 when the
// bytes there are not valid UTF-8 or encode a control or line separator (C1, U+2028, U+2029).
std::size_t printable_utf8_length(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  std::size_t length = 0;
  char32_t code = 0;
  if (lead >= 0xC2 && lead <= 0xDF) length = 2, code = lead & 0x1Fu;
  else if (lead >= 0xE0 && lead <= 0xEF) length = 3, code = lead & 0x0Fu;
  else if (lead >= 0xF0 && lead <= 0xF4) length = 4, code = lead & 0x07u;
  else return 0;
  if (i + length > text.size()) return 0;
  for (std::size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0u) != 0x80u) return 0;
    code = (code << 6) | (byte(i + k) & 0x3Fu);
  }
  const char32_t smallest[] = {0, 0, 0x80, 0x800, 0x10000};
  if (code < smallest[length] || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  if (code <= 0x9F || code == 0x2028 || code == 0x2029) return 0;
  return length;
}

}  // namespace

std::string printable_one_line(std::string_view text) {
  static constexpr char hex[] = "0123456789ABCDEF";
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c == '\n' || c == '\r' || c == '\t') {
      out += ' ';
      ++i;
    } else if (c >= 0x20 && c < 0x7F) {
      out += static_cast<char>(c);
      ++i;
    } else if (const std::size_t n = c >= 0x80 ? printable_utf8_length(text, i) : 0; n > 0) {
      out.append(text.substr(i, n));
      i += n;
    } else {
      out += "\\x";
      out += hex[c >> 4];
      out += hex[c & 0xF];
      ++i;
    }
  }
  return out;
}

namespace {

std::string format_message(const std::string& file, int line, int column, const std::string& key,
                           const std::string& constraint) {
  std::string message = file;
  if (line > 0) {
    message += ':' + std::to_string(line) + ':' + std::to_string(std::max(column, 1));
  }
  message += ": ";
  if (!key.empty()) message += "key '" + key + "': ";
  message += constraint;
  // The message must stay on one printable line (editors and the CLI tests rely on it), whatever
  // the file name or an echoed value contains.
  return printable_one_line(message);
}

}  // namespace

InputError::InputError(std::string file, int line, int column, std::string key,
                       std::string constraint)
    : std::runtime_error(format_message(file, line, column, key, constraint)),
      file_(std::move(file)),
      line_(line),
      column_(line > 0 ? std::max(column, 1) : 0),
      key_(std::move(key)),
      constraint_(std::move(constraint)) {}

}  // namespace jointhb::io
