#include "scene/json_locator.h"

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace robophi::scene {

namespace {

// The length (1 to 4) of the well-formed UTF-8 sequence at text[i] (RFC 3629:
// no overlong forms, no surrogates, nothing above U+10FFFF), or 0.
std::size_t utf8SequenceLength(std::string_view text, std::size_t i) {
  const auto at = [&](std::size_t k) {
    return i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0u;
  };
  const unsigned lead = at(0);
  const auto continuation = [&](std::size_t k, unsigned low = 0x80, unsigned high = 0xBF) {
    return at(k) >= low && at(k) <= high;
  };
  if (lead < 0x80) return 1;
  if (lead >= 0xC2 && lead <= 0xDF) return continuation(1) ? 2 : 0;
  if (lead == 0xE0) return continuation(1, 0xA0) && continuation(2) ? 3 : 0;
  if (lead == 0xED) return continuation(1, 0x80, 0x9F) && continuation(2) ? 3 : 0;
  if (lead >= 0xE1 && lead <= 0xEF) return continuation(1) && continuation(2) ? 3 : 0;
  if (lead == 0xF0) return continuation(1, 0x90) && continuation(2) && continuation(3) ? 4 : 0;
  if (lead >= 0xF1 && lead <= 0xF3)
    return continuation(1) && continuation(2) && continuation(3) ? 4 : 0;
  if (lead == 0xF4)
    return continuation(1, 0x80, 0x8F) && continuation(2) && continuation(3) ? 4 : 0;
  return 0;
}

// Thrown on the first syntax error; caught by readLocatedJson.
struct SyntaxError {
  SourcePosition where;
  std::string message;
};

// A recursive-descent reader over the text, tracking line and column.
class Reader {
 public:
  Reader(std::string_view text, LocatedJson& out, std::vector<JsonProblem>& problems)
      : text_(text), out_(&out), problems_(problems) {}

  void readDocument() {
    skipBlanks();
    if (atEnd()) fail("the file is empty: expected a JSON object");
    out_->value = readValue("", 0);
    skipBlanks();
    if (!atEnd()) fail(fmt::format("unexpected {} after the end of the document", describeHere()));
  }

 private:
  static constexpr int kMaxDepth = 200;

  bool atEnd() const { return offset_ >= text_.size(); }
  char peek() const { return atEnd() ? '\0' : text_[offset_]; }
  SourcePosition here() const { return {line_, column_}; }

  void advance() {
    const char c = text_[offset_++];
    if (c == '\n') {
      ++line_;
      column_ = 1;
    } else if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) {
      // Count characters: UTF-8 continuation bytes do not start a new column.
      ++column_;
    }
  }

  [[noreturn]] void fail(std::string message) const {
    throw SyntaxError{here(), std::move(message)};
  }
  [[noreturn]] void failAt(SourcePosition where, std::string message) const {
    throw SyntaxError{where, std::move(message)};
  }

  std::string describeHere() const {
    if (atEnd()) return "end of file";
    return describeCharacter();
  }

  // The character at the offset for a message: a control character or a
  // non-ASCII one by its code (the text is UTF-8: checked before parsing), as
  // printing one byte of a multi-byte character would put invalid UTF-8 in it.
  std::string describeCharacter() const {
    const auto c = static_cast<unsigned char>(peek());
    if (c < 0x20 || c == 0x7F) return fmt::format("control character 0x{:02x}", c);
    if (c < 0x80) return fmt::format("'{}'", static_cast<char>(c));
    const std::size_t length = utf8SequenceLength(text_, offset_);
    std::uint32_t code = c & (length == 2 ? 0x1Fu : length == 3 ? 0x0Fu : 0x07u);
    for (std::size_t k = 1; k < length; ++k)
      code = (code << 6) | (static_cast<unsigned char>(text_[offset_ + k]) & 0x3Fu);
    return fmt::format("'{}' (U+{:04X})", text_.substr(offset_, length), code);
  }

  // Skips white space, `// line` and `/* block */` comments.
  void skipBlanks() {
    while (!atEnd()) {
      const char c = peek();
      if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
        advance();
      } else if (c == '/' && offset_ + 1 < text_.size() && text_[offset_ + 1] == '/') {
        while (!atEnd() && peek() != '\n') advance();
      } else if (c == '/' && offset_ + 1 < text_.size() && text_[offset_ + 1] == '*') {
        const SourcePosition start = here();
        advance();
        advance();
        while (!(peek() == '*' && offset_ + 1 < text_.size() && text_[offset_ + 1] == '/')) {
          if (atEnd()) failAt(start, "unterminated /* comment");
          advance();
        }
        advance();
        advance();
      } else {
        return;
      }
    }
  }

  nlohmann::json readValue(const std::string& pointer, int depth) {
    if (depth > kMaxDepth) fail("the document is nested too deeply");
    out_->valuePositions[pointer] = here();
    const char c = peek();
    if (c == '{') return readObject(pointer, depth);
    if (c == '[') return readArray(pointer, depth);
    if (c == '"') return readString();
    if (c == '-' || (c >= '0' && c <= '9')) return readNumber();
    if (std::isalpha(static_cast<unsigned char>(c))) return readWord();
    if (atEnd()) fail("unexpected end of file: expected a value");
    fail(
        fmt::format("unexpected {}: expected a value (object, array, string, number, true, "
                    "false or null)",
                    describeHere()));
  }

  nlohmann::json readObject(const std::string& pointer, int depth) {
    nlohmann::json object = nlohmann::json::object();
    const SourcePosition open = here();
    advance();  // {
    skipBlanks();
    if (peek() == '}') {
      advance();
      return object;
    }
    while (true) {
      skipBlanks();
      if (atEnd()) failAt(open, "unterminated object: '{' is never closed");
      if (peek() != '"') {
        if (peek() == '}') fail("trailing comma before '}'");
        fail(fmt::format("expected a key in double quotes, got {}", describeHere()));
      }
      const SourcePosition keyAt = here();
      const std::string key = readString();
      const std::string member = pointer + "/" + pointerToken(key);
      skipBlanks();
      if (peek() != ':')
        fail(fmt::format("expected ':' after key \"{}\", got {}", key, describeHere()));
      advance();
      skipBlanks();
      if (object.contains(key)) {
        const SourcePosition first = out_->keyPositions[member];
        problems_.push_back({keyAt, member,
                             fmt::format("duplicate key '{}' (first at line {}, column {})", key,
                                         first.line, first.column)});
        // Read the duplicate into a scratch document so the first keeps its positions.
        LocatedJson scratch;
        LocatedJson* const document = out_;
        out_ = &scratch;
        readValue(member, depth + 1);
        out_ = document;
      } else {
        out_->keyPositions[member] = keyAt;
        object[key] = readValue(member, depth + 1);
      }
      skipBlanks();
      if (peek() == ',') {
        advance();
        continue;
      }
      if (peek() == '}') {
        advance();
        return object;
      }
      if (atEnd()) failAt(open, "unterminated object: '{' is never closed");
      fail(fmt::format("expected ',' or '}}' after the value of \"{}\", got {}", key,
                       describeHere()));
    }
  }

  nlohmann::json readArray(const std::string& pointer, int depth) {
    nlohmann::json array = nlohmann::json::array();
    const SourcePosition open = here();
    advance();  // [
    skipBlanks();
    if (peek() == ']') {
      advance();
      return array;
    }
    while (true) {
      skipBlanks();
      if (atEnd()) failAt(open, "unterminated array: '[' is never closed");
      if (peek() == ']') fail("trailing comma before ']'");
      array.push_back(readValue(pointer + "/" + std::to_string(array.size()), depth + 1));
      skipBlanks();
      if (peek() == ',') {
        advance();
        continue;
      }
      if (peek() == ']') {
        advance();
        return array;
      }
      if (atEnd()) failAt(open, "unterminated array: '[' is never closed");
      fail(fmt::format("expected ',' or ']' in the array, got {}", describeHere()));
    }
  }

  static void appendUtf8(std::string& out, std::uint32_t codePoint) {
    if (codePoint < 0x80) {
      out += static_cast<char>(codePoint);
    } else if (codePoint < 0x800) {
      out += static_cast<char>(0xC0 | (codePoint >> 6));
      out += static_cast<char>(0x80 | (codePoint & 0x3F));
    } else if (codePoint < 0x10000) {
      out += static_cast<char>(0xE0 | (codePoint >> 12));
      out += static_cast<char>(0x80 | ((codePoint >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (codePoint & 0x3F));
    } else {
      out += static_cast<char>(0xF0 | (codePoint >> 18));
      out += static_cast<char>(0x80 | ((codePoint >> 12) & 0x3F));
      out += static_cast<char>(0x80 | ((codePoint >> 6) & 0x3F));
      out += static_cast<char>(0x80 | (codePoint & 0x3F));
    }
  }

  std::uint32_t readHex4() {
    std::uint32_t value = 0;
    for (int i = 0; i < 4; ++i) {
      const char c = peek();
      std::uint32_t digit = 0;
      if (c >= '0' && c <= '9') {
        digit = static_cast<std::uint32_t>(c - '0');
      } else if (c >= 'a' && c <= 'f') {
        digit = static_cast<std::uint32_t>(c - 'a' + 10);
      } else if (c >= 'A' && c <= 'F') {
        digit = static_cast<std::uint32_t>(c - 'A' + 10);
      } else {
        fail("expected 4 hexadecimal digits after \\u");
      }
      value = value * 16 + digit;
      advance();
    }
    return value;
  }

  std::string readString() {
    const SourcePosition open = here();
    advance();  // "
    std::string result;
    while (true) {
      if (atEnd()) failAt(open, "unterminated string");
      const char c = peek();
      if (c == '"') {
        advance();
        return result;
      }
      if (c == '\n') failAt(open, "unterminated string (a string cannot span lines)");
      if (static_cast<unsigned char>(c) < 0x20)
        fail("control character in a string: use an escape");
      if (c != '\\') {
        result += c;
        advance();
        continue;
      }
      advance();
      const char e = peek();
      switch (e) {
        case '"':
          result += '"';
          break;
        case '\\':
          result += '\\';
          break;
        case '/':
          result += '/';
          break;
        case 'b':
          result += '\b';
          break;
        case 'f':
          result += '\f';
          break;
        case 'n':
          result += '\n';
          break;
        case 'r':
          result += '\r';
          break;
        case 't':
          result += '\t';
          break;
        case 'u': {
          advance();
          std::uint32_t codePoint = readHex4();
          if (codePoint >= 0xD800 && codePoint < 0xDC00) {
            // A high surrogate must be followed by its low half: alone it is not a character.
            if (peek() != '\\') fail("a \\u high surrogate must be followed by a low one");
            advance();
            if (peek() != 'u') fail("expected a low surrogate \\u escape");
            advance();
            const std::uint32_t low = readHex4();
            if (low < 0xDC00 || low >= 0xE000) fail("invalid low surrogate in \\u escape");
            codePoint = 0x10000 + ((codePoint - 0xD800) << 10) + (low - 0xDC00);
          } else if (codePoint >= 0xDC00 && codePoint < 0xE000) {
            fail("a \\u low surrogate without its high half is not a character");
          }
          appendUtf8(result, codePoint);
          continue;
        }
        default:
          fail(fmt::format("invalid escape: \\ followed by {} in a string", describeHere()));
      }
      advance();
    }
  }

  nlohmann::json readNumber() {
    const SourcePosition start = here();
    const std::size_t begin = offset_;
    bool integral = true;
    if (peek() == '-') advance();
    if (peek() == '0') {
      advance();
      if (std::isdigit(static_cast<unsigned char>(peek())))
        failAt(start, "a number cannot have leading zeros");
    } else if (std::isdigit(static_cast<unsigned char>(peek()))) {
      while (std::isdigit(static_cast<unsigned char>(peek()))) advance();
    } else {
      if (std::isalpha(static_cast<unsigned char>(peek())))
        failAt(start,
               "-" + readIdentifier() + " is not a JSON number: scene values must be finite");
      fail("expected a digit after '-'");
    }
    if (peek() == '.') {
      integral = false;
      advance();
      if (!std::isdigit(static_cast<unsigned char>(peek()))) fail("expected a digit after '.'");
      while (std::isdigit(static_cast<unsigned char>(peek()))) advance();
    }
    if (peek() == 'e' || peek() == 'E') {
      integral = false;
      advance();
      if (peek() == '+' || peek() == '-') advance();
      if (!std::isdigit(static_cast<unsigned char>(peek())))
        fail("expected a digit in the exponent");
      while (std::isdigit(static_cast<unsigned char>(peek()))) advance();
    }
    const std::string_view token = text_.substr(begin, offset_ - begin);
    if (integral) {
      std::int64_t value = 0;
      const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
      if (ec == std::errc() && end == token.data() + token.size()) return value;
    }
    double value = 0.0;
    const auto [end, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
    if (ec == std::errc::result_out_of_range) {
      // Underflow to zero is harmless; overflow would be an infinity.
      if (std::fabs(std::strtod(std::string(token).c_str(), nullptr)) > 1.0)
        failAt(start, fmt::format("number {} is too large for a double (max ~1.8e308)", token));
      return 0.0;
    }
    if (ec != std::errc() || end != token.data() + token.size())
      failAt(start, fmt::format("invalid number {}", token));
    return value;
  }

  std::string readIdentifier() {
    std::string word;
    while (std::isalnum(static_cast<unsigned char>(peek())) || peek() == '_') {
      word += peek();
      advance();
    }
    return word;
  }

  nlohmann::json readWord() {
    const SourcePosition start = here();
    const std::string word = readIdentifier();
    if (word == "true") return true;
    if (word == "false") return false;
    if (word == "null") return nullptr;
    if (word == "NaN" || word == "nan" || word == "Infinity" || word == "inf" || word == "infinity")
      failAt(start, fmt::format("{} is not a JSON number: scene values must be finite", word));
    failAt(start, fmt::format("unexpected word '{}': expected a value (strings need double quotes)",
                              word));
  }

  std::string_view text_;
  LocatedJson* out_;
  std::vector<JsonProblem>& problems_;
  std::size_t offset_ = 0;
  int line_ = 1;
  int column_ = 1;
};

}  // namespace

SourcePosition LocatedJson::positionOf(const std::string& pointer) const {
  std::string p = pointer;
  while (true) {
    if (const auto it = valuePositions.find(p); it != valuePositions.end()) return it->second;
    const auto slash = p.rfind('/');
    if (slash == std::string::npos) return {};
    p.resize(slash);
  }
}

SourcePosition LocatedJson::keyPositionOf(const std::string& pointer) const {
  if (const auto it = keyPositions.find(pointer); it != keyPositions.end()) return it->second;
  return positionOf(pointer);
}

std::optional<JsonProblem> findInvalidUtf8(std::string_view text) {
  int line = 1, column = 1;
  std::size_t i = 0;
  while (i < text.size()) {
    const auto byte = static_cast<unsigned char>(text[i]);
    const std::size_t length = utf8SequenceLength(text, i);
    if (length == 0) {
      std::string shown;
      for (std::size_t k = i; k < text.size() && k < i + 4; ++k)
        shown += fmt::format("{}0x{:02X}", k == i ? "" : " ", static_cast<unsigned char>(text[k]));
      return JsonProblem{
          {line, column},
          "",
          fmt::format("invalid UTF-8 (bytes {}{}): a scene file must be UTF-8 text; {}", shown,
                      i + 4 < text.size() ? " ..." : "",
                      byte >= 0xA0 ? "this looks like Latin-1 or another 8-bit encoding, save "
                                     "the file as UTF-8"
                                   : "save the file as UTF-8")};
    }
    if (byte == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
    i += length;
  }
  return std::nullopt;
}

JsonReadResult readLocatedJson(std::string_view text) {
  JsonReadResult result;
  LocatedJson located;
  // A UTF-8 byte order mark is not part of the document.
  if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  // All text is checked first: names and comments reach messages, model.json and replay.html.
  if (auto problem = findInvalidUtf8(text)) {
    result.errors.push_back(std::move(*problem));
    return result;
  }
  try {
    Reader reader(text, located, result.errors);
    reader.readDocument();
  } catch (const SyntaxError& e) {
    result.errors.push_back({e.where, "", "JSON syntax error: " + e.message});
    return result;
  }
  result.json = std::move(located);
  return result;
}

std::string pointerToken(std::string_view key) {
  std::string token;
  for (const char c : key) {
    if (c == '~') {
      token += "~0";
    } else if (c == '/') {
      token += "~1";
    } else {
      token += c;
    }
  }
  return token;
}

}  // namespace robophi::scene
